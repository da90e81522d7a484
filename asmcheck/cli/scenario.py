"""``asmcheck scenario``: run Avalla scenarios (ASMETA's validator language)."""
from __future__ import annotations

import json
import os

from .. import api
from .common import EXIT_ERROR, EXIT_OK, EXIT_VIOLATED, add_domain_options, check_output_path, out


def run(args) -> int:
    if getattr(args, "coverage", None) and args.coverage != "-":
        check_output_path(args.coverage, "--coverage")
    results = []
    code = EXIT_OK
    files = _expand(args.files)
    if not files:
        raise api.UsageError("no scenario to run (the folder has no .avalla file)")
    if getattr(args, "monitored", None):
        raise api.UsageError("--monitored does not apply to a scenario: its monitored functions take the values "
                             "its set commands give, as in AsmetaV (--int-range and --max-loop do apply)")
    for path in files:
        try:
            res = api.scenario(path, max_until=args.max_until, seed=args.seed,
                               import_path=list(getattr(args, "import_path", None) or []),
                               int_range=args.int_range, max_loop=args.max_loop)
        except api.AsmError as err:
            results.append((path, None, err))
            code = EXIT_ERROR
            continue
        except RecursionError:
            err = api.AsmError(None, f"{path}: the scenario or its spec nests too deeply (recursion limit reached)")
            results.append((path, None, err))
            code = EXIT_ERROR
            continue
        results.append((path, res, None))
        if not res.ok and code == EXIT_OK:
            code = EXIT_VIOLATED
    if args.format == "json":
        docs = []
        for path, res, err in results:
            if err is not None:
                docs.append({"file": path, "result": "error", "error": _error(err)})
            else:
                docs.append(api.scenario_json(res))
        if getattr(args, "coverage", None) and code != EXIT_ERROR:
            docs = [{"scenarios": docs, "coverage": _coverage(args, files, "json")}]
        out(json.dumps(docs[0] if len(docs) == 1 else {"scenarios": docs}, indent=2))
    else:
        lines = []
        for path, res, err in results:
            if err is not None:
                lines.append(err.render())
                lines.append(f"scenario {path}: ERROR")
            else:
                lines.extend(api.scenario_report(res, args.verbose))
        if len(results) > 1:
            ok = sum(1 for _, res, err in results if err is None and res.ok)
            bad = sum(1 for _, res, err in results if err is None and not res.ok)
            errs = sum(1 for _, _, err in results if err is not None)
            lines.append(f"{len(results)} scenarios: {ok} passed, {bad} failed, {errs} with input errors")
        if getattr(args, "coverage", None) and code != EXIT_ERROR:
            lines += [""] + _coverage(args, files, "text")
        out("\n".join(lines))
    return code


def _coverage(args, files, fmt):
    """``--coverage[=OUT.html]``: rule, branch and update coverage by the scenarios (AsmetaV's report)."""
    from ..review.coverage import cli_scenario_coverage
    return cli_scenario_coverage(files, args.coverage, fmt=fmt, max_until=args.max_until)


def _error(err) -> dict:
    sp = err.span
    return {"path": sp.path if sp else None, "line": sp.line if sp and sp.line else None,
            "column": sp.col if sp and sp.line else None, "message": err.message}


def _expand(paths: list[str]) -> list[str]:
    """Files as given; a folder stands for the scenarios in it (sorted), as in AsmetaV."""
    found = []
    for p in paths:
        if os.path.isdir(p):
            found.extend(sorted(os.path.join(p, f) for f in os.listdir(p) if f.endswith(".avalla")))
        else:
            found.append(p)
    return found


def register(sub) -> None:
    p = sub.add_parser(
        "scenario", help="run Avalla scenarios (.avalla) against the spec they load",
        description="Run each Avalla scenario FILE (the language of ASMETA's validator AsmetaV): load the "
                    "spec, apply set/exec/pick, run step and step until, evaluate every check and the "
                    "scenario invariants. Monitored functions take the values the scenario sets (and keep "
                    "them until the next set); choose rules take their first choice unless picked (or "
                    "--seed). Exit 0 when every check passes, 1 when a check fails (or an invariant is "
                    "violated, a step fails, a step until does not end), 2 on an input error.")
    p.add_argument("files", nargs="+", metavar="FILE.avalla", help="scenario files (a folder: every .avalla in it)")
    p.add_argument("--format", choices=["text", "json"], default="text")
    p.add_argument("--coverage", nargs="?", const="-", metavar="OUT.html",
                   help="also report which rules, branches and updates the scenarios cover (and write the "
                        "spec's source coloured by coverage to OUT.html)")
    p.add_argument("-v", "--verbose", action="store_true",
                   help="also list steps, sets, picks and execs, and the values read by passed checks")
    p.add_argument("--max-until", type=int, default=100_000, metavar="N",
                   help="the most steps one 'step until' may take (default 100000; AsmetaV has no bound)")
    add_domain_options(p)
    p.add_argument("--seed", type=int, help="choose rules that no pick fixes take random choices from this seed")
    p.set_defaults(func=run)
