"""Partitions as Ray actors (``explore --cluster ADDRESS|auto|local``).

One actor per partition holds that partition's share of the seen states and its frontier.  A
level's successors travel as one batch per (sender, owner) pair, as Ray objects that go from the
sending actor to the owning actor without passing through the driver.  Each actor rebuilds the
machine from a :class:`asmcheck.parallel.Recipe` (the spec's path and options), so every node
of the cluster needs asmcheck installed and the spec (and its imports) at the same path.

Ray is an optional extra: ``pip install 'asmcheck[cluster]'``.
"""
from __future__ import annotations

import contextlib
import os
import pathlib
import sys
import tempfile

from ..errors import UsageError
from .partition import Partition
from .search import WorkerLost

NO_RAY = ("--cluster needs Ray, an optional extra: pip install 'asmcheck[cluster]' "
          "(or pip install 'ray[default]>=2')")

# the local instance's object store holds one level's batches: a fifth of the memory available,
# from 96 MB to 1 GB (a level's batches beyond it are spilled to disk, which is slow)
# the memory share of a Ray actor: the default bound of its node divided among the actors there
PER_NODE = "per-node"


def local_object_store() -> int:
    avail = 0
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    avail = int(line.split()[1]) * 1024
    except OSError:  # pragma: no cover - not Linux
        pass
    return max(96 << 20, min(1 << 30, avail // 5))


def import_ray():
    try:
        import ray
    except ImportError:
        raise UsageError(NO_RAY) from None
    return ray


class _Owner:
    """The body of the partition actor."""

    def __init__(self, wid, n, recipe, memory_share, keep_graph):
        from .native_expand import Refused
        self.refused = None
        try:
            # the native expander compiles the spec's step function here, or loads it from
            # this node's cache
            self.p = Partition(wid, n, recipe(), memory_share, keep_graph)
        except Refused as e:
            self.p = None
            self.refused = str(e)

    def node(self):
        """(this actor's node, the default memory bound of a process there)."""
        import ray
        from ..explore.store import default_max_memory
        return ray.get_runtime_context().get_node_id(), default_max_memory()

    def set_memory_share(self, share):
        if self.p is not None:
            self.p.memory_share = share

    def call(self, method, *args):
        if self.p is None:
            from .native_expand import Refused
            raise Refused(self.refused)
        return getattr(self.p, method)(*args)

    def expand_level(self, *args):
        report, batches = self.p.expand_level(*args)
        return (report, *batches) if len(batches) > 0 else report

    def receive(self, *batches):
        return self.p.receive(list(batches))


# Ray's native code announces on the process's stderr that a local instance uses token
# authentication; asmcheck starts that instance itself, so the line says nothing to its user
RAY_NOTICES = ("Token authentication is enabled for this Ray cluster",)


@contextlib.contextmanager
def _ray_notices_filtered():
    """File descriptor 2 goes to a file while Ray starts; its lines but Ray's notices are then
    written to stderr."""
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):     # no real stderr (an embedding, a test's capture)
        yield
        return
    with tempfile.TemporaryFile(mode="w+b") as tmp:
        os.dup2(tmp.fileno(), 2)
        try:
            yield
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            tmp.seek(0)
            text = tmp.read().decode("utf-8", "replace")
            kept = [ln for ln in text.splitlines(keepends=True) if not ln.startswith(RAY_NOTICES)]
            if kept:
                sys.stderr.write("".join(kept))
                sys.stderr.flush()


def connect(cluster: str, workers: int):
    """Join (or start) the Ray instance named by ``cluster``: 'local' starts one on this machine
    (as many CPUs as workers, a small object store), 'auto' joins the running cluster found by
    Ray, anything else is a cluster address.  Returns (ray, whether we started it)."""
    ray = import_ray()
    if ray.is_initialized():
        return ray, False
    here = str(pathlib.Path(__file__).resolve().parents[2])
    env = {"env_vars": {"PYTHONPATH": os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH")) if p)}}
    try:
        with _ray_notices_filtered():
            _init(ray, cluster, workers, env)
    except (ConnectionError, RuntimeError, ValueError) as e:
        raise UsageError(f"--cluster {cluster}: cannot connect to Ray ({e})") from None
    return ray, True


def _init(ray, cluster: str, workers: int, env: dict) -> None:
    if cluster == "local":
        ray.init(num_cpus=max(1, min(workers, os.cpu_count() or 1)), object_store_memory=local_object_store(),
                 include_dashboard=False, log_to_driver=False, runtime_env=env,
                 configure_logging=False)
    else:
        ray.init(address=cluster, log_to_driver=False, runtime_env=env, configure_logging=False)


class RayBackend:
    name = "ray"

    def __init__(self, recipe, n: int, cluster: str = "local", memory_share=None, keep_graph=False):
        ray, self.started = connect(cluster, n)
        self.ray = ray
        self.n = n
        from ray.exceptions import RayError
        self.RayError = RayError
        Actor = ray.remote(num_cpus=0, max_restarts=0)(_Owner)
        first = None if memory_share == PER_NODE else memory_share
        self.actors = [Actor.options(scheduling_strategy="SPREAD", name=None).remote(
            w, n, recipe, first, keep_graph) for w in range(n)]
        try:
            self.pids = self._get([a.call.remote("ping") for a in self.actors])
            if memory_share == PER_NODE:
                self.shares = self.node_shares()
                self._get([a.set_memory_share.remote(s) for a, s in zip(self.actors, self.shares)])
        except BaseException:
            # (an actor that cannot build its expander: the actors and the instance we started go)
            self.close()
            raise

    def node_shares(self) -> list:
        """Each actor's memory share: the default bound of its node divided among the actors
        placed on that node (the actors of one machine share its memory)."""
        nodes = self._get([a.node.remote() for a in self.actors])
        per = {}
        for node, _ in nodes:
            per[node] = per.get(node, 0) + 1
        return [None if bound is None else bound // per[node] for node, bound in nodes]

    def _get(self, refs):
        try:
            return self.ray.get(refs)
        except self.RayError as e:
            from .native_expand import Refused
            cause = getattr(e, "cause", None)
            if isinstance(cause, Refused):
                raise Refused(str(cause)) from None
            text = str(e).splitlines()[0] if str(e) else type(e).__name__
            dead = type(e).__name__
            raise WorkerLost(f"a partition actor failed during the search ({dead}: {text}); "
                             f"the search has no verdict") from None

    def call_all(self, method: str, args_list):
        if method == "expand_level":
            n = self.n
            refs = [a.expand_level.options(num_returns=n + 1).remote(*args)
                    for a, args in zip(self.actors, args_list)]
            reports = self._get([r[0] for r in refs])
            # the batches stay in the object store: receive() takes them from there
            return [(rep, r[1:]) for rep, r in zip(reports, refs)]
        return self._get([a.call.remote(method, *args) for a, args in zip(self.actors, args_list)])

    def call(self, w: int, method: str, *args):
        return self._get(self.actors[w].call.remote(method, *args))

    def route(self, batches_by_src):
        return self._get([a.receive.remote(*[b[w] for b in batches_by_src]) for w, a in enumerate(self.actors)])

    def close(self):
        for a in getattr(self, "actors", []):
            try:
                self.ray.kill(a)
            except Exception:
                pass
        self.actors = []
        if getattr(self, "started", False):
            self.ray.shutdown()
            self.started = False
