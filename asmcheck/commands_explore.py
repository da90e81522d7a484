"""``asmcheck explore``: exhaustive exploration with properties, limits and reports."""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path

from .errors import AsmError, UsageError

EXIT_OK, EXIT_VIOLATED, EXIT_ERROR, EXIT_INCOMPLETE = 0, 1, 2, 3


def _progress_printer():
    if not sys.stderr.isatty():
        return None

    def show(states, depth, transitions, secs):
        rate = states / secs if secs > 0 else 0
        sys.stderr.write(f"\r  {states:,} states, {transitions:,} transitions, depth {depth}, "
                         f"{rate:,.0f} states/s   ")
        sys.stderr.flush()
    return show


def run_exploration(path: str, args, prop_files=None):
    """Load a spec and its properties, explore, return (spec, machine, explorer, result, props)."""
    from .commands import _load, machine_options
    from .explore.bfs import Explorer
    from .props import spec_properties
    from .props.files import properties_for

    spec, machine = _load(path, machine_options(args))
    state_props, step_props = spec_properties(machine)
    extra_state, extra_step, temporal = properties_for(spec, machine, path, prop_files,
                                                       use_default=not getattr(args, "no_default_properties", False))
    state_props += extra_state
    step_props += extra_step
    progress = _progress_printer() if getattr(args, "format", "text") == "text" else None
    keep_graph = bool(getattr(args, "graph", None)) or bool(temporal)
    engine = getattr(args, "engine", "auto")
    ex = None
    has_invar = any(p.kind == "invar" for p in spec.properties)
    from .parallel import cli as scaling
    if scaling.wanted(args):
        ex, result = scaling.explore(path, machine, state_props, step_props, temporal, args, keep_graph=keep_graph,
                                     progress=progress, options=machine_options(args), prop_files=prop_files)
    elif engine != "python" and not keep_graph and not step_props and not has_invar:
        from .explore.native import NativeExplorer, Unsupported
        try:
            ex = NativeExplorer(machine, max_states=args.max_states, max_depth=args.max_depth,
                                max_seconds=args.max_seconds, deadlock=args.deadlock, state_props=state_props)
            result = ex.run()
        except Unsupported as e:
            if engine == "native":
                raise UsageError(f"the native explorer cannot run {Path(path).name}: {e}") from None
            ex = None
    elif engine == "native":
        why = "step properties" if step_props else "INVAR constraints" if has_invar else "LTL/CTL properties or --graph"
        raise UsageError(f"the native explorer cannot run {Path(path).name}: it needs the state graph or "
                         f"checks {why}")
    if ex is None:
        ex = Explorer(machine, max_states=args.max_states, max_depth=args.max_depth, max_seconds=args.max_seconds,
                      deadlock=args.deadlock, progress=progress, keep_graph=keep_graph,
                      state_props=state_props, step_props=step_props)
        result = ex.run()
        result.engine = "python"
    if progress is not None:
        sys.stderr.write("\r" + " " * 78 + "\r")
    return spec, machine, ex, result, temporal


def cmd_explore(args) -> int:
    from .report.trace import build_trace, trace_json, trace_text
    from .explore.bfs import ReplayError

    spec, machine, ex, result, temporal = run_exploration(args.file, args, args.properties)
    traces = []
    for v in result.violations:
        try:
            tr = build_trace(ex, v)
        except ReplayError as e:
            print(f"asmcheck: internal error: the trace of {v.prop.name} does not replay ({e})", file=sys.stderr)
            return EXIT_ERROR
        traces.append((v, tr))
    temporal_results = []
    if temporal and result.verdict != "incomplete":
        from .temporal import check_temporal
        temporal_results = check_temporal(ex, temporal, fair=args.fair)
        for tres in temporal_results:
            if not tres.holds:
                result.verdict = "violated"
    if args.graph:
        from .report.graph import write_graph
        write_graph(ex, args.graph)
    if getattr(args, "avalla", None) and traces:
        from .report.avalla_export import explore_avalla
        explore_avalla(args.avalla, machine, args.file, traces)
    if getattr(args, "html", None):
        from .report import html as html_report
        from .report.gate import build_outcome
        outcome = build_outcome(args.file, spec, machine, ex, result, temporal, temporal_results)
        pre_code = 1 if result.verdict == "violated" else 3 if result.verdict == "incomplete" else 0
        html_report.write(args.html, html_report.html_report([outcome], pre_code, title="asmcheck explore"))
    code = EXIT_OK
    if result.verdict == "violated":
        code = EXIT_VIOLATED
    elif result.verdict == "incomplete":
        code = EXIT_INCOMPLETE
    if args.format == "json":
        out = {
            "spec": spec.name,
            "verdict": result.verdict,
            "states": result.states,
            "transitions": result.transitions,
            "depth": result.depth,
            "seconds": round(result.seconds, 3),
            "engine": getattr(result, "engine", "python"),
            "properties": _property_table(result, temporal_results),
            "violations": [{"property": v.prop.name, "kind": tr.kind, "message": v.message,
                            "trace": trace_json(machine, tr)} for v, tr in traces]
                          + [t.json(machine) for t in temporal_results if not t.holds],
        }
        if result.reason:
            out["incomplete"] = result.reason
        if getattr(result, "bitstate", None):
            out["bitstate"] = result.bitstate
        print(json.dumps(out, indent=2))
        return code
    color = sys.stdout.isatty() and not os.environ.get("NO_COLOR")
    print(f"{Path(args.file).name}: {result.states:,} states, {result.transitions:,} transitions, "
          f"depth {result.depth}, {result.seconds:.2f} s")
    for row in _property_table(result, temporal_results):
        print(f"  {row['property']:<40} {row['verdict']}")
    for v, tr in traces:
        print()
        where = f" ({v.prop.span.short()})" if getattr(v.prop, "span", None) is not None and v.prop.span.line else ""
        what = "deadlock" if v.prop.name == "deadlock" else f"{v.prop.name}{where} is violated"
        steps = len(tr.steps) - 1
        print(f"{what}" + (f": {v.message}" if v.message else "") +
              f" -- shortest trace, {steps} step{'s' if steps != 1 else ''}" +
              (" (the last step breaks it)" if tr.kind == "step" else "") + ":")
        for line in trace_text(machine, tr, color):
            print("  " + line)
    for t in temporal_results:
        if not t.holds:
            print()
            for line in t.text(machine, color):
                print(line)
    if result.reason:
        print(f"incomplete: {result.reason}")
    for line in getattr(result, "notes", ()):
        print(line)
    print(f"verdict: {result.verdict}")
    return code


