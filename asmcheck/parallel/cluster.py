"""Partitions as Ray actors (``explore --cluster ADDRESS|auto|local``).

One actor per partition holds that partition's share of the seen states and its frontier.  A
level's successors travel as one batch per (sender, owner) pair, as Ray objects that go from the
sending actor to the owning actor without passing through the driver.  Each actor rebuilds the
machine from a :class:`asmcheck.parallel.Recipe` (the spec's path and options), so every node
of the cluster needs asmcheck installed and the spec (and its imports) at the same path.

An actor serves one search at a time and may serve the next: when asmcheck joined a Ray instance
it did not start (``ray.init`` called before, as a test or a notebook does), the actors of a
search that ended well wait in a pool for the next search of this process on that instance
(:class:`ActorPool`), which then pays no actor start-up (a process started, Ray and asmcheck
imported: seconds on a small machine).  A pooled actor is taken again only as a new one would
be: its partition dropped, the import path as a new process has it, and its resident memory
back within :data:`REUSE_SLACK` of what it was when it first began a search (else it is
killed).  An instance a search starts (``--cluster local``) serves all its attempts (again with
more element slots, on the Python step function: :func:`session`), their actors pooled, and is
shut down with them at the end of the search.  Idle pooled actors hold their processes' memory
(no CPU: an actor asks for none) until the instance is left or this process exits.

Ray is an optional extra: ``pip install 'asmcheck[cluster]'``.
"""
from __future__ import annotations

import atexit
import contextlib
import os
import pathlib
import socket
import sys
import tempfile
import threading

from ..errors import UsageError
from .native_expand import Refused
from .partition import Partition, rss_bytes
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


# a pooled actor is taken again only if its resident memory is back within this many bytes of
# what it was when it first began a search (the memory share bounds the whole process)
REUSE_SLACK = 32 << 20


class _Owner:
    """The body of the partition actor: :meth:`setup` gives it a search's partition, :meth:`reset`
    drops it (the actor may then serve another search)."""

    def __init__(self):
        self.p = None
        self.base_rss = None

    def setup(self, wid, n, recipe, memory_share, keep_graph):
        """Build the partition ``wid`` of ``n`` (raises Refused when the native expander cannot
        take the spec); returns this process's id."""
        import time
        from ..semantics.resolve import set_import_path
        self.p = None
        cpu0 = time.process_time()
        if self.base_rss is None:
            self.base_rss = rss_bytes()
        # as a new process has it: the recipe sets its own import path, if any
        set_import_path([])
        # the native expander compiles the spec's step function here, or loads it from this
        # node's cache
        self.p = Partition(wid, n, recipe(), memory_share, keep_graph)
        self.p.cpu0 = cpu0
        return os.getpid()

    def reset(self) -> int:
        """Drop the partition; returns how much more resident memory this process holds than when
        it first began a search."""
        import gc
        from ..explore.native_build import trim_heap
        self.p = None
        gc.collect()
        trim_heap()
        return rss_bytes() - (self.base_rss or 0)

    def node(self):
        """(this actor's node, the default memory bound of a process there)."""
        import ray
        from ..explore.store import default_max_memory
        return ray.get_runtime_context().get_node_id(), default_max_memory()

    def set_memory_share(self, share):
        if self.p is not None:
            self.p.memory_share = share

    def call(self, method, *args):
        return getattr(self.p, method)(*args)

    def expand_level(self, *args):
        report, batches = self.p.expand_level(*args)
        return (report, *batches) if len(batches) > 0 else report

    def receive(self, *batches):
        return self.p.receive(list(batches))


class ActorPool:
    """The idle partition actors of this process on the Ray instance it joined (keyed by the
    instance's node and this process's job: a pool outlives neither), each with the reference of
    its :meth:`_Owner.reset` (asked for when its search ended, read when it is taken); killed at
    exit."""

    def __init__(self):
        self.key = None
        self.idle: list = []
        self.lock = threading.Lock()        # (searches of several threads take and give)

    def take(self, key, n: int) -> list:
        """Up to ``n`` idle actors [(actor, reset reference)] of the instance ``key``."""
        with self.lock:
            if key != self.key:
                self.key, self.idle = key, []
            got, self.idle = self.idle[:n], self.idle[n:]
            return got

    def give(self, key, actors) -> None:
        with self.lock:
            if key == self.key:
                self.idle.extend(actors)
                actors = []
        # (an instance left meanwhile: these go)
        _kill([a for a, _ in actors])

    def close(self) -> None:
        with self.lock:
            idle, self.idle, self.key = self.idle, [], None
        _kill([a for a, _ in idle])


def _kill(actors) -> None:
    ray = sys.modules.get("ray")
    if ray is None:
        return
    for a in actors:
        try:
            ray.kill(a)
        except Exception:
            pass


POOL = ActorPool()
atexit.register(POOL.close)


