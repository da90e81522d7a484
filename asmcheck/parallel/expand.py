"""The one interface the partitioned search needs from a step function.

A search engine plugs into :mod:`asmcheck.parallel.search` by offering an *expander*: given a
state's key it gives the state's successor keys, each with the choices that led there, and the
property checks of that state and its steps.  Keys travel between processes and machines, so a
key must be picklable, compare equal in every process for equal states, and have a
:meth:`owner_hash` that is the same in every process.

:class:`PythonExpander` is the expander over the Python step function (the reference
semantics): a key is the tuple of a canonical state's items.  A native engine plugs in with
packed states as keys (see docs/scaling.md, "What a faster engine must expose").
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import AsmError
from ..explore.bfs import error_edge, too_many_reason
from ..semantics.choice import TooManySuccessors
from .stable import StateHasher

# kinds of property check results, in the order the sequential search meets them per state
K_STATE, K_ERROR, K_STEP, K_DEADLOCK = 0, 1, 2, 3


@dataclass
class Expansion:
    """What expanding one state gives."""
    state_failures: list = field(default_factory=list)   # [(state property index, message, error)]
    error: tuple | None = None                           # (message, error) when no step can be computed
    failed: list = field(default_factory=list)            # [error] of each branch whose step fails, in order
    too_many: str | None = None                           # why the successors were not all enumerated
    succ: list = field(default_factory=list)              # [(key, picks)] in enumeration order
    step_failures: list = field(default_factory=list)    # [(successor index, step property index, message, error)]
    distinct: int = 0                                     # distinct successor states
    deadlock: str | None = None                           # the deadlock message, when --deadlock finds one


class PythonExpander:
    """Successors by the Python step function, canonicalised as the sequential explorer does,
    with the same INVAR filter and the same property checks."""

    def __init__(self, machine, state_props=(), step_props=(), deadlock=False):
        from ..explore.bfs import Explorer
        # the sequential explorer's helpers: canonicaliser, INVAR filter, layout
        self.ex = Explorer(machine, state_props=state_props, step_props=step_props, deadlock=deadlock)
        self.m = machine
        self.state_props = list(state_props)
        self.step_props = list(step_props)
        self.deadlock = deadlock
        self.hasher = StateHasher()

    # ------------------------------------------------------------------ keys
    def owner_hash(self, key) -> int:
        return self.hasher(key)

    def freeze(self, key):
        """A compact local form of the key (for the seen set of this process)."""
        return self.ex.layout.freeze(dict(key))

    def thaw(self, frozen) -> tuple:
        return tuple(self.ex.layout.thaw(frozen).items())

    @staticmethod
    def state_of(key) -> dict:
        return dict(key)

    # ------------------------------------------------------------------ steps
    def initial(self) -> list:
        """The initial states [(key, picks)], in the sequential explorer's order (duplicates kept)."""
        out = []
        for log, st in self.m.initial_states():
            if not self.ex._invar_ok(st):
                continue
            out.append((tuple(self.ex._norm(st).items()), tuple(c.pick for c in log)))
        return out

    def check_state(self, st: dict, skip=frozenset()) -> list:
        out = []
        m = self.m
        for i, prop in enumerate(self.state_props):
            if prop.name in skip:
                continue
            try:
                ok = prop.check_state(m, st)
            except AsmError as e:
                out.append((i, f"cannot be evaluated: {e.message}", e))
                continue
            if not ok:
                out.append((i, "", None))
        return out

    def expand(self, key, skip=frozenset(), successors=True) -> Expansion:
        """Check the state ``key`` and (when ``successors``) compute its successors.  Properties
        named in ``skip`` are already violated and need not be checked again."""
        ex = self.ex
        m = self.m
        st = dict(key)
        res = Expansion(self.check_state(st, skip))
        if not successors:
            return res
        # the well-defined successors; each branch whose step fails is an error, kept in the
        # order the sequential search meets it (that search goes on past it, and so does this one)
        failed: list = []
        try:
            succ = ex.admitted_successors(st, failed)
        except TooManySuccessors as e:
            # a limit, not a property of the spec: the search stops at this state
            res.too_many = too_many_reason(m, e)
            return res
        except AsmError as e:
            res.error = (e.message, e)
            return res
        for e in failed:
            error_edge(0, e)            # (drops the frames of the step the error holds)
        res.failed = failed
        layout = ex.layout
        me = layout.freeze(st)
        targets = set()
        step_props = [(i, p) for i, p in enumerate(self.step_props) if p.name not in skip]
        out = res.succ
        for picks, ups, raw, nxt, mon in succ:
            j = len(out)
            out.append((tuple(nxt.items()), picks))
            targets.add(layout.freeze(nxt))
            for i, prop in step_props:
                try:
                    ok = prop.check_step(m, st, ups, raw, mon)
                except AsmError as e:
                    res.step_failures.append((j, i, f"cannot be evaluated: {e.message}", e))
                    continue
                if not ok:
                    res.step_failures.append((j, i, "", None))
        res.distinct = len(targets)
        # a state where a step fails is not a deadlock: the error is reported
        if self.deadlock and not failed and all(t == me for t in targets):
            res.deadlock = "no successor" if not targets else "the only successor is the state itself"
        return res
