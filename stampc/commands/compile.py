"""``stampc compile``: lower a domain/problem to the JSON IR or to PPDDL.

Never imports user-bound Python code: bindings are carried as strings.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Callable, TextIO

from stampc.commands.common import (add_import_options, add_input_arguments, fail_with,
                                    print_warnings, reports_errors)
from stampc.diagnostics import StampcError

HELP = "compile .stamp (or import .pddl) to the versioned JSON IR or to PPDDL"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_input_arguments(parser)
    parser.add_argument("--target", choices=("ir", "ppddl"), default="ir")
    parser.add_argument("--keep-derived", action="store_true",
                        help="for --target ppddl: write derived predicates as (:derived ...) "
                             "instead of compiling them away")
    parser.add_argument("--level", choices=("lifted", "grounded", "both"), default="both",
                        help="for --target ir: which IR level(s) to write (default both)")
    parser.add_argument("-o", "--output", metavar="DIR",
                        help="write files here (default: print to standard output)")
    add_import_options(parser)


@reports_errors("compile")
def run(args: argparse.Namespace) -> int:
    from stampc import api
    from stampc.ir.json_io import write_grounded_json, write_lifted_json

    started = time.perf_counter()
    try:
        model = api.load_model(args.files, lenient=args.lenient)
        print_warnings(model.diagnostics)
        # name -> writer; IR documents are streamed (a grounded one can be large)
        outputs: dict[str, Callable[[TextIO], None]] = {}
        if args.target == "ppddl":
            domain_text, problem_text = api.to_ppddl(model, keep_derived=args.keep_derived)
            outputs["domain.pddl"] = _text(domain_text)
            outputs["problem.pddl"] = _text(problem_text)
        else:
            if args.level in ("lifted", "both"):
                outputs["lifted.json"] = lambda f: write_lifted_json(model, f)
            if args.level in ("grounded", "both"):
                gm = api.ground(model, conflicting_effects=args.conflicting_effects)
                print_warnings(gm.diagnostics)
                outputs["grounded.json"] = lambda f: write_grounded_json(gm, f)
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
            for name, write in outputs.items():
                with open(out / name, "w", encoding="utf-8") as f:
                    write(f)
        except OSError as exc:
            print(f"stampc compile: cannot write to {out}: {exc.strerror}", file=sys.stderr)
            return 2
        print(f"wrote {', '.join(outputs)} to {out} in {time.perf_counter() - started:.3f}s",
              file=sys.stderr)
    else:
        for name, write in outputs.items():
            if len(outputs) > 1:
                print(f";; ---- {name}" if name.endswith(".pddl") else f"// ---- {name}")
            write(sys.stdout)
    return 0


def _text(text: str) -> Callable[[TextIO], None]:
    return lambda f: f.write(text + ("" if text.endswith("\n") else "\n"))
