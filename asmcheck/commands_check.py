"""The `asmcheck check` subcommand: the property gate for CI.

``asmcheck check [PATHS...]`` explores every spec under PATHS (``*.asm`` files; folders are
walked, modules skipped; default ``specs/``) with the properties that apply to it, prints
one row per spec and property, and exits

* 0 when every property holds (or is violated as the spec declares it expects),
* 1 when a property is violated unexpectedly, or an expected violation does not happen,
* 2 on an input error (a spec or property file that does not parse or type-check, a path
  that does not exist, an expected violation of a property that is not checked),
* 3 when a limit (states, depth, time) stopped an exploration first.

When several apply, the first in the order 2, 1, 3 wins.  See report/gate.py for how an
expected violation (``// asmcheck: expect violated NAME``) is judged.
"""
from __future__ import annotations

import argparse
import os
import re
import sys
import time
from pathlib import Path

from .errors import AsmError, UsageError

# the clock the per-spec times are read from (tests replace it to get fixed times)
CLOCK = time.perf_counter


def find_specs(paths: list[str]) -> list[str]:
    """The ``.asm`` files under ``paths``, in order: a file as given, a folder walked (sorted,
    modules and hidden folders left out)."""
    out: list[str] = []
    for p in paths:
        path = Path(p)
        if path.is_file():
            out.append(p)
        elif path.is_dir():
            for f in sorted(path.rglob("*.asm")):
                rel = f.relative_to(path)
                if any(part.startswith(".") for part in rel.parts[:-1]):
                    continue
                if _is_module(f):
                    continue
                out.append(str(f))
        else:
            raise UsageError(f"{p}: no such file or folder")
    seen = set()
    uniq = []
    for f in out:
        key = os.path.abspath(f)
        if key not in seen:
            seen.add(key)
            uniq.append(f)
    return uniq


def _is_module(path: Path) -> bool:
    from .props.files import _strip_comments
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return False
    m = re.search(r"\b(asm|module)\s+[A-Za-z_]", _strip_comments(text))
    return bool(m) and m.group(1) == "module"


def check_spec(path: str, args, *, strict: bool = False, avalla_dir: str | None = None, root: str | None = None,
               clock=None):
    """Explore one spec and judge its properties: a report.gate.SpecOutcome."""
    from .commands_explore import run_exploration
    from .explore.bfs import ReplayError
    from .report.gate import build_outcome, error_outcome

    clock = clock or CLOCK
    t0 = clock()
    try:
        spec, machine, ex, result, temporal = run_exploration(path, args, getattr(args, "properties", None))
        temporal_results = []
        temporal_error = ""
        if temporal and result.verdict != "incomplete":
            from .temporal import check_temporal
            try:
                temporal_results = check_temporal(ex, temporal, fair=getattr(args, "fair", []) or [])
            except AsmError:
                raise
            except Exception as exc:        # an internal error: reported on the rows, the gate goes on
                temporal_error = f"internal error in LTL/CTL checking: {type(exc).__name__}: {exc}"
        out = build_outcome(path, spec, machine, ex, result, temporal, temporal_results, strict=strict, root=root,
                            avalla_dir=avalla_dir, temporal_error=temporal_error)
    except AsmError as err:
        return error_outcome(path, err, root, clock() - t0)
    except ReplayError as err:
        return error_outcome(path, AsmError(None, f"internal error: a counterexample does not replay ({err})"),
                             root, clock() - t0)
    except RecursionError:
        return error_outcome(path, AsmError(None, f"{path}: the spec nests too deeply (recursion limit reached)"),
                             root, clock() - t0)
    except Exception as exc:               # an internal error: this spec fails, the others are checked
        return error_outcome(path, AsmError(None, f"{path}: internal error: {type(exc).__name__}: {exc}"),
                             root, clock() - t0)
    out.seconds = clock() - t0
    if avalla_dir is not None:
        from .report.avalla_export import write_scenario
        for row in out.properties:
            cx = row.counterexample
            if cx is not None and cx.avalla is not None:
                write_scenario(os.path.join(avalla_dir, os.path.basename(cx.avalla_path)), cx.avalla)
    return out


