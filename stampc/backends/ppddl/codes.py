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
TOO_DEEP = "P108"          # formula / effect / expression nested beyond MAX_NESTING
FOND = "P109"              # (oneof ...): FOND non-determinism is not supported
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

# Warnings of --lenient (API lenient=True): what mdp-lib's mini-gpt parser accepts.
IMPLICIT_PREDICATE = "P201"  # predicate used without declaration: declared implicitly
IMPLICIT_CONSTANT = "P202"   # undeclared name in the domain (a problem object): a constant
REPEATED_VARIABLE = "P203"   # a variable name repeated in a predicate declaration
GOAL_FALSE = "P204"          # problem without a goal: the goal is false (as in mini-gpt)

#: Hint added to the errors that --lenient turns into warnings.
LENIENT_HINT = "--lenient (API: lenient=True) accepts this as mini-gpt does, with a warning"

#: code -> one-line description, used by the docs table test.
DESCRIPTIONS = {
    SYNTAX: "syntax error; the message lists the expected tokens in words",
    UNSUPPORTED: "construct outside the supported dialect (either types, :durative-action, ...)",
    REQUIREMENT: "unknown or unsupported requirement flag",
    DUPLICATE: "name declared twice (type, constant, object, predicate, action, parameter)",
    IO: "file cannot be read",
    MISSING: "no domain, no problem, problem name not found, or several problems and no name",
    DOMAIN_MISMATCH: "the problem's (:domain X) does not name the domain it is read with",
    NO_GOAL: "problem without (:goal ...)",
    TOO_DEEP: "formula, effect or numeric expression nested more than 100 levels deep",
    FOND: "FOND non-deterministic (oneof ...) effects are not supported",
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
    IMPLICIT_PREDICATE: "warning (--lenient): undeclared predicate declared implicitly",
    IMPLICIT_CONSTANT: "warning (--lenient): undeclared name in the domain taken as a constant",
    REPEATED_VARIABLE: "warning (--lenient): variable repeated in a predicate declaration",
    GOAL_FALSE: "warning (--lenient): problem without a goal; the goal is false",
}