# Ray's native code announces on the process's stderr that a local instance uses token
# authentication; asmcheck starts that instance itself, so the line says nothing to its user
RAY_NOTICES = ("Token authentication is enabled for this Ray cluster",)


@contextlib.contextmanager
def _ray_output_to_stderr():
    """While Ray starts or stops: what it writes on stdout or stderr (file descriptors 1 and 2, and
    Python's sys.stdout: a start-up banner, a usage-stats notice, its native code's log lines) goes
    to a file, whose lines but Ray's notices are then written to stderr.  stdout carries the report
    alone (--format json, junit, sarif); the workers' output stays with Ray (``log_to_driver=False``)."""
    saved = {}
    for fd, stream in ((1, sys.stdout), (2, sys.stderr)):
        try:
            stream.flush()
        except (OSError, ValueError):     # (a stdout closed by its reader)
            pass
        try:
            saved[fd] = os.dup(fd)
        except OSError:                   # no such descriptor (an embedding)
            pass
    with tempfile.TemporaryFile(mode="w+b") as tmp, contextlib.redirect_stdout(sys.stderr):
        for fd in saved:
            os.dup2(tmp.fileno(), fd)
        try:
            yield
        finally:
            for stream in (sys.stdout, sys.stderr):
                try:
                    stream.flush()
                except (OSError, ValueError):
                    pass
            for fd, keep in saved.items():
                os.dup2(keep, fd)
                os.close(keep)
            tmp.seek(0)
            text = tmp.read().decode("utf-8", "replace")
            kept = [ln for ln in text.splitlines(keepends=True) if not ln.startswith(RAY_NOTICES)]
            if kept:
                sys.stderr.write("".join(kept))
                sys.stderr.flush()


def shutdown(ray) -> None:
    """Leave the Ray instance (stopping it if this process started it); what Ray writes then goes
    to stderr (:func:`_ray_output_to_stderr`)."""
    with _ray_output_to_stderr():
        ray.shutdown()


