"""``asmcheck bmc``: bounded model checking and k-induction with Z3."""
from __future__ import annotations

import json
from pathlib import Path

from .. import api
from .common import EXIT_ERROR, add_domain_options, check_limits, color_on, error, load_options, out


def run(args) -> int:
    if args.k < 0:
        raise api.UsageError("-k must be 0 or more")
    check_limits(args)
    model = api.load(args.file, **load_options(args))
    try:
        res = model.bmc(args.k, induction=args.induction, properties=args.property, assume=args.assume,
                        aux=args.aux or (), infer=args.infer, first=args.first, loop_bound=args.loop_bound,
                        max_seconds=args.max_seconds)
    except api.ReplayMismatch as e:
        error(f"asmcheck: internal error: a trace found by Z3 does not replay through the step function ({e}); "
              f"no counterexample is shown")
        return EXIT_ERROR
    code = res.exit_code
    rows = res.rows
    temporal = model.temporal
    if args.format == "itf":
        from ..review.itf import itf_documents
        out(json.dumps(itf_documents(model.machine, res.violations, args.file), indent=1))
        return code
    if args.format == "json":
        doc = {
            "spec": model.name,
            "engine": "z3",
            "mode": "induction" if args.induction else "bmc",
            "verdict": res.verdict,
            "states": None,
            "transitions": None,
            "depth": res.depth,
            "k": args.k,
            "seconds": round(res.seconds, 3),
            "properties": rows,
            "violations": res.violation_json(),
        }
        if res.reason:
            doc["unknown"] = res.reason
        if temporal:
            doc["not_checked"] = res.not_checked
        out(json.dumps(doc, indent=2))
        return code
    color = color_on()
    what = f"k-induction up to k={args.k}" if args.induction else f"bounded model checking to depth {args.k}"
    out(f"{Path(args.file).name}: {what} (z3), {res.seconds:.2f} s")
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
        out(f"  {r['property']:<{width}} {r['verdict']}{extra}{aux}")
    for lines in res.violation_text(color):
        out()
        for line in lines:
            out(line)
    if res.not_checked:
        out(f"not checked by bmc: {', '.join(res.not_checked)} (temporal properties)")
    if res.reason:
        out(f"unknown: {res.reason}")
    out(f"verdict: {res.verdict}" + (f" (depth {res.depth})" if res.verdict == "holds-to-depth" else ""))
    return code


def register(sub) -> None:
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
    add_domain_options(p)
    p.add_argument("--format", choices=["text", "json", "itf"], default="text",
                   help="itf: the counterexamples as ITF traces (Apalache/Quint's Informal Trace Format)")
    p.set_defaults(func=run)