def _property_table(result, temporal_results) -> list[dict]:
    bad = {v.prop.name for v in result.violations}
    incomplete = result.stopped_early
    rows = []
    for p in result.checked:
        verdict = "violated" if p.name in bad else ("incomplete" if incomplete else "holds")
        rows.append({"property": p.name, "kind": getattr(p, "kind", "invariant"), "verdict": verdict})
    for v in result.violations:
        if v.prop.name in ("deadlock", "error"):
            rows.append({"property": v.prop.name, "kind": v.prop.kind, "verdict": "violated"})
    if getattr(result, "deadlock_checked", False) and "deadlock" not in bad:
        rows.append({"property": "deadlock", "kind": "deadlock",
                     "verdict": "incomplete" if incomplete else "holds"})
    for t in temporal_results:
        verdict = getattr(t, "verdict", None) or ("holds" if t.holds else "violated")
        if verdict == "error":
            verdict = "cannot be checked"
        rows.append({"property": t.name, "kind": t.kind, "verdict": verdict})
    return rows


def add_explore_options(p) -> None:
    from .commands import _add_domain_options
    p.add_argument("--max-states", type=int, metavar="N", help="stop after N distinct states (verdict incomplete)")
    p.add_argument("--max-depth", type=int, metavar="N", help="do not go deeper than N steps (verdict incomplete)")
    p.add_argument("--max-seconds", type=float, metavar="S", help="stop after S seconds (verdict incomplete)")
    p.add_argument("--deadlock", action="store_true",
                   help="report a state whose only successor is itself, or that has none")
    p.add_argument("--properties", action="append", metavar="FILE",
                   help="a property file to check (repeatable); by default the files in properties/ that apply")
    p.add_argument("--no-default-properties", action="store_true",
                   help="check only the spec's own properties (and --properties files)")
    p.add_argument("--engine", choices=["auto", "python", "native"], default="auto",
                   help="native: generated C code (finite specs with state invariants only); python: the step "
                        "function itself; auto (default): native when the spec allows it")
    p.add_argument("--fair", action="append", default=[], metavar="DOMAIN|all",
                   help="weak fairness for LTL/CTL: every agent of DOMAIN (or every choice, 'all') that is "
                        "continuously enabled eventually moves")
    _add_domain_options(p)
    from .parallel.cli import add_explore_options as add_scaling_options
    add_scaling_options(p)


def register(sub) -> None:
    p = sub.add_parser(
        "explore", help="explore every reachable state and check properties",
        description="Explore every reachable state of FILE breadth-first (all choose branches, all monitored "
                    "inputs, all interleavings), check its invariants and the properties that apply, and print the "
                    "shortest counterexample of each violated property.",
        epilog="Exit codes: 0 every property holds over the whole state space; 1 a property is violated; "
               "2 usage, syntax or type error; 3 incomplete (a limit stopped the search first).")
    p.add_argument("file", metavar="FILE")
    add_explore_options(p)
    p.add_argument("--graph", metavar="OUT.dot|OUT.graphml", help="write the state graph")
    p.add_argument("--avalla", metavar="OUT.avalla|DIR",
                   help="write each counterexample as an Avalla scenario that replays it")
    p.add_argument("--html", metavar="OUT.html", help="write a self-contained HTML report")
    p.add_argument("--format", choices=["text", "json"], default="text")
    p.set_defaults(func=cmd_explore)

    # subcommands that live in their own modules
    from . import commands_bmc, commands_check, commands_scenario
    commands_scenario.register(sub)
    commands_bmc.register(sub)
    commands_check.register(sub)
