"""The package's shape, read from its imports with ``ast``: imports run one way along the
pipeline, no module imports another's private names, there is no import cycle, and only
the command line uses argparse and rich's console.  Also: no module over about 900 lines
without a docstring that says why."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

pytestmark = pytest.mark.engines("none")

ROOT = Path(__file__).resolve().parents[1]
PKG = ROOT / "asmcheck"

# the pipeline, lowest first: a module may import modules of its own layer or of lower ones
LAYERS = [
    ("base", ["asmcheck.errors", "asmcheck.version", "asmcheck.stdlib", "asmcheck.cache"]),
    ("syntax", ["asmcheck.syntax"]),
    ("semantics", ["asmcheck.semantics"]),
    ("props", ["asmcheck.props"]),
    # runs over the step function: the explorer, simulation, conformance, scenarios
    ("explore", ["asmcheck.explore", "asmcheck.simulate", "asmcheck.conform", "asmcheck.avalla"]),
    ("temporal, smt", ["asmcheck.temporal", "asmcheck.smt"]),
    ("report", ["asmcheck.report"]),
    # the partitioned, cluster, bitstate and swarm searches: over the explorer, with reports
    ("parallel", ["asmcheck.parallel"]),
    ("api", ["asmcheck.api", "asmcheck.options", "asmcheck"]),
    # what is built on the API: the command line and the tools beside it
    ("cli", ["asmcheck.cli", "asmcheck.__main__", "asmcheck.lsp", "asmcheck.review"]),
]


def module_name(path: Path) -> str:
    rel = path.relative_to(ROOT).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in sorted(PKG.rglob("*.py"))}


MODULES = modules()


def layer_of(name: str) -> int:
    best, rank = -1, None
    for i, (_, prefixes) in enumerate(LAYERS):
        for pre in prefixes:
            if (name == pre or name.startswith(pre + ".")) and len(pre) > best:
                best, rank = len(pre), i
    assert rank is not None, f"{name} is in no layer of the pipeline: add it to LAYERS"
    return rank


def resolve(mod: str, is_pkg: bool, node) -> list[tuple[str, list[str]]]:
    """(imported module, names taken from it) for an import statement in ``mod``."""
    if isinstance(node, ast.Import):
        return [(a.name, []) for a in node.names]
    base = mod.split(".") if is_pkg else mod.split(".")[:-1]
    if node.level:
        base = base[: len(base) - (node.level - 1)]
        target = ".".join(base + ([node.module] if node.module else []))
    else:
        target = node.module or ""
    out = []
    names = [a.name for a in node.names]
    # 'from . import x' where x is a module imports that module
    plain = []
    for n in names:
        if f"{target}.{n}" in MODULES:
            out.append((f"{target}.{n}", []))
        else:
            plain.append(n)
    if plain or not names:
        out.append((target, plain))
    return out


def imports() -> dict[str, list[tuple[str, list[str], int]]]:
    """module -> [(imported module, names, line)], every import statement (function-level too)."""
    out = {}
    for name, path in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        found = []
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                for target, names in resolve(name, path.name == "__init__.py", node):
                    found.append((target, names, node.lineno))
        out[name] = found
    return out


IMPORTS = imports()


def internal(target: str) -> str | None:
    """The asmcheck module an import refers to (a package's name stands for its __init__)."""
    if target == "asmcheck" or target.startswith("asmcheck."):
        while target and target not in MODULES:
            target = target.rpartition(".")[0]
        return target or None
    return None


def test_every_module_has_a_layer():
    for name in MODULES:
        layer_of(name)


def test_imports_run_one_way_along_the_pipeline():
    bad = []
    for mod, found in IMPORTS.items():
        for target, _, line in found:
            t = internal(target)
            if t is None or t == mod:
                continue
            if layer_of(t) > layer_of(mod):
                bad.append(f"{MODULES[mod].relative_to(ROOT)}:{line}: {mod} ({LAYERS[layer_of(mod)][0]}) imports "
                           f"{t} ({LAYERS[layer_of(t)][0]})")
    assert not bad, "imports against the pipeline:\n" + "\n".join(bad)


def test_no_private_name_crosses_a_module():
    bad = []
    for mod, found in IMPORTS.items():
        for target, names, line in found:
            t = internal(target)
            if t is None:
                continue
            for n in names:
                if n.startswith("_") and not n.startswith("__"):
                    bad.append(f"{MODULES[mod].relative_to(ROOT)}:{line}: imports {n} from {t}")
            if target.rpartition(".")[2].startswith("_") and not target.endswith("__main__"):
                bad.append(f"{MODULES[mod].relative_to(ROOT)}:{line}: imports the private module {target}")
    assert not bad, "private names imported from another module:\n" + "\n".join(bad)


def cycles() -> list[list[str]]:
    graph = {m: sorted({internal(t) for t, _, _ in found if internal(t) not in (None, m)})
             for m, found in IMPORTS.items()}
    # a package's __init__ importing its own submodules (to re-export them) is not a cycle with
    # them unless they import the package back
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def strong(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            strong(v)
    return out


def test_no_import_cycle():
    found = cycles()
    assert not found, "modules that import each other in a circle:\n" + "\n".join(" <-> ".join(c) for c in found)


def test_only_the_command_line_uses_argparse_and_rich_console():
    bad = []
    for mod, found in IMPORTS.items():
        if mod == "asmcheck.cli" or mod.startswith("asmcheck.cli."):
            continue
        for target, names, line in found:
            if target == "argparse" or target.startswith("rich"):
                bad.append(f"{MODULES[mod].relative_to(ROOT)}:{line}: {mod} imports {target}")
    assert not bad, "\n".join(bad)


def test_the_command_line_uses_the_api_only():
    """cli/ calls the public API (asmcheck.api, asmcheck.errors through it) and nothing below."""
    bad = []
    for mod, found in IMPORTS.items():
        if not (mod == "asmcheck.cli" or mod.startswith("asmcheck.cli.")):
            continue
        for target, _, line in found:
            t = internal(target)
            if t is None or t.startswith("asmcheck.cli") or t in ("asmcheck.api", "asmcheck.version",
                                                                   "asmcheck.errors") or \
                    t.startswith("asmcheck.review"):      # the review tools, beside the API
                continue
            if t == "asmcheck.lsp" and mod == "asmcheck.cli.lsp":
                continue        # `asmcheck lsp` starts the language server, which sits beside the command line
            bad.append(f"{MODULES[mod].relative_to(ROOT)}:{line}: {mod} imports {t}")
    assert not bad, "the command line reaches below the API:\n" + "\n".join(bad)


OUTSIDE = [ROOT / "scripts", ROOT / "benchmarks"]
# a benchmark of one internal unit may reach it: bench_canonical.py times the canonicaliser
# (asmcheck/explore/canonical.py) inside a run of the command line
# and bench_parallel.py times the partitioned search's parts (expanders, owners, levels) one by one
UNIT_BENCHMARKS = {"bench_canonical.py": {"asmcheck.explore"},
                   "bench_parallel.py": {"asmcheck.explore.bfs", "asmcheck.parallel", "asmcheck.parallel.search",
                                         "asmcheck.parallel.expand", "asmcheck.props", "asmcheck.props.files",
                                         "asmcheck.props.load", "asmcheck.semantics.resolve",
                                         # the native engine's threads, timed on one and two threads
                                         "asmcheck.explore.native"},
                   # bench_cluster.py times the partitioned search apart from starting the actors
                   "bench_cluster.py": {"asmcheck.explore.native", "asmcheck.parallel", "asmcheck.semantics.resolve"},
                   # bench_native.py --phases times the phases of one run (search, Kripke structure, LTL)
                   "bench_native.py": {"asmcheck.explore.bfs", "asmcheck.temporal", "asmcheck.temporal.ctl",
                                       "asmcheck.temporal.ltl", "asmcheck.explore"}}


@pytest.mark.parametrize("folder", OUTSIDE, ids=lambda p: p.name)
def test_scripts_and_benchmarks_use_the_api(folder):
    """scripts/ and benchmarks/ import asmcheck's public API (or run its command line)."""
    bad = []
    for path in sorted(folder.glob("*.py")):
        allowed = {"asmcheck", "asmcheck.api", "asmcheck.cli"} | UNIT_BENCHMARKS.get(path.name, set())
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("asmcheck"):
                if node.module not in allowed:
                    bad.append(f"{path.relative_to(ROOT)}:{node.lineno}: imports {node.module}")
            elif isinstance(node, ast.Import):
                for a in node.names:
                    if a.name.startswith("asmcheck") and a.name not in allowed:
                        bad.append(f"{path.relative_to(ROOT)}:{node.lineno}: imports {a.name}")
        # strings run by a child interpreter count too
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and "from asmcheck." in node.value:
                for line in node.value.splitlines():
                    line = line.strip()
                    if line.startswith("from asmcheck.") and line.split()[1] not in allowed:
                        bad.append(f"{path.relative_to(ROOT)}: a child script imports {line.split()[1]}")
    assert not bad, "\n".join(bad)


def test_long_modules_say_why():
    """A module over about 900 lines has a docstring that says why it is one module."""
    bad = []
    for mod, path in MODULES.items():
        text = path.read_text(encoding="utf-8")
        n = text.count("\n")
        if n <= 950:
            continue
        doc = ast.get_docstring(ast.parse(text)) or ""
        if "one module" not in doc and "lines" not in doc:
            bad.append(f"{path.relative_to(ROOT)}: {n} lines, and its docstring does not say why")
    assert not bad, "\n".join(bad)


def test_the_checks_find_what_they_look_for(tmp_path):
    """The readers above see an upward import, a private import and a cycle when there is one."""
    fake = {
        "asmcheck.syntax.a": [("asmcheck.report.gate", ["x"], 1)],
        "asmcheck.report.gate": [("asmcheck.syntax.a", ["_hidden"], 2)],
    }
    ups = [(m, t) for m, f in fake.items() for t, _, _ in f if layer_of(t) > layer_of(m)]
    assert ups == [("asmcheck.syntax.a", "asmcheck.report.gate")]
    priv = [n for f in fake.values() for _, names, _ in f for n in names if n.startswith("_")]
    assert priv == ["_hidden"]
    saved = dict(IMPORTS)
    try:
        IMPORTS.clear()
        IMPORTS.update({"asmcheck.syntax.parser": [("asmcheck.errors", [], 1)],
                        "asmcheck.errors": [("asmcheck.syntax.parser", [], 1)]})
        assert cycles() == [["asmcheck.errors", "asmcheck.syntax.parser"]]
    finally:
        IMPORTS.clear()
        IMPORTS.update(saved)
