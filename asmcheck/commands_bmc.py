"""``asmcheck bmc``: bounded model checking and k-induction with Z3."""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path

EXIT_OK, EXIT_VIOLATED, EXIT_ERROR, EXIT_UNKNOWN = 0, 1, 2, 3


def cmd_bmc(args) -> int:
    from .report.trace import trace_json, trace_text
    from .smt.bmc import ReplayMismatch
    from .smt.check import check

    if args.k < 0:
        from .errors import UsageError
        raise UsageError("-k must be 0 or more")
    try:
        spec, machine, model, out, temporal, targets = check(args.file, args)
    except ReplayMismatch as e:
        print(f"asmcheck: internal error: a trace found by Z3 does not replay through the step function ({e}); "
              f"no counterexample is shown", file=sys.stderr)
        return EXIT_ERROR
    code = {"violated": EXIT_VIOLATED, "unknown": EXIT_UNKNOWN}.get(out.verdict, EXIT_OK)
    rows = _property_rows(out, model)
    if args.format == "json":
        res = {
            "spec": spec.name,
            "engine": "z3",
            "mode": "induction" if args.induction else "bmc",
            "verdict": out.verdict,
            "states": None,
            "transitions": None,
            "depth": out.depth,
            "k": args.k,
            "seconds": round(out.seconds, 3),
            "properties": rows,
            "violations": [{"property": f.prop.name, "kind": f.trace.kind, "message": f.message, "depth": f.depth,
                            "trace": trace_json(machine, f.trace)} for f in out.found],
        }
        if out.reason:
            res["unknown"] = out.reason
        if temporal:
            res["not_checked"] = [p.name for p in temporal if p.kind in ("ltl", "ctl")]
        print(json.dumps(res, indent=2))
        return code
    color = sys.stdout.isatty() and not os.environ.get("NO_COLOR")
    what = f"k-induction up to k={args.k}" if args.induction else f"bounded model checking to depth {args.k}"
    print(f"{Path(args.file).name}: {what} (z3), {out.seconds:.2f} s")
    width = max([40] + [len(r["property"]) + 1 for r in rows])
    for r in rows:
        extra = ""
        if r["verdict"] == "violated":
            extra = f" at depth {r['depth']}"
        elif r["verdict"] == "proved" and "k" in r:
            extra = f" (k={r['k']}" + (f", with {', '.join(r['needed'])}" if r["needed"] else "")
            if r["lemmas"]:
                extra += f"; {len(r['lemmas'])} lemma{'s' if len(r['lemmas']) != 1 else ''}: " + \
                    "; ".join(r["lemmas"][:8]) + ("; ..." if len(r["lemmas"]) > 8 else "")
            extra += ")"
        aux = "  [auxiliary]" if r.get("auxiliary") else ""
        print(f"  {r['property']:<{width}} {r['verdict']}{extra}{aux}")
    for f in out.found:
        print()
        prop = f.prop.wrapper
        span = getattr(prop, "span", None)
        where = f" ({span.short()})" if span is not None and span.line else ""
        head = "a step raises an error" if f.prop.kind == "error" else f"{f.prop.name}{where} is violated"
        steps = len(f.trace.steps) - 1
        print(f"{head}" + (f": {f.message}" if f.message else "") +
              f" -- shortest trace, {steps} step{'s' if steps != 1 else ''}" +
              (" (the last step breaks it)" if f.trace.kind == "step" else "") + ", replayed:")
        for line in trace_text(machine, f.trace, color):
            print("  " + line)
    if temporal and any(p.kind in ("ltl", "ctl") for p in temporal):
        print(f"not checked by bmc: {', '.join(p.name for p in temporal if p.kind in ('ltl', 'ctl'))} "
              f"(temporal properties)")
    if out.reason:
        print(f"unknown: {out.reason}")
    print(f"verdict: {out.verdict}" + (f" (depth {out.depth})" if out.verdict == "holds-to-depth" else ""))
    return code


def _property_rows(out, model) -> list[dict]:
    rows = []
    for p in out.props:
        r = {"property": p.name, "kind": getattr(p.wrapper, "kind", p.kind), "verdict": out.verdicts[p.name]}
        if p.name in out.depths:
            r["depth"] = out.depths[p.name]
        if p.name in out.induction:
            r["k"] = out.induction[p.name]["k"]
            r["needed"] = out.induction[p.name]["needed"]
            r["lemmas"] = out.induction[p.name]["lemmas"]
        if p.aux:
            r["auxiliary"] = True
        rows.append(r)
    return rows


def register(sub) -> None:
    """Add the subcommand to `sub` (an argparse subparsers object)."""
    from .commands import _add_domain_options
    p = sub.add_parser(
        "bmc", help="bounded model checking and k-induction with Z3",
        description="Encode the initial states and the step of FILE in Z3, unroll K steps and look for a "
                    "violation of its invariants, of the properties that apply to it and for run-time errors. "
                    "A violation is decoded and replayed by the step function before it is shown. With "
                    "--induction, k-induction proves the properties for every depth.",
        epilog="Exit codes: 0 no violation up to K (or proved); 1 a property is violated; 2 usage, syntax or "
               "type error, or a construct the encoding does not support; 3 unknown (time limit, a value the "
               "encoding cannot represent, or not inductive up to K).")
    p.add_argument("file", metavar="FILE")
    p.add_argument("-k", type=int, default=10, metavar="K", help="number of steps to unroll (default 10)")
    p.add_argument("--induction", action="store_true", help="prove the properties for every depth by k-induction "
                                                            "(k = 1..K)")
    p.add_argument("--property", action="append", metavar="NAME",
                   help="check only this property (repeatable); with --induction the others serve as "
                        "auxiliary invariants")
    p.add_argument("--assume", action="append", metavar="NAME",
                   help="with --property: the properties that may strengthen the induction (default: all others)")
    p.add_argument("--aux", action="append", metavar="TERM",
                   help="an auxiliary invariant, 'name: term' or 'term' (repeatable): checked, and used to "
                        "strengthen k-induction")
    p.add_argument("--infer", action="store_true",
                   help="with --induction: also try every two-literal clause over locations with few values as "
                        "a lemma (kept when k-induction proves it)")
    p.add_argument("--first", action="store_true", help="stop at the first violation")
    p.add_argument("--loop-bound", type=int, metavar="N",
                   help="unroll while / iterate loops N times in a step (default 16; a loop that may run longer "
                        "makes the answer unknown)")
    p.add_argument("--max-seconds", type=float, metavar="S", help="give up after S seconds (verdict unknown)")
    p.add_argument("--properties", action="append", metavar="FILE",
                   help="a property file to check (repeatable); by default the files in properties/ that apply")
    p.add_argument("--no-default-properties", action="store_true",
                   help="check only the spec's own properties (and --properties files)")
    _add_domain_options(p)
    p.add_argument("--format", choices=["text", "json"], default="text")
    p.set_defaults(func=cmd_bmc)
