"""``stampc compile``: lower a domain/problem to the JSON IR or to PPDDL.

Never imports user-bound Python code: bindings are carried as strings.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from stampc.commands.common import (add_import_options, add_input_arguments, fail_with,
                                    print_warnings, reports_errors)
from stampc.diagnostics import StampcError

HELP = "compile .stamp (or import .pddl) to the versioned JSON IR or to PPDDL"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_input_arguments(parser)
    parser.add_argument("--target", choices=("ir", "ppddl"), default="ir")
    parser.add_argument("--level", choices=("lifted", "grounded", "both"), default="both",
                        help="for --target ir: which IR level(s) to write (default both)")
    parser.add_argument("-o", "--output", metavar="DIR",
                        help="write files here (default: print to standard output)")
    add_import_options(parser)


@reports_errors("compile")
def run(args: argparse.Namespace) -> int:
    from stampc import api
    from stampc.ir.json_io import grounded_to_json, lifted_to_json

    started = time.perf_counter()
    try:
        model = api.load_model(args.files, lenient=args.lenient)
        print_warnings(model.diagnostics)
        outputs: dict[str, str] = {}
        if args.target == "ppddl":
            domain_text, problem_text = api.to_ppddl(model)
            outputs["domain.pddl"] = domain_text
            outputs["problem.pddl"] = problem_text
        else:
            if args.level in ("lifted", "both"):
                outputs["lifted.json"] = json.dumps(lifted_to_json(model), indent=1)
            if args.level in ("grounded", "both"):
                gm = api.ground(model, conflicting_effects=args.conflicting_effects)
                print_warnings(gm.diagnostics)
                outputs["grounded.json"] = json.dumps(grounded_to_json(gm), indent=1)
                print(f"grounded: {len(gm.facts)} facts, {len(gm.actions)} actions",
                      file=sys.stderr)
    except StampcError as exc:
        return fail_with(exc)
    except FileNotFoundError as exc:
        print(f"stampc compile: {exc}", file=sys.stderr)
        return 2
    if args.output:
        out = Path(args.output)
        try:
            out.mkdir(parents=True, exist_ok=True)
            for name, text in outputs.items():
                (out / name).write_text(text + ("" if text.endswith("\n") else "\n"))
        except OSError as exc:
            print(f"stampc compile: cannot write to {out}: {exc.strerror}", file=sys.stderr)
            return 2
        print(f"wrote {', '.join(outputs)} to {out} in {time.perf_counter() - started:.3f}s",
              file=sys.stderr)
    else:
        for name, text in outputs.items():
            if len(outputs) > 1:
                print(f";; ---- {name}" if name.endswith(".pddl") else f"// ---- {name}")
            print(text)
    return 0