def run_check(paths: list[str], args, *, clock=None, root=None, progress=None) -> list:
    """Check every spec under ``paths``: [SpecOutcome], in order."""
    specs = find_specs(paths)
    if not specs:
        raise UsageError("no .asm specs under " + ", ".join(paths))
    outcomes = []
    for path in specs:
        if progress is not None:
            progress(path)
        outcomes.append(check_spec(path, args, strict=getattr(args, "strict_expect", False),
                                   avalla_dir=getattr(args, "avalla", None), root=root, clock=clock))
    return outcomes


# ----------------------------------------------------------------- text
def summary_table(outcomes, color: bool = False, timings: bool = True) -> list[str]:
    from .report.gate import FAIL, ERROR, INCOMPLETE
    head = ["SPEC", "PROPERTY", "VERDICT", "STATES"] + (["SECONDS"] if timings else [])
    rows = []
    for o in outcomes:
        for p in o.properties:
            row = [o.path, p.name, p.label, f"{o.states:,}" if o.verdict != "error" else "-"]
            if timings:
                row.append(f"{o.seconds:.2f}")
            rows.append((row, p.status))
    widths = [max(len(head[i]), *(len(r[i]) for r, _ in rows)) for i in range(len(head))]

    def fmt(cells, status=None):
        parts = []
        for i, c in enumerate(cells):
            if i >= 3:
                parts.append(c.rjust(widths[i]))
            else:
                parts.append(c.ljust(widths[i]) if i < len(cells) - 1 else c)
        line = "  ".join(parts).rstrip()
        if color and status in (FAIL, ERROR):
            line = f"\x1b[1;31m{line}\x1b[0m"
        elif color and status == INCOMPLETE:
            line = f"\x1b[33m{line}\x1b[0m"
        return line
    out = [fmt(head)]
    out.extend(fmt(r, s) for r, s in rows)
    return out


def details(outcomes, color: bool = False, traces: str = "failing") -> list[str]:
    """What went wrong, spec by spec, with the counterexamples."""
    from .report.gate import ERROR, FAIL, INCOMPLETE, cx_summary, trace_lines
    out = []
    for o in outcomes:
        if o.error:
            out.append("")
            out.append(f"ERROR {o.path}: the spec could not be checked")
            out.extend("  " + ln for ln in o.error.splitlines())
            continue
        for p in o.properties:
            show_trace = p.counterexample is not None and (
                traces == "all" or (traces == "failing" and p.status == FAIL))
            if p.status == PASS_STATUS and not show_trace:
                continue
            where = f" ({p.location})" if p.location else ""
            tag = {FAIL: "FAIL", ERROR: "ERROR", INCOMPLETE: "INCOMPLETE"}.get(p.status, "NOTE")
            head = f"{tag} {o.path}: "
            if p.verdict == "violated":
                cx = p.counterexample
                n = len(cx.steps) - 1 if cx and cx.steps else None
                what = "deadlock" if p.kind == "deadlock" else (
                    "a step fails" if p.kind == "error" else f"{p.name}{where} is violated")
                head += what + (f": {p.message}" if p.message else "")
                if p.expected:
                    head += " (expected)"
                elif p.status != FAIL:
                    head += " (tolerated: the spec declares other expected violations)"
                if n is not None and show_trace:
                    head += f" -- {cx_summary(cx)}:"
                out.append("")
                out.append(head)
                if show_trace:
                    out.extend("  " + ln for ln in trace_lines(cx, color))
                    if cx.avalla_path:
                        out.append(f"  Avalla scenario: {cx.avalla_path}")
            elif p.verdict == "holds" and p.expected:
                at = f" ({p.expect_location})" if p.expect_location else ""
                out.append("")
                out.append(head + f"{p.name}{where} holds, but the spec expects it to be violated{at}")
            elif p.verdict == "unknown":
                at = f"{p.expect_location}: " if p.expect_location else ""
                out.append("")
                out.append(head + at + p.message)
            elif p.status == ERROR:
                out.append("")
                out.append(head + f"{p.name}{where}: {p.label}" + (f": {p.message}" if p.message else ""))
            elif p.status == INCOMPLETE:
                why = o.reason or p.message
                out.append("")
                out.append(head + f"{p.name}: {p.label}" + (f" ({why})" if why else ""))
    return out


PASS_STATUS = "pass"


