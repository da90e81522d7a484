"""The `asmcheck scenario` subcommand: run Avalla scenarios (ASMETA's validator language)."""
from __future__ import annotations

import json
import os

from .errors import AsmError, UsageError

EXIT_OK, EXIT_VIOLATED, EXIT_ERROR = 0, 1, 2


def cmd_scenario(args) -> int:
    from .avalla.report import error_json, json_report, text_report
    from .avalla.runner import run_scenario

    results = []
    code = EXIT_OK
    files = _expand(args.files)
    if not files:
        raise UsageError("no scenario to run (the folder has no .avalla file)")
    for path in files:
        try:
            out = run_scenario(path, max_until=args.max_until, seed=args.seed)
        except AsmError as err:
            results.append((path, None, err))
            code = EXIT_ERROR
            continue
        except RecursionError:
            err = AsmError(None, f"{path}: the scenario or its spec nests too deeply (recursion limit reached)")
            results.append((path, None, err))
            code = EXIT_ERROR
            continue
        results.append((path, out, None))
        if not out.ok and code == EXIT_OK:
            code = EXIT_VIOLATED
    if args.format == "json":
        docs = []
        for path, out, err in results:
            if err is not None:
                docs.append({"file": path, "result": "error", "error": error_json(err)})
            else:
                docs.append(json_report(out))
        print(json.dumps(docs[0] if len(docs) == 1 else {"scenarios": docs}, indent=2))
    else:
        lines = []
        for path, out, err in results:
            if err is not None:
                lines.append(err.render())
                lines.append(f"scenario {path}: ERROR")
            else:
                lines.extend(text_report(out, args.verbose))
        if len(results) > 1:
            ok = sum(1 for _, out, err in results if err is None and out.ok)
            bad = sum(1 for _, out, err in results if err is None and not out.ok)
            errs = sum(1 for _, _, err in results if err is not None)
            lines.append(f"{len(results)} scenarios: {ok} passed, {bad} failed, {errs} with input errors")
        print("\n".join(lines))
    return code


def _expand(paths: list[str]) -> list[str]:
    """Files as given; a folder stands for the scenarios in it (sorted), as in AsmetaV."""
    out = []
    for p in paths:
        if os.path.isdir(p):
            out.extend(sorted(os.path.join(p, f) for f in os.listdir(p) if f.endswith(".avalla")))
        else:
            out.append(p)
    return out


def register(sub) -> None:
    """Add the subcommand to `sub` (an argparse subparsers object)."""
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
    p.add_argument("-v", "--verbose", action="store_true",
                   help="also list steps, sets, picks and execs, and the values read by passed checks")
    p.add_argument("--max-until", type=int, default=1000, metavar="N",
                   help="the most steps one 'step until' may take (default 1000)")
    p.add_argument("--seed", type=int, help="choose rules that no pick fixes take random choices from this seed")
    p.set_defaults(func=cmd_scenario)
