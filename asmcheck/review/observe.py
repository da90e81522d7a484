"""What the explored configurations showed, gathered once for advise, coverage and testgen."""
from __future__ import annotations

from collections import defaultdict

from ..semantics import ir
from ..semantics.state import is_dom_key, same_value


def vkey(v):
    try:
        hash(v)
        return (type(v) is bool, v)
    except TypeError:
        return ("repr", repr(v))


class Observations:
    """Counts over every configuration (observer of :class:`~asmcheck.review.space.Space`) and
    over every reachable state (its ``on_state``)."""

    def __init__(self, keep_first: bool = True):
        self.configs = 0
        self.error_configs = 0
        self.node_configs: dict = defaultdict(int)     # id(node) -> configurations activating it
        self.nodes: dict = {}                          # id(node) -> node
        self.first: dict = {}                          # target -> (state id, picks, successor id)
        self.first_failing: dict = {}                  # the same, through a failing step
        self.outcomes: dict = defaultdict(set)         # id(node) -> outcomes seen (if/switch/choose)
        self.forall_cfg: dict = defaultdict(int)       # id(forall) -> configurations with a non-empty activation
        self.inst_fired: dict = {}                     # update instance -> (node, key)
        self.inst_nontrivial: set = set()
        self.written: set = set()                      # location keys some update activation wrote
        self.clash_pairs: dict = defaultdict(set)      # key -> {frozenset of two instances}
        self.clash_example: dict = {}                  # key -> (event, event)
        self.states = 0
        self.values: dict = defaultdict(set)           # key -> value keys in reachable states
        self.present: dict = defaultdict(int)          # key -> states where defined
        self.keep_first = keep_first
        self.errors: list = []                          # (state id, message) of the failing steps (first few)

    # ------------------------------------------------------------------ states
    def on_state(self, sid, st: dict) -> None:
        self.states += 1
        for k, v in st.items():
            if is_dom_key(k) or v is None:
                continue
            self.values[k].add(vkey(v))
            self.present[k] += 1

    def values_of(self, key) -> set:
        """The values (vkey) of ``key`` over the reachable states, ``(False, None)`` for undef."""
        out = set(self.values.get(key, ()))
        if self.present.get(key, 0) < self.states:
            out.add((False, None))
        return out

    # ------------------------------------------------------------------ configurations
    def __call__(self, c) -> None:
        self.configs += 1
        if c.error is not None:
            self.error_configs += 1
            if len(self.errors) < 20:
                self.errors.append((c.state, c.error))
        seen = set()
        # targets are first covered by steps that succeed (a test can replay them); a failing
        # step's activations still count for the checks
        first = self.first if c.error is None else self.first_failing
        fa_nonempty = set()
        for ev in c.events:
            node = ev.node
            nid = id(node)
            if nid not in seen:
                seen.add(nid)
                self.node_configs[nid] += 1
                self.nodes[nid] = node
                if ("rule", nid) not in first:
                    first[("rule", nid)] = (c.state, c.picks, c.target)
            out = ev.outcome
            t = type(node)
            if t is ir.Update:
                if ev.key is not None:
                    inst = (nid, ev.key, ev.binding)
                    self.inst_fired[inst] = (node, ev.key)
                    if not same_value(ev.before, ev.value):
                        self.inst_nontrivial.add(inst)
                    self.written.add(ev.key)
                    if ("update", nid) not in first:
                        first[("update", nid)] = (c.state, c.picks, c.target)
            elif t is ir.Forall:
                if out:
                    fa_nonempty.add(nid)
            elif out is not None:
                if ev.vector is not None:
                    vk = ("vector", nid, ev.vector, out)
                    if vk not in first:
                        first[vk] = (c.state, c.picks, c.target)
                self.outcomes[nid].add(out)
                if ("branch", nid, out) not in first:
                    first[("branch", nid, out)] = (c.state, c.picks, c.target)
        for nid in fa_nonempty:
            self.forall_cfg[nid] += 1
        for cl in c.clashes:
            a, b = cl.first, cl.second
            ia = (id(a.node), a.key, a.binding)
            ib = (id(b.node), b.key, b.binding)
            self.clash_pairs[cl.key].add(frozenset((ia, ib)))
            if cl.key not in self.clash_example:
                self.clash_example[cl.key] = (a.node, a.value, b.node, b.value)
