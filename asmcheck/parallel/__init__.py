"""Search beyond one core: partitioned breadth-first search on worker processes or a Ray
cluster, swarm simulation and bitstate search.

:func:`explore_partitioned` is the entry point of the partitioned search: it gives the same
states, numbers, counts, verdicts and shortest traces as the sequential explorer
(:class:`asmcheck.explore.bfs.Explorer`), whatever the number of workers.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field

from .search import InlineBackend, PartitionedSearch, WorkerLost  # noqa: F401


def cpu_count() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def parse_workers(text) -> int:
    """``--workers N`` or ``auto`` (every core this process may use)."""
    from ..errors import UsageError
    if text is None:
        return 1
    if isinstance(text, int):
        n = text
    elif str(text).strip().lower() == "auto":
        return cpu_count()
    else:
        try:
            n = int(str(text).strip())
        except ValueError:
            raise UsageError(f"--workers expects a number or 'auto', not {text!r}") from None
    if n < 1 or n > 255:
        raise UsageError(f"--workers expects 1 to 255 workers, not {n}")
    return n


@dataclass
class Recipe:
    """How to rebuild the machine and its properties in another process (a Ray actor): the spec's
    path, the machine options, the property files and the import path."""
    path: str
    options: dict = field(default_factory=dict)
    prop_files: list | None = None
    use_default: bool = True
    import_path: list = field(default_factory=list)
    deadlock: bool = False
    state_names: list | None = None     # the properties checked (None: all that apply), in order
    step_names: list | None = None
    expander: str = "python"            # 'native': the compiled step function (NativeExpander)
    cn_k: int | None = None             # its element slots per extended domain (None: the default)

    def load(self):
        return self.load_all()[:3]

    def load_all(self):
        """(machine, state properties, step properties, temporal properties and fairness)."""
        from ..props import spec_properties
        from ..props.files import properties_for
        from ..props.load import load_machine
        from ..semantics.resolve import set_import_path
        if self.import_path:
            set_import_path(self.import_path)
        spec, machine = load_machine(self.path, self.options)
        state_props, step_props = spec_properties(machine)
        extra_state, extra_step, temporal = properties_for(spec, machine, self.path, self.prop_files,
                                                           use_default=self.use_default)
        state_props += extra_state
        step_props += extra_step
        if self.state_names is not None:
            state_props = [p for p in state_props if p.name in self.state_names]
        if self.step_names is not None:
            step_props = [p for p in step_props if p.name in self.step_names]
        return machine, state_props, step_props, temporal

    def __call__(self):
        machine, state_props, step_props = self.load()
        return make_expander(self.expander, machine, state_props, step_props, self.deadlock, self.cn_k)


def make_expander(kind: str, machine, state_props, step_props, deadlock, cn_k=None):
    """An expander of the kind named: 'python' (the Python step function) or 'native' (the
    compiled one; raises :class:`asmcheck.parallel.native_expand.Refused` where it cannot)."""
    if kind == "native":
        from .native_expand import NativeExpander
        return NativeExpander(machine, state_props, step_props, deadlock, cn_k)
    from .expand import PythonExpander
    return PythonExpander(machine, state_props, step_props, deadlock)


def explore_partitioned(machine, *, workers: int = 2, backend: str = "processes", state_props=(),
                        step_props=(), deadlock=False, max_states=None, max_depth=None, max_seconds=None,
                        keep_graph=False, progress=None, memory_share=None, recipe: Recipe | None = None,
                        cluster: str | None = None, make_expander=None, on_level=None, expander: str = "python"):
    """Explore ``machine`` with the states partitioned among ``workers`` partitions.

    ``backend``: 'inline' (partitions in this process: simulated workers), 'processes' (forked
    worker processes) or 'ray' (one Ray actor per partition on the cluster ``cluster``; needs
    ``recipe``).  ``memory_share``: bytes of resident memory each worker may use; a worker over
    it ends the run with a partial report (verdict incomplete).  ``expander``: 'python' (the
    Python step function), 'native' (the compiled step function of the native engine) or 'auto'
    (native where the native engine takes the spec; the search runs again on the Python step
    function when it refuses the spec, before or during the search).  Returns (explorer, result);
    the explorer answers traces and reports like the sequential one; ``result.engine`` names the
    step function that expanded the states and ``result.native_refused`` why it is not the
    native one ('' when it is, or was not asked for)."""
    if expander not in ("python", "native", "auto"):
        raise ValueError(f"unknown expander {expander!r}")
    if backend == "ray":
        # one connection for every attempt (again with more element slots, on the Python step
        # function): a Ray instance this search starts is started once, its actors serve each attempt
        from .cluster import session
        with session(cluster or "local", workers):
            return _explore_attempts(machine, workers, backend, state_props, step_props, deadlock, max_states,
                                     max_depth, max_seconds, keep_graph, progress, memory_share, recipe, cluster,
                                     make_expander, on_level, expander)
    return _explore_attempts(machine, workers, backend, state_props, step_props, deadlock, max_states, max_depth,
                             max_seconds, keep_graph, progress, memory_share, recipe, cluster, make_expander,
                             on_level, expander)


def _explore_attempts(machine, workers, backend, state_props, step_props, deadlock, max_states, max_depth,
                      max_seconds, keep_graph, progress, memory_share, recipe, cluster, make_expander, on_level,
                      expander):
    args = (machine, workers, backend, state_props, step_props, deadlock, max_states, max_depth, max_seconds,
            keep_graph, progress, memory_share, recipe, cluster)
    if expander == "python" or make_expander is not None:
        return _explore_partitioned(*args, make_expander, on_level, "python")
    from ..explore.native import CN_K_MAX
    from .native_expand import MoreSlots, Refused
    cn_k = None
    while True:
        try:
            return _explore_partitioned(*args, None, on_level, "native", cn_k)
        except MoreSlots as e:
            # as the native search does: again, on code with twice the element slots
            if e.cn_k * 2 <= CN_K_MAX:
                cn_k = e.cn_k * 2
                continue
            if expander == "native":
                raise
            reason = str(e)
        except Refused as e:
            if expander == "native":
                raise
            reason = str(e)
        break
    ex, result = _explore_partitioned(*args, None, on_level, "python")
    result.native_refused = reason
    return ex, result


def _explore_partitioned(machine, workers, backend, state_props, step_props, deadlock, max_states, max_depth,
                         max_seconds, keep_graph, progress, memory_share, recipe, cluster, make_expander_,
                         on_level, kind, cn_k=None):
    from dataclasses import replace

    from .native_expand import Refused
    from .view import PartitionedExplorer

    state_props = list(state_props)
    step_props = list(step_props)
    # the coordinator's own expander (initial states, owners of keys): of the workers' kind
    local = make_expander(kind, machine, state_props, step_props, deadlock, cn_k)
    if make_expander_ is None:
        # (forked workers inherit the loaded native library; each builds its own expander on it)
        def make_expander_():
            return make_expander(kind, machine, state_props, step_props, deadlock, cn_k)
    if backend == "inline":
        b = InlineBackend(make_expander_, workers, memory_share, keep_graph)
    elif backend == "processes":
        from .procs import ProcessBackend
        b = ProcessBackend(make_expander_, workers, memory_share, keep_graph)
    elif backend == "ray":
        from .cluster import RayBackend
        if recipe is None:
            raise ValueError("a Ray search needs a Recipe to rebuild the machine in its actors")
        b = RayBackend(replace(recipe, expander=kind, cn_k=cn_k), workers, cluster or "local", memory_share, keep_graph)
    else:
        raise ValueError(f"unknown backend {backend!r}")
    ended_well = False
    try:
        search = PartitionedSearch(b, local, state_props=state_props, step_props=step_props, deadlock=deadlock,
                                   max_states=max_states, max_depth=max_depth, max_seconds=max_seconds,
                                   keep_graph=keep_graph, progress=progress, on_level=on_level)
        result = search.run()
        ex = PartitionedExplorer(machine, search, state_props, step_props, deadlock, keep_graph)
        ex.finish(result)
        if backend != "inline":
            result.worker_cpu = b.call_all("cpu", [()] * workers)
        ended_well = True
    except Refused:
        # (the workers are sound: the search runs again, on other code)
        ended_well = True
        raise
    finally:
        # (the actors of a search that ended well may serve the next one: see .cluster)
        b.close(reuse=ended_well)
    result.engine = "native" if kind == "native" else "python"
    result.native_refused = ""
    result.workers = workers
    result.backend = b.name
    result.peak_rss = list(search.peak_rss) if "search" in locals() else []
    return ex, result
