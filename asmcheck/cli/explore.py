"""``asmcheck explore``: exhaustive exploration with properties, limits and reports."""
from __future__ import annotations

import json
from pathlib import Path

from .. import api
from .common import (EXIT_ERROR, EXIT_INCOMPLETE, EXIT_OK, EXIT_VIOLATED, Progress, add_explore_options,
                     check_output_folder, check_output_path, color_on, error, explore_options, load_options, out,
                     verdict_rows, writing)


def run(args) -> int:
    check_outputs(args)
    model = api.load(args.file, **load_options(args))
    use_bar = args.format == "text"
    with (Progress() if use_bar else _NoProgress()) as progress:
        run_ = model.explore(graph=bool(args.graph), progress=progress, warn=lambda msg: error(f"asmcheck: {msg}"),
                             symmetry=args.symmetry, **explore_options(args))
    try:
        violations = run_.violations
    except api.ReplayError as e:
        error(f"asmcheck: internal error: a trace does not replay ({e})")
        return EXIT_ERROR
    if run_.temporal_error:
        error(f"asmcheck: {run_.temporal_error}")
        return EXIT_ERROR
    if args.graph:
        with writing("--graph", args.graph):
            warning = run_.write_graph(args.graph)
        if warning:
            error(f"asmcheck: warning: {warning}")
    if args.avalla and run_.traces():
        with writing("--avalla", args.avalla):
            run_.write_avalla(args.avalla)
    if args.html:
        with writing("--html", args.html):
            run_.write_html(args.html)
    code = {"violated": EXIT_VIOLATED, "incomplete": EXIT_INCOMPLETE}.get(run_.verdict, EXIT_OK)
    nothing = run_.checked == 0 and not run_.result.violations and not getattr(run_.result, "deadlock_checked", False)
    if args.format == "itf":
        from ..review.itf import itf_documents
        out(json.dumps(itf_documents(model.machine, violations, args.file), indent=1))
        return code
    if args.format == "json":
        doc = run_.json()
        doc.update(run_.scaling_json())
        if nothing:
            doc["verdict"] = "no property checked"
            doc["property_files"] = model.candidate_property_files()
        if args.coverage:
            doc["coverage"] = _coverage(args, "json")
        out(json.dumps(doc, indent=2))
        return code
    color = color_on()
    r = run_.result
    out(f"{Path(args.file).name}: {r.states:,} states, {r.transitions:,} transitions, "
        f"depth {r.depth}, {r.seconds:.2f} s, {run_.engine} engine"
        + (f", {run_.workers} workers" if run_.workers > 1 else ""))
    if run_.engine_note:
        out(f"  (native engine not used: {run_.engine_note})")
    for line in run_.symmetry_lines():
        out(line)
    verdict_rows([(row["property"], api.verdict_text(row)) for row in run_.rows])
    for lines in run_.violation_text(color):
        out()
        for line in lines:
            out(line)
    for lines in run_.temporal_text(color):
        out()
        for line in lines:
            out(line)
    if nothing:
        files = model.candidate_property_files()
        out("no property checked" + (": the spec declares none and no property file applies to it" if not files
                                     else ""))
        if files:
            out(f"property files that name {model.name} (give them with --properties):")
            for f in files:
                out(f"  {f}")
    if r.reason:
        out(f"incomplete: {r.reason}")
    if run_.symmetry_hint:
        out(run_.symmetry_hint)
    for line in run_.scaling_lines():
        out(line)
    out(f"verdict: {'no property checked' if nothing else r.verdict}")
    if args.coverage:
        out()
        out("\n".join(_coverage(args, "text")))
    return code


def _coverage(args, fmt):
    """``--coverage[=OUT.html]``: rule, branch and update coverage over the explored configurations."""
    from ..review.coverage import explore_coverage_for
    return explore_coverage_for(args, fmt)


class _NoProgress:
    def __enter__(self):
        return None

    def __exit__(self, *exc):
        return False


def add_symmetry_option(p) -> None:
    p.add_argument("--symmetry", action="store_true",
                   help="explore one state per class of states that differ only by a renaming of interchangeable "
                        "elements (the elements of an enum, static abstract or Integer subset domain that no literal "
                        "names, when the spec and its properties only compare them by equality); the counts are then "
                        "counts of "
                        "classes (on the native engine, its threads with --workers, else the Python engine); the "
                        "report says which domains are reduced, or why none is")


def check_outputs(args) -> None:
    """Refuse, before the search, output paths that cannot be written."""
    if args.graph:
        suffix = Path(args.graph).suffix.lower()
        if suffix not in (".dot", ".gv", ".graphml"):
            raise api.UsageError(f"--graph: write a .dot or .graphml file, not {args.graph!r}")
        check_output_path(args.graph, "--graph")
    if args.html:
        check_output_path(args.html, "--html")
    if args.avalla:
        if args.avalla.endswith(".avalla"):
            check_output_path(args.avalla, "--avalla")
        else:
            check_output_folder(args.avalla, "--avalla")
    if getattr(args, "coverage", None) and args.coverage != "-":
        check_output_path(args.coverage, "--coverage")


def register(sub) -> None:
    p = sub.add_parser(
        "explore", help="explore every reachable state and check properties",
        description="Explore every reachable state of FILE breadth-first (all choose branches, all monitored "
                    "inputs, all interleavings), check its invariants and the properties that apply, and print the "
                    "shortest counterexample of each violated property.",
        epilog="Exit codes: 0 every property holds over the whole state space; 1 a property is violated; "
               "2 usage, syntax or type error; 3 incomplete (a limit or Ctrl-C stopped the search first).")
    p.add_argument("file", metavar="FILE")
    add_explore_options(p)
    p.add_argument("--graph", metavar="OUT.dot|OUT.graphml", help="write the state graph")
    p.add_argument("--avalla", metavar="OUT.avalla|DIR",
                   help="write each counterexample as an Avalla scenario that replays it")
    p.add_argument("--html", metavar="OUT.html", help="write a self-contained HTML report")
    p.add_argument("--format", choices=["text", "json", "itf"], default="text",
                   help="itf: the counterexamples as ITF traces (Apalache/Quint's Informal Trace Format)")
    add_symmetry_option(p)
    p.add_argument("--coverage", nargs="?", const="-", metavar="OUT.html",
                   help="also report which rules, branches and updates the state space covers (and write the "
                        "spec's source coloured by coverage to OUT.html)")
    p.set_defaults(func=run)