def connect(cluster: str, workers: int):
    """Join (or start) the Ray instance named by ``cluster``: 'local' starts one on this machine
    (as many CPUs as workers, a small object store), 'auto' joins the running cluster found by
    Ray, anything else is a cluster address.  Returns (ray, whether we started it)."""
    ray = import_ray()
    if cluster not in ("local", "auto"):
        _address(cluster, f"--cluster {cluster}")
    if ray.is_initialized():
        return ray, False
    if cluster not in ("local", "auto"):
        check_address(cluster)
    elif cluster == "auto":
        # the address Ray joins for 'auto' when the environment names one (another form, such as a
        # dashboard's http:// address, is left to Ray)
        named = os.environ.get("RAY_ADDRESS", "")
        try:
            _address(named, "RAY_ADDRESS")
        except UsageError:
            named = ""
        if named:
            check_address(cluster, named)
    here = str(pathlib.Path(__file__).resolve().parents[2])
    env = {"env_vars": {"PYTHONPATH": os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH")) if p)}}
    try:
        with _ray_output_to_stderr():
            _init(ray, cluster, workers, env)
    except (ConnectionError, RuntimeError, ValueError) as e:
        raise UsageError(f"--cluster {cluster}: cannot connect to Ray ({e})") from None
    return ray, True


@contextlib.contextmanager
def session(cluster: str, workers: int):
    """Connected to the Ray instance named by ``cluster`` (see :func:`connect`) while inside:
    the partition backends made there use this connection and pool their actors; an instance
    this session started (or joined) is left, its pooled actors killed, at the end."""
    ray, started = connect(cluster, workers)
    try:
        yield ray
    finally:
        if started:
            POOL.close()
            shutdown(ray)


#: how long the address of a cluster may take to answer (a TCP connection to its head node)
CONNECT_SECONDS = 10.0


def _address(text: str, what: str) -> tuple[str, int]:
    """(host, port) of a cluster address, HOST:PORT or ray://HOST:PORT; a usage error (of ``what``)
    otherwise."""
    addr = text[len("ray://"):] if text.startswith("ray://") else text
    host, sep, port = addr.rpartition(":")
    host = host.strip("[]")
    if not sep or not host or "/" in host or not port.isdigit() or not 0 < int(port) < 65536:
        raise UsageError(f"{what}: expected local, auto or the address of a Ray head node, HOST:PORT")
    return host, int(port)


def check_address(cluster: str, address: str | None = None) -> None:
    """Refuse at once a cluster address that nothing answers (``address``: the one Ray takes for
    ``cluster``, else ``cluster`` itself): Ray tries again and again for minutes (its GCS client, 20
    times), silently."""
    what = f"--cluster {cluster}" + (f" (RAY_ADDRESS={address})" if address else "")
    host, port = _address(address or cluster, what)
    try:
        socket.create_connection((host, port), timeout=CONNECT_SECONDS).close()
    except OSError as e:
        why = e.strerror or str(e) or type(e).__name__
        raise UsageError(f"{what}: cannot connect to Ray (nothing answers at {host}:{port}: {why})") from None


def _init(ray, cluster: str, workers: int, env: dict) -> None:
    if cluster == "local":
        # (address 'local': a new instance, even where RAY_ADDRESS or a 'ray start' of this machine
        # names one to join)
        ray.init(address="local", num_cpus=max(1, min(workers, os.cpu_count() or 1)),
                 object_store_memory=local_object_store(), include_dashboard=False, log_to_driver=False,
                 runtime_env=env, configure_logging=False)
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
        self.Actor = ray.remote(num_cpus=0, max_restarts=0)(_Owner)
        # (an instance asmcheck started ends with the search: its actors are not kept)
        self.pool_key = None
        if not self.started:
            ctx = ray.get_runtime_context()
            self.pool_key = (ctx.get_node_id(), ctx.get_job_id())
        self.actors = []
        self.last_error = None
        self.reused = self._reusable(POOL.take(self.pool_key, n)) if self.pool_key is not None else []
        try:
            try:
                self._setup(recipe, memory_share, keep_graph)
            except WorkerLost:
                if not self.reused or not isinstance(self.last_error, self.ray.exceptions.RayActorError):
                    raise
                # a pooled actor is gone (its node left the cluster): new actors, once
                self._kill(self.actors)
                self.actors, self.reused = [], []
                self._setup(recipe, memory_share, keep_graph)
        except Refused:
            # (an actor that cannot build its expander: the actors are sound, they may serve the
            # search again on another expander)
            self.close(reuse=True)
            raise
        except BaseException:
            self.close()
            raise

    def _reusable(self, pooled) -> list:
        """The pooled actors whose reset succeeded with their memory back near its first level;
        the others are killed."""
        if not pooled:
            return []
        try:
            grown = self.ray.get([ref for _, ref in pooled], timeout=60)
        except Exception:
            grown = [None] * len(pooled)
        ok = [g is not None and g <= REUSE_SLACK for g in grown]
        self._kill([a for (a, _), k in zip(pooled, ok) if not k])
        return [a for (a, _), k in zip(pooled, ok) if k]

    def _setup(self, recipe, memory_share, keep_graph):
        n = self.n
        self.actors = self.reused + [self.Actor.options(scheduling_strategy="SPREAD", name=None).remote()
                                     for _ in range(n - len(self.reused))]
        first = None if memory_share == PER_NODE else memory_share
        self.pids = self._get([a.setup.remote(w, n, recipe, first, keep_graph) for w, a in enumerate(self.actors)])
        if memory_share == PER_NODE:
            self.shares = self.node_shares()
            self._get([a.set_memory_share.remote(s) for a, s in zip(self.actors, self.shares)])

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
            self.last_error = e
            cause = getattr(e, "cause", None)
            if isinstance(cause, Refused):
                raise Refused(str(cause)) from None
            text = str(e).splitlines()[0] if str(e) else type(e).__name__
            dead = type(e).__name__
            raise WorkerLost(f"a partition actor failed during the search ({dead}: {text}); "
                             f"the search has no verdict") from None

    def level(self, args_list, route: bool):
        """One level in one round trip: every actor's expand_level, and (``route``) each owner's
        receive of its batches, sent at once (Ray runs a receive when the batches it takes
        exist; they go from actor to actor).  When a worker stopped, its partners' receive ran
        for nothing: the search ends there.  Returns (reports, receive()'s results or None)."""
        n = self.n
        refs = [a.expand_level.options(num_returns=n + 1).remote(*args)
                for a, args in zip(self.actors, args_list)]
        if not route:
            return self._get([r[0] for r in refs]), None
        recv = [a.receive.remote(*[refs[src][1 + w] for src in range(n)]) for w, a in enumerate(self.actors)]
        out = self._get([r[0] for r in refs] + recv)
        return out[:n], out[n:]

    def call_all(self, method: str, args_list):
        return self._get([a.call.remote(method, *args) for a, args in zip(self.actors, args_list)])

    def call(self, w: int, method: str, *args):
        return self._get(self.actors[w].call.remote(method, *args))

    def close(self, reuse=False):
        """End the search: with ``reuse`` (it ended well, on an instance asmcheck joined) the
        actors drop their partitions and go to the pool; else they are killed."""
        actors, self.actors = getattr(self, "actors", []), []
        if reuse and actors and getattr(self, "pool_key", None) is not None:
            try:
                POOL.give(self.pool_key, [(a, a.reset.remote()) for a in actors])
                actors = []
            except Exception:
                pass
        self._kill(actors)
        if getattr(self, "started", False):
            shutdown(self.ray)
            self.started = False

    @staticmethod
    def _kill(actors):
        _kill(actors)