def summary_line(outcomes, code: int) -> list[str]:
    from .report.gate import counts
    c = counts(outcomes)
    gate = {0: "PASS", 1: "FAIL", 2: "ERROR", 3: "INCOMPLETE"}[code]
    return [f"checked {c['specs']} spec{'s' if c['specs'] != 1 else ''}, {c['properties']} "
            f"propert{'ies' if c['properties'] != 1 else 'y'}: {c['holds']} hold, {c['expected']} violated as "
            f"expected, {c['tolerated']} tolerated, {c['failed']} failed, {c['incomplete']} incomplete, "
            f"{c['errors']} input error{'s' if c['errors'] != 1 else ''}",
            f"gate: {gate} (exit {code})"]


def check_text(outcomes, code: int, color: bool = False, timings: bool = True, traces: str = "failing") -> str:
    lines = summary_table(outcomes, color, timings)
    lines += details(outcomes, color, traces)
    lines.append("")
    lines += summary_line(outcomes, code)
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------- the command
def write_reports(outcomes, args, code: int, root=None) -> None:
    from .report import junit, report_json, sarif
    if getattr(args, "json", None) and args.json != "-":
        report_json.write(args.json, report_json.check_json(outcomes, code))
    if getattr(args, "junit", None):
        junit.write(args.junit, junit.junit_xml(outcomes))
    if getattr(args, "sarif", None):
        sarif.write(args.sarif, sarif.sarif_log(outcomes, code, root=root))
    if getattr(args, "html", None):
        from .report import html
        html.write(args.html, html.html_report(outcomes, code))


def cmd_check(args) -> int:
    from .report.gate import exit_code

    paths = args.paths or ["specs"]
    args.format = "text" if sys.stderr.isatty() and getattr(args, "json", None) != "-" else "json"
    if args.avalla:
        os.makedirs(args.avalla, exist_ok=True)
    outcomes = run_check(paths, args)
    code = exit_code(outcomes)
    write_reports(outcomes, args, code)
    if args.json == "-":
        from .report import report_json
        report_json.dump(sys.stdout, report_json.check_json(outcomes, code))
        return code
    color = sys.stdout.isatty() and not os.environ.get("NO_COLOR")
    sys.stdout.write(check_text(outcomes, code, color, traces=args.traces))
    return code


def register(sub) -> None:
    """Add the subcommand to `sub` (an argparse subparsers object)."""
    from .commands_explore import add_explore_options
    p = sub.add_parser(
        "check", help="check every spec under PATHS: the property gate for CI",
        description="Explore every spec under PATHS (.asm files; folders are walked; default specs/) with the "
                    "properties that apply to it (its own, and those of the property files in properties/), "
                    "print a table of spec, property, verdict, states and seconds, and the counterexample of "
                    "each failure. A spec may declare the properties it is built to break with a line "
                    "'// asmcheck: expect violated NAME': such a violation passes the gate ('violated "
                    "(expected)'), and fails it when it does not happen. Other violations in such a spec are "
                    "consequences of its bug: they are 'tolerated' (--strict-expect fails them).",
        epilog="Exit codes: 0 the gate passes; 1 a property is violated unexpectedly, or an expected violation "
               "does not happen; 2 input error (syntax, types, a missing path, an expected violation of an "
               "unknown property); 3 incomplete (a limit stopped an exploration first). When several apply, "
               "2 wins over 1, and 1 over 3.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("paths", nargs="*", metavar="PATH", help="spec files or folders (default: specs)")
    add_explore_options(p)
    p.add_argument("--junit", metavar="OUT.xml", help="write a JUnit XML report: one test case per spec and property")
    p.add_argument("--sarif", metavar="OUT.sarif",
                   help="write a SARIF 2.1.0 log: one result per violation, at the property's declaration")
    p.add_argument("--json", metavar="OUT.json", help="write the results as JSON ('-': print them instead of the "
                                                     "table); docs/check.schema.json")
    p.add_argument("--html", metavar="OUT.html", help="write a self-contained HTML report with every counterexample")
    p.add_argument("--avalla", metavar="DIR", help="write every counterexample as an Avalla scenario into DIR")
    p.add_argument("--strict-expect", action="store_true",
                   help="in a spec that declares expected violations, fail on any other violation too")
    p.add_argument("--traces", choices=["failing", "all", "none"], default="failing",
                   help="which counterexamples to print (default: those of failures)")
    p.set_defaults(func=cmd_check)
