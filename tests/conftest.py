import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SHARED = Path(os.environ.get("ASMCHECK_SHARED", ROOT.parent / "shared"))
ASMETA = SHARED / "asmeta"
BENCH = SHARED / "bench"


def need_asmeta():
    if not (ASMETA / "MANIFEST.tsv").exists():
        pytest.skip(f"the ASMETA corpus is not at {ASMETA} (set ASMCHECK_SHARED to the shared folder)")
    return ASMETA


def need_bench():
    if not (BENCH / "gen_swing.py").exists():
        pytest.skip(f"the benchmark twins are not at {BENCH}")
    return BENCH


@pytest.fixture
def asmeta():
    return need_asmeta()


@pytest.fixture
def write_spec(tmp_path):
    """Write a spec named after its asm/module header into tmp_path; return its path."""
    def _write(text: str, name: str | None = None) -> str:
        import re
        if name is None:
            m = re.search(r"\b(?:asm|module)\s+([A-Za-z_][A-Za-z0-9_]*)", text)
            name = m.group(1) if m else "Spec"
        p = tmp_path / f"{name}.asm"
        p.write_text(text, encoding="utf-8")
        return str(p)
    return _write


# ----------------------------------------------------------------- engines
# Every test says which exploration engine it pins, with a marker on the module (pytestmark) or
# the test:
#   engines("python")  the Python engine: ASMCHECK_ENGINE=python makes engine='auto' mean it
#   engines("native")  the native engine (the test names --engine native, or compares the two)
#   engines("both")    engine-neutral: the test runs twice, [auto] (native wherever it can run)
#                      and [python] (ASMCHECK_ENGINE=python)
#   engines("none")    explores nothing (front end, simulator, editors, ...)
ENGINE_KINDS = ("python", "native", "both", "none")


# The native engine's C is compiled with -Og in the tests (set here for the whole run, its workers and
# their child processes, unless ASMCHECK_CFLAGS is set already; ASMCHECK_CFLAGS= runs the suite with the
# compiler's own flags): half the compile time of GCC_FLAGS and as fast a search. The reports do not
# depend on the flags; tests/test_native_build.py builds with the real ones and compares the two.
TEST_CFLAGS = "-Og"


def pytest_configure(config):
    config.addinivalue_line("markers", "engines(kind): the exploration engine a test pins: " + ", ".join(ENGINE_KINDS))
    os.environ.setdefault("ASMCHECK_CFLAGS", TEST_CFLAGS)


def _engine_kind(node):
    m = node.get_closest_marker("engines")
    if m is None:
        return None
    kind = m.args[0] if m.args else None
    if kind not in ENGINE_KINDS:
        raise pytest.UsageError(f"{node.nodeid}: engines({kind!r}): expected one of {', '.join(ENGINE_KINDS)}")
    return kind


def pytest_generate_tests(metafunc):
    if _engine_kind(metafunc.definition) == "both":
        metafunc.parametrize("asmcheck_engine", ["auto", "python"], indirect=True)


def pytest_collection_modifyitems(config, items):
    missing = sorted({item.nodeid.split("::")[0] for item in items if _engine_kind(item) is None})
    if missing:
        raise pytest.UsageError("tests that do not say which engine they pin (add pytestmark = "
                                "pytest.mark.engines(...) ; see tests/conftest.py): " + ", ".join(missing))
    items[:] = longest_modules_first(items)


SLOW_WEIGHT = 20.0      # the seconds a test marked slow counts for, when the modules are ordered
TEST_WEIGHT = 0.3       # and any other test


def longest_modules_first(items: list) -> list:
    """The tests module by module, the modules with the most work first (tests marked slow count
    SLOW_WEIGHT, others TEST_WEIGHT), each module's tests in their order.  The test workers
    (pytest-xdist, --dist worksteal) take the collection in two halves and the one that runs out
    takes the tail of the other's queue: long tests at the front start early instead of being
    the last ones running while the other worker idles, and a module's module-scoped fixtures are
    set up once per worker (its tests stay together)."""
    modules: dict[str, list] = {}
    for item in items:
        modules.setdefault(item.nodeid.split("::")[0], []).append(item)

    def weight(name: str) -> float:
        return sum(SLOW_WEIGHT if it.get_closest_marker("slow") else TEST_WEIGHT for it in modules[name])

    order = sorted(modules, key=lambda name: -weight(name))         # stable: ties keep their order
    return [item for name in order for item in modules[name]]


@pytest.fixture(autouse=True)
def asmcheck_engine(request, monkeypatch):
    """The engine this test runs on (see ENGINE_KINDS): sets ASMCHECK_ENGINE for it and its children."""
    kind = _engine_kind(request.node)
    value = getattr(request, "param", None) or ("python" if kind == "python" else "auto")
    if value == "python":
        monkeypatch.setenv("ASMCHECK_ENGINE", "python")
    else:
        monkeypatch.delenv("ASMCHECK_ENGINE", raising=False)
    return value


# a local Ray instance for the tests of one module (tests/test_cluster*.py), started if none runs
@pytest.fixture(scope="module")
def ray_local():
    try:
        import ray
    except ImportError:
        pytest.skip("Ray is not installed (pip install 'asmcheck[cluster]')")
    started = False
    if not ray.is_initialized():
        # two workers, a small object store: this machine is shared
        ray.init(num_cpus=2, object_store_memory=96 * 1024 * 1024, include_dashboard=False, log_to_driver=False,
                 configure_logging=False, runtime_env={"env_vars": {"PYTHONPATH": str(ROOT)}})
        started = True
    yield ray
    if started:
        ray.shutdown()
