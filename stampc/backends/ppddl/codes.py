"""Diagnostic codes of the PPDDL importer (documented in docs/ppddl.md)."""

from __future__ import annotations

SYNTAX = "P100"            # syntax error (unexpected token / character / end of file)
UNSUPPORTED = "P101"       # construct outside the supported PPDDL dialect
REQUIREMENT = "P102"       # unknown or unsupported requirement flag
DUPLICATE = "P103"         # name declared twice
IO = "P104"                # file cannot be read
MISSING = "P105"           # no domain / no problem / problem name not found / ambiguous
DOMAIN_MISMATCH = "P106"   # problem's (:domain X) does not name the domain
NO_GOAL = "P107"           # problem without (:goal ...)
UNDEFINED_TYPE = "P110"
UNDEFINED_PREDICATE = "P111"
UNDEFINED_OBJECT = "P112"
UNDEFINED_VARIABLE = "P113"
ARITY = "P114"             # wrong number of arguments
TYPE_MISMATCH = "P115"     # argument's type incompatible with the parameter's
TYPE_CYCLE = "P116"        # cyclic type hierarchy
UNDEFINED_FUNCTION = "P117"
PROBABILITY_RANGE = "P120"  # probability outside [0, 1]
PROBABILITY_SUM = "P121"    # outcome probabilities sum above 1
BAD_NUMBER = "P122"         # e.g. 1/0
NUMERIC = "P123"            # numeric effect / metric other than reward or total-cost

#: code -> one-line description, used by the docs table test.
DESCRIPTIONS = {
    SYNTAX: "syntax error; the message lists the expected tokens in words",
    UNSUPPORTED: "construct outside the supported dialect (either types, :derived, ...)",
    REQUIREMENT: "unknown or unsupported requirement flag",
    DUPLICATE: "name declared twice (type, constant, object, predicate, action, parameter)",
    IO: "file cannot be read",
    MISSING: "no domain, no problem, problem name not found, or several problems and no name",
    DOMAIN_MISMATCH: "the problem's (:domain X) does not name the domain it is read with",
    NO_GOAL: "problem without (:goal ...)",
    UNDEFINED_TYPE: "undefined type",
    UNDEFINED_PREDICATE: "undefined predicate",
    UNDEFINED_OBJECT: "undefined object or constant",
    UNDEFINED_VARIABLE: "variable not bound by the action parameters or a quantifier",
    ARITY: "wrong number of arguments",
    TYPE_MISMATCH: "argument type incompatible with the parameter type",
    TYPE_CYCLE: "cyclic type hierarchy",
    UNDEFINED_FUNCTION: "undefined numeric function",
    PROBABILITY_RANGE: "probability outside [0, 1]",
    PROBABILITY_SUM: "outcome probabilities of one probabilistic effect sum above 1",
    BAD_NUMBER: "malformed number (e.g. a zero denominator)",
    NUMERIC: "numeric effect or metric other than reward / total-cost",
}
