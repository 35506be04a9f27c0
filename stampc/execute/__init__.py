"""Execution you can trust: ``stampc execute``'s checks and report.

- :mod:`.provenance` — content hashes tying a policy to its inputs;
- :mod:`.policyfile` — reading policy.json with located diagnostics;
- :mod:`.truth` — the world's truth model, which samples each action's outcome;
- :mod:`.goals` — concrete goal checks per world (scenes and examples can bind their own);
- :mod:`.recheck` — the independent re-check of every executed trajectory;
- :mod:`.runner` — the execution loop; :mod:`.report` — figures, text and JSON.
"""
