"""Every front-end diagnostic code in one table (docs/language.md lists the same codes).

Codes are stable: tools match on them. ``E0xx`` syntax and structure, ``E1xx`` names,
``E2xx`` arity/types/duplicates, ``E3xx`` stochastic and TAMP rules, ``E5xx`` lowering,
``E6xx`` bound Python code read statically, ``W4xx`` warnings (lints), ``N6xx`` notes.
"""

from __future__ import annotations

from stampc.diagnostics import Diagnostic, Label, Severity, Span

CODES: dict[str, tuple[Severity, str]] = {
    "E001": (Severity.ERROR, "syntax error"),
    "E002": (Severity.ERROR, "declaration not allowed here"),
    "E003": (Severity.ERROR, "used module or file not found"),
    "E004": (Severity.ERROR, "invalid number (an integer is required)"),
    "E005": (Severity.ERROR, "invalid object range"),
    "E006": (Severity.ERROR, "nesting too deep"),
    "E007": (Severity.ERROR, "index variable not bound"),
    "E008": (Severity.ERROR, "invalid index or index range"),
    "E101": (Severity.ERROR, "undefined type"),
    "E102": (Severity.ERROR, "undefined predicate or function"),
    "E103": (Severity.ERROR, "undefined constant or object"),
    "E104": (Severity.ERROR, "undefined generator"),
    "E105": (Severity.ERROR, "undefined variable"),
    "E106": (Severity.ERROR, "unbound variable (used outside its quantifier)"),
    "E107": (Severity.ERROR, "undefined domain"),
    "E110": (Severity.ERROR, "comprehension names an undeclared object"),
    "E201": (Severity.ERROR, "arity mismatch"),
    "E202": (Severity.ERROR, "argument type mismatch"),
    "E203": (Severity.ERROR, "duplicate definition"),
    "E204": (Severity.ERROR, "duplicate parameter"),
    "E205": (Severity.ERROR, "cyclic type hierarchy"),
    "E301": (Severity.ERROR, "probability outside [0, 1]"),
    "E302": (Severity.ERROR, "outcome probabilities sum above 1"),
    "E303": (Severity.ERROR, "`?` on a static predicate"),
    "E304": (Severity.ERROR, "effect on a static predicate"),
    "E305": (Severity.ERROR, "continuous parameter that no generator produces"),
    "E306": (Severity.ERROR, "malformed or missing binding"),
    "E307": (Severity.ERROR, "goal uses an undeclared object"),
    "E308": (Severity.ERROR, "unreachable goal fact"),
    "E309": (Severity.ERROR, "generator output of a non-continuous type"),
    "E311": (Severity.ERROR, "effect on a derived predicate"),
    "E312": (Severity.ERROR, "derived predicate recursion through negation (not stratified)"),
    "E313": (Severity.ERROR, "symmetric predicate without two parameters of one type"),
    "E501": (Severity.ERROR, "cannot lower to the lifted IR"),
    "E601": (Severity.ERROR, "bound module not found or unreadable"),
    "E602": (Severity.ERROR, "bound module has no such function"),
    "E603": (Severity.ERROR, "bound function cannot take the arguments the engine passes"),
    "E604": (Severity.ERROR, "executor reads an action parameter the action does not declare"),
    "E605": (Severity.ERROR, "generator samples of the wrong size"),
    "N601": (Severity.NOTE, "binding not checked: its module cannot be read without importing"),
    "W401": (Severity.WARNING, "unused predicate"),
    "W402": (Severity.WARNING, "unused type"),
    "W403": (Severity.WARNING, "unused generator"),
    "W404": (Severity.WARNING, "`?` fact never read by a precondition"),
    "W405": (Severity.WARNING, "`?` predicate read both positively and negatively"),
    "W406": (Severity.WARNING, "evaluator for a predicate no effect marks with `?`"),
    "W407": (Severity.WARNING, "bound function's parameters in another order than declared"),
    "W408": (Severity.WARNING, "`? predicate` without an evaluator"),
}


def diag(code: str, message: str, span: Span, hint: str | None = None,
         labels: tuple[Label, ...] = ()) -> Diagnostic:
    """A diagnostic with the severity registered for ``code``."""
    severity, _title = CODES[code]
    return Diagnostic(code, severity, message, span, hint, tuple(labels))
