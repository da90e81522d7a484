"""LTL and CTL over the explored state graph (built on the explorer's graph).

:func:`check_temporal` takes a complete exploration (``keep_graph=True``) and the temporal
properties that apply (``ir.Property`` of kind ``ltl`` / ``ctl``, plus ``justice`` and
``compassion`` fairness constraints; ``invariant`` properties are checked as ``AG p``
with NuSMV's reading of monitored functions), and returns one :class:`TemporalResult` per
LTL / CTL / invariant property, in the order given.

* the Kripke structure: :mod:`.kripke` (explored states, or explored transitions with the
  monitored values the atoms read, as AsmetaSMV's NuSMV models have them; the spec's
  ``INVAR`` constraints restrict it);
* CTL: :mod:`.ctl` (fixpoints, fair CTL as NuSMV);
* LTL: :mod:`.ltl` (Büchi product, fair SCC search, lassos);
* fairness: ``JUSTICE p`` (p infinitely often), ``COMPASSION(p, q)`` (p infinitely often
  implies q infinitely often), and ``fair`` = the ``--fair`` domains: weak fairness of
  every agent of the domain (``all``: of every alternative of every choose rule).

A search stopped by a limit leaves a partial state graph: :mod:`.partial` decides the properties
that have the same value whatever the unexplored part holds (:func:`.partial.check_partial`;
its results carry ``decided_on``, the states explored).

Counterexamples (and witnesses of existential CTL properties) are replayed through the
step function; :func:`asmcheck.report.trace.temporal_text` and ``temporal_json`` render them.

Run-time errors.  Where a step fails (an inconsistent update, a value out of its domain) the
explorer keeps the well-defined successors of the state and records each failing branch
(``explorer.error_edges``).  The properties are then checked on the well-defined part of the
state graph, and a failing branch is a transition to a *halt*: a node that holds the state
where the step failed and loops on itself, as the simulator stops there and the run stays in
its last well-defined state (``on_error="halt"``).  A path through the error is still a path, so
``af p`` is violated by a run that fails before ``p``, and ``ef p`` is not satisfied by the
failing step.  Every verdict then holds *relative to the run-time error*
(:attr:`TemporalResult.relative_to`).  ``on_error="drop"`` removes the failing branches instead
(only a state left without any successor halts); docs/run-time-errors.md compares both with
ASMETA's model checker.
"""
from __future__ import annotations

import time
from array import array

from ..errors import AsmError
from .formula import AG, Atoms, Builder, FormulaError, atoms_of, span_text
from .kripke import AtomError, build_kripke

__all__ = ["check_temporal", "TemporalResult"]


class TemporalResult:
    def __init__(self, prop, kind: str, holds: bool, *, message: str = "", nodes=None, loop=None,
                 fairness=(), explorer=None, K=None, seconds: float = 0.0, stats=None, witness=False):
        self.prop = prop
        self.name = prop.name
        self.kind = kind                 # ltl ctl invariant
        self.holds = holds
        self.message = message           # why the property could not be checked ("" when it was)
        self.nodes = nodes or []         # Kripke nodes of the counterexample / witness
        self.loop = loop                 # index in nodes where the cycle starts (lassos)
        self.fairness = list(fairness)
        self.explorer = explorer
        self.K = K
        self.seconds = seconds
        self.stats = stats or {}
        self.witness = witness           # the path shows why the property holds
        # the run-time error the verdict is relative to (an AsmError: the first step found to
        # fail), None when every step of the explored graph is well defined
        self.relative_to = None
        # decided on a partial state space (asmcheck.temporal.partial): the states explored when
        # the search stopped; None for a verdict on the whole state space
        self.decided_on = None
        self._trace = None

    @property
    def verdict(self) -> str:
        if self.message:
            return "error"
        return "holds" if self.holds else "violated"

    # -------------------------------------------------------------- the path, replayed
    def trace(self):
        """(Trace, loop index in the trace or None, inputs_step) or None."""
        if self._trace is None and self.nodes and self.explorer is not None:
            self._trace = _replay(self.explorer, self.K, self.nodes, self.loop, self.prop)
        return self._trace


# ----------------------------------------------------------------- replay
def _replay(explorer, K, nodes, loop, prop=None):
    """Re-run the path of Kripke nodes through the step function; check every state
    against the explored graph.  Returns (Trace, loop index, inputs_step).

    A step of the path shows the monitored values that only the atoms of ``prop`` (and of the
    fairness constraints and INVARs the structure has) read, not the step: the first in the
    enumeration order that give the node's truth values."""
    from ..explore.bfs import ReplayError
    from ..explore.trace import Trace, atom_reads, atom_values, term_ids, trace_steps
    from ..semantics.choice import Choice

    failing = None
    cut = next((i for i, v in enumerate(nodes) if v in K.halt), None)
    if cut is not None:
        # the path ends where a step fails: the run stops there (the halt loops on itself)
        _, _, ix = K.halt[nodes[cut]]
        failing = explorer.error_edges[ix][2]
        nodes, loop = (nodes[:cut] if K.mode == "state" else nodes[:cut + 1]), None
    if K.mode == "state":
        sids = list(nodes)
        steps = [(K.edge_picks[(a, b)], b) for a, b in zip(sids, sids[1:])]
        if loop is not None:
            steps.append((K.edge_picks[(sids[-1], sids[loop])], sids[loop]))
        inputs_step = False
    else:
        # a node's step is taken from the target of the node before it (the first node's from
        # its own source, an initial state)
        sids = [K.sid[nodes[0]]] + [K.tgt[v] for v in nodes[:-1]]
        steps = [(K.picks_from(v, a), K.tgt[v]) for v, a in zip(nodes[:-1], sids)]
        last = nodes[-1]
        # a node is a state with the inputs of its step: a lasso closes with the last
        # node's step; a finite path shows it too when atoms read monitored values
        inputs_step = loop is None and bool(K.mon_atoms) and failing is None
        if loop is not None or inputs_step:
            steps.append((K.picks_from(last, sids[-1]), K.tgt[last]))
    got = explorer.replay_steps(sids[0], steps)
    replayed = [(st, log, ups, raw, mapping) for st, log, ups, _, raw, mapping in got]
    tsteps = trace_steps(replayed)
    tr = Trace(None, tsteps, "temporal")
    sym = getattr(explorer, "sym", None)
    if sym is not None and loop is not None:
        tr.up_to = sym.describe()
    if failing is not None:
        sym = getattr(explorer, "sym", None)
        if sym is not None and tsteps:
            # (symmetry reduction: the branch of the trace's last, concrete state)
            failing = sym.concrete_error(explorer.m, tsteps[-1].state, failing) or failing
        tr.failing = list(getattr(failing, "choices", None) or ())
        tr.message = failing.message
    items = getattr(K, "mon_items", None) if K.mode == "step" else None
    keep = list(range(len(items or ())))
    if items and prop is not None:
        # the atoms of the property's formula, of the INVARs and of the fairness constraints (the
        # structure shares its atoms among the properties checked together)
        ids = term_ids([getattr(prop, "body", None), getattr(prop, "body2", None)] +
                       [p.body for p in explorer.m.spec.properties if p.kind == "invar"])
        fair = {id(lab) for _, lab in K.justice} | {id(x) for _, a, b in K.compassion for x in (a, b)}
        keep = [k for k, a in enumerate(items) if id(a.term) in ids or
                id(K.label.get(K.mon_atoms[k])) in fair]
        items = [items[k] for k in keep]
    if items:
        # a node keeps its atoms' truth values, not the monitored values behind them: the values
        # that only the atoms read (the step does not) are found again, the first that give the
        # node's values, and shown with the step's own; the atoms are then evaluated again from
        # the values shown and must give the node's values
        for i, v in enumerate(nodes):
            full = K.vec[v]
            vec = tuple(full[k] for k in keep)
            if i + 1 < len(got):
                state, mon = got[i][0], got[i + 1][3]
            elif v in K.halt:
                state, mon = got[i][0], getattr(failing, "mon", None) or {}
            else:
                continue
            reads = atom_reads(explorer.m, items, state, mon, vec)
            if reads is None:
                raise ReplayError(f"no monitored values give the atoms' values of the step from state "
                                  f"{sids[i]} in the trace")
            shown, _ = atom_values(explorer.m, items, state, {**(mon or {}), **reads})
            if shown != tuple(bool(x) for x in vec):
                raise ReplayError(f"the atoms evaluated with the values shown in the step from state "
                                  f"{sids[i]} do not give the values of the path")
            if i + 1 < len(got):
                tsteps[i + 1].atom_reads = reads
            elif reads:
                m = explorer.m
                tr.failing += [Choice("monitored", m.location_text(k), 1, 0, x) for k, x in reads.items()]
    return tr, loop, inputs_step


# ----------------------------------------------------------------- the entry point
def _fair_text(p) -> str:
    body = span_text(p.body.span) if p.body is not None else ""
    if p.kind == "compassion":
        q = span_text(p.body2.span) if p.body2 is not None else ""
        return f"COMPASSION({body}, {q})"
    return f"JUSTICE {body}"


def has_existential_top(f) -> bool:
    return f[0] in ("EX", "EU", "EG") or (f[0] == "or" and any(has_existential_top(x) for x in f[1:]))


def label_atoms(machine, props, state) -> list:
    """The (term, env) of the atoms that :func:`check_temporal` will evaluate in the explored
    states (those reading monitored functions in the steps' sources), for ``props`` (the temporal
    properties of a run) and ``state`` (the first initial state): an engine that evaluates
    atoms itself (the native explorer's ``state_labels``) translates them before the search.
    An atom missing here is evaluated in Python, so this list only has to be a good guess."""
    atoms = Atoms(machine)
    builder = Builder(machine, atoms, state)
    for p in props:
        try:
            if p.kind == "justice":
                atoms.add(p.body, {})
            elif p.kind == "compassion":
                atoms.add(p.body, {})
                atoms.add(p.body2, {})
            elif p.kind in ("ltl", "ctl", "invariant"):
                builder.build(p.body, "ltl" if p.kind == "ltl" else "ctl")
        except (FormulaError, AsmError):
            continue
    for p in machine.spec.properties:
        if p.kind == "invar":
            try:
                atoms.add(p.body, {})
            except AsmError:
                continue
    return [(a.term, a.env) for a in atoms.items]


def formulas(machine, props, fair, state):
    """The atoms and formulas of the temporal properties ``props`` (the first explored state
    ``state`` serves the formula builder): (atoms, checks, justice, compassion, fairness texts,
    errors, INVAR atoms, atoms the formulas read)."""
    atoms = Atoms(machine)
    builder = Builder(machine, atoms, state)
    checks = []           # (prop, kind, formula or None, error message)
    justice, compassion = [], []
    fairness_text = []
    errors = []
    for p in props:
        kind = p.kind
        try:
            if kind == "justice":
                justice.append((_fair_text(p), atoms.add(p.body, {})))
                fairness_text.append(_fair_text(p))
            elif kind == "compassion":
                compassion.append((_fair_text(p), atoms.add(p.body, {}), atoms.add(p.body2, {})))
                fairness_text.append(_fair_text(p))
            elif kind in ("ltl", "ctl", "invariant"):
                f = builder.build(p.body, "ltl" if kind == "ltl" else "ctl")
                if kind == "invariant":
                    f = AG(f)
                checks.append((p, kind, f, ""))
        except FormulaError as e:
            if kind in ("justice", "compassion"):
                errors.append(f"{_fair_text(p)}: {e.message}")
            else:
                checks.append((p, kind, None, e.message))
    for d in fair:
        fairness_text.append(f"weak fairness of every {d}" if d != "all" else "weak fairness of every alternative of every choose rule")
    invars = []
    for p in machine.spec.properties:
        if p.kind == "invar":
            invars.append(atoms.add(p.body, {}))
    used = set()
    for _, _, f, _ in checks:
        if f is not None:
            atoms_of(f, used)
    return atoms, checks, justice, compassion, fairness_text, errors, invars, used


def quotient_plan(machine, props, fair=(), graph=False):
    """For an engine that can record, while it searches, the steps the temporal checks' quotient
    is built from (the native explorer's ``step_quotient``): a function of the first initial state
    giving the (term, env) of the atoms that read monitored functions, in the order
    :func:`build_kripke` numbers them (an empty list: none), or None when the checks need the edges
    alone: LTL on the state graph (no atom reads a monitored function), more than 63 such atoms.
    With ``--graph`` or ``--fair`` (whose structure is not merged) the edges are needed too
    (``plan.edges_too``): then the plan is only for atoms that read monitored functions (the
    engine records their values in each step, and runs no step again to find them).  None (no
    function) without LTL/CTL properties."""
    if not any(p.kind in ("ltl", "ctl") for p in props):
        return None
    edges_too = bool(graph or fair)
    # each search of an explorer asks again with the same initial states: the answer of the last
    # question is kept (the states themselves held, so that identity names them)
    last: dict = {}

    def remembered(key, states, compute):
        got = last.get(key)
        if got is not None and len(got[0]) == len(states) and all(a is b for a, b in zip(got[0], states)):
            return got[1]
        out = compute()
        last[key] = (list(states), out)
        return out

    def plan(state):
        return remembered("plan", [state], lambda: _plan(state))

    def _plan(state):
        atoms, checks, justice, compassion, _, errors, invars, used = formulas(machine, props, [], state)
        if errors or not any(f is not None for _, _, f, _ in checks):
            return None
        all_atoms = sorted(set(used) | set(invars) | {a for _, a in justice} |
                           {a for _, p, q in compassion for a in (p, q)})
        mon = [i for i in all_atoms if atoms.items[i].monitored]
        if len(mon) > 63 or (not mon and (edges_too or any(kind == "ltl" and f is not None
                                                           for _, kind, f, _ in checks))):
            return None
        return [(atoms.items[i].term, atoms.items[i].env) for i in mon]
    plan.edges_too = edges_too

    def need(states):
        # the successor lists the CTL check reads (temporal/need.py), ``states`` the initial states:
        # (EdgeNeed or ALL, the atoms)
        return remembered("need", states, lambda: _need(states))

    def _need(states):
        from .need import ALL, edge_need
        atoms, checks, justice, compassion, _, errors, invars, used = formulas(machine, props, [], states[0])
        if errors or edges_too:
            return ALL, atoms
        return edge_need(checks, atoms, justice, compassion, invars, used, machine=machine, initial=states), atoms
    plan.need = need
    return plan


def step_halts(explorer, n_states: int, on_error: str):
    """(which of the ``n_states`` states have a recorded step, a bytearray; the halts: a failing
    branch that becomes a transition to a halt node, as (state, choices, monitored values, index
    of the error edge); the first run-time error, or None).  With ``on_error="drop"`` only a state
    left without any well-defined step halts.  A state that halts counts as one with a step."""
    from . import kernel
    has_succ = getattr(explorer, "has_successor", None)
    has_out = has_succ() if has_succ is not None else None
    if has_out is None:
        has_out = kernel.mark(n_states, explorer.edge_arrays()[0])
    error_edges = list(getattr(explorer, "error_edges", None) or ())
    halts = []
    for ix, (src, picks, e) in enumerate(error_edges):
        if on_error == "halt" or not has_out[src]:
            halts.append((src, picks, getattr(e, "mon", None) or {}, ix))
    for src, _, _, _ in halts:
        has_out[src] = 1
    return has_out, halts, (error_edges[0][2] if error_edges else None)


def _lists_missing(explorer, K, halts=()):
    """When the search recorded only some successor lists (temporal/need.py): the condition of the
    lists the properties decided after the search read when they are not decided so (an ``ag(p)``
    some node breaks, an ``ef(b)`` the edges kept do not show, a whole ``ag``/``ef`` where a step
    fails), or None (nothing more to record).  When something is recorded again, so are the lists
    of every ``ef(b)`` and of every whole ``ag(p)`` broken (the search again leaves nothing to decide
    or explain after it)."""
    from .formula import FALSE, Or
    from .need import ALL, EdgeNeed, later_cond
    need = getattr(explorer, "edge_need", None)
    if not isinstance(need, EdgeNeed) or not need.later:
        return None
    from .ctl import CTL
    ctl = CTL(K)

    def undecided(kind, p) -> bool:
        if kind == "ef":
            return bool(halts) or not ef_shown(explorer, K, ctl, p)
        return ctl.sat(p).find(0) >= 0 and (kind == "ag" or bool(halts))
    if not any(undecided(kind, p) for kind, p in need.later):
        return None
    # (recorded then: the lists of every ef(b), and of every ag(p) and whole ag(p) some node
    # breaks -- those of every undecided property among them)
    more = FALSE
    for kind, p in need.later:
        if kind == "ef" or ctl.sat(p).find(0) >= 0:
            r = later_cond(kind, p)
            if r == ALL:
                return ALL
            more = Or(more, r)
    return Or(need.cond, more)


def _tree_entry(explorer, f):
    """The ``later`` entry ("agt", p) or ("ef", b) of the recorded need that the property ``f`` is,
    or None."""
    from .need import EdgeNeed, whole
    need = getattr(explorer, "edge_need", None)
    if not isinstance(need, EdgeNeed):
        return None
    w = whole(f)
    if w is None or w[0] not in ("agt", "ef") or w not in need.later:
        return None
    return w


def ef_shown(explorer, K, ctl, b) -> bool:
    """Whether the edges the structure keeps show that ``E[true U b]`` holds at every node of the one
    initial state s0 (a structure whose lists outside the need's condition keep their first entry
    only, each node leaving such a state with the same value of b): b holds at s0's node, or every
    successor t of s0 reaches a state that a b node leaves, through edges known to be there -- the
    search tree's (parent -> child) and the entries of the lists kept (at least the first of each).
    The successors of s0 are the targets of its nodes and the states whose parent is s0 (a state
    found first from s0); s0 itself reaches everything.  False: not shown (violated or not)."""
    from . import kernel
    from .graph import b_and, b_not, b_or, members
    bn = b_and(ctl.sat(b), ctl.fair)
    init = K.init
    if not init:
        return False
    if all(bn[v] for v in init):
        return True
    S = explorer.n_states
    par = explorer.parent
    tgt = K.tgt
    s0 = K.sid[init[0]]
    # the states a b node leaves
    reach = _leaving(K, S, bn)
    new = reach
    for _ in range(256):
        # the tree: a parent reaches its children (each state walked up once)
        for s in members(new):
            p = par[s]
            while p >= 0 and not reach[p]:
                reach[p] = 1
                p = par[p]
        # the lists kept (the nodes leaving s, their targets): a state with a target that reaches
        more = b_or(reach, _leaving(K, S, kernel.gather(tgt, reach)))
        new = b_and(more, b_not(reach))
        reach = more
        if new.find(1) < 0:
            break
    else:
        return False
    if not all(bn[v] or reach[tgt[v]] for v in init):
        return False
    # (the states found from s0 are numbered right after it)
    t = s0 + 1
    while t < S and par[t] == s0:
        if not reach[t]:
            return False
        t += 1
    return True


class _ByState:
    """The structure's lists read state by state (state s's list is class s): the compiled ``ex`` over
    it tells, for each state, whether its list has a node of a set."""

    def __init__(self, K, S: int):
        self.n = S
        self.cls = array("i", range(S))
        self.cls_succ = K.cls_succ


def _leaving(K, S: int, g: bytearray) -> bytearray:
    """The states (of ``S``) with a ``g`` node in their list (the nodes leaving them)."""
    from . import kernel
    got = kernel.ex(_ByState(K, S), g) if S else bytearray()
    if got is not None:
        return got
    out = bytearray(S)
    succ = K.cls_succ
    for s in range(S):
        if any(g[w] for w in succ[s]):
            out[s] = 1
    return out


def tree_path(explorer, K, ctl, b, budget: int = 11):
    """The path that shows ``E[true U b]`` at the one initial state s0 (the witness of ``ef(b)``, the
    counterexample of ``ag(not b)``), from the search's breadth-first tree: (nodes, loop, the
    structure the nodes are of), or None when no b node is reached.

    :meth:`CTL.explain` searches breadth first from the nodes leaving s0 (in the order of s0's
    list), moving out of the nodes where ``E[true U b]`` holds, for a b node.  Expanding a node
    (s, t) enqueues the nodes leaving t in t's list order, and tests each.  Take, for each state t
    reached, u_t the first node enqueued with target t.  A node whose target's list was enumerated
    before enqueues only targets enqueued before; so the targets are first enqueued while expanding
    some u_p, and by induction the states are first enqueued in the order in which the search
    numbers them (it expands the states in that order, each list in its order), u_t is enqueued
    while expanding u_p for p the parent the search gave t (the first state whose list holds t),
    and the u are expanded in the search's order.  Nodes where ``E[true U b]`` is false are not
    expanded, but what they would enqueue reaches no b node either, nor does anything found only
    through them (it would reach b through them): the order among the states that reach b is the
    same.  So the first b node found is the first b node of the list of y, the first state in the
    search's order with a b node in its list (s0: the first b node leaving it, tested first), and
    its path is u_{s1} .. u_y of the tree's path s0 s1 .. y, then that node (a node whose target's
    list is not all kept has the value of b of every node of that list: the first kept entry is
    the first b node).  The nodes u are not in the structure (s0's list, or a parent's, may keep
    only its first entry): the path uses nodes appended after the structure's (the structure
    returned reads them), each a step parent -> child, whose choices are found again as the
    structure's own nodes' are (:meth:`picks_between`).  Then b's own path from that node, as
    :meth:`CTL.explain` continues (``budget``: the one it has there)."""
    from .graph import b_and
    bn = b_and(ctl.sat(b), ctl.fair)
    init = K.init
    first = next((v for v in init if bn[v]), None)
    if first is not None:
        nodes, loop = ctl.explain(b, first, True, budget)
        return nodes, loop, K
    y = _leaving(K, explorer.n_states, bn).find(1)
    if y < 0:
        return None
    w = next(x for x in K.cls_succ[y] if bn[x])
    path = explorer.path_to(y)
    steps = list(zip(path, path[1:]))
    nodes, loop = ctl.explain(b, w, True, budget)
    extra = [K.n + i for i in range(len(steps))]
    if loop is not None:
        loop += len(extra)
    return extra + nodes, loop, _TreeSteps(K, explorer, steps)


class _TreeSteps:
    """A structure read as ``K`` with the steps of a tree's path appended as nodes K.n, K.n + 1, ..
    (source, target): what a trace replays of them (their states and choices)."""

    def __init__(self, K, explorer, steps):
        self._K = K
        self._explorer = explorer
        self.sid = _Appended(K.sid, [s for s, _ in steps], K.n)
        self.tgt = _Appended(K.tgt, [t for _, t in steps], K.n)

    def __getattr__(self, name):
        return getattr(self._K, name)

    def picks_from(self, v: int, src: int):
        if v >= self._K.n:
            return self._explorer.picks_between(src, self.tgt[v])
        return self._K.picks_from(v, src)


class _Appended:
    def __init__(self, base, more, n):
        self.base, self.more, self.n = base, more, n

    def __getitem__(self, v):
        return self.more[v - self.n] if v >= self.n else self.base[v]


def check_temporal(explorer, props, fair=(), on_error: str = "halt", quotient: bool = True):
    """``on_error``: what a step that fails is on the paths, ``halt`` (a transition to a node that
    stays in the state for ever) or ``drop`` (no transition; a state left without any halts).
    ``quotient``: a structure whose nodes are steps is checked as its bisimulation quotient (the
    same verdicts and paths; False: one node per step, for the tests that compare both)."""
    t_start = time.perf_counter()
    machine = explorer.m
    fair = [f for f in (fair or [])]
    atoms, checks, justice, compassion, fairness_text, errors, invars, used = formulas(
        machine, props, fair, explorer.state(0))
    results = []
    # every state has a successor (a step without updates loops): a state without one is
    # where a step failed, and paths through it would be cut short
    has_out, halts, relative_to = step_halts(explorer, explorer.n_states, on_error)
    stuck = has_out.find(0)
    if stuck >= 0:
        errors.append(f"the state graph is incomplete: the step from state {stuck} could not be computed "
                      f"(see the 'error' row)")
    if errors:
        msg = "; ".join(errors)
        return [TemporalResult(p, kind, False, message=msg, fairness=fairness_text) for p, kind, _, _ in checks]
    cache: dict = {}
    structures: dict = {}

    def kripke(step: bool):
        if step not in structures:
            structures[step] = build_kripke(explorer, atoms, used, invars, justice, compassion, fair, step=step,
                                            cache=cache, halts=halts, quotient=quotient)
        return structures[step]
    try:
        if any(kind != "ltl" and f is not None for _, kind, f, _ in checks):
            more = _lists_missing(explorer, kripke(True), halts)
            if more is not None:
                # an ag(p) broken: the search again with the lists its path reads
                from .need import ALL, EdgeNeed
                structures.clear()
                cache.clear()
                explorer.lists_again(EdgeNeed(more, []) if more != ALL else ALL, atoms)
                has_out, halts, relative_to = step_halts(explorer, explorer.n_states, on_error)
                kripke(True)
        if any(kind == "ltl" and f is not None for _, kind, f, _ in checks):
            kripke(False)
    except (AtomError, AsmError) as e:
        return [TemporalResult(p, kind, False, message=e.message, fairness=fairness_text) for p, kind, _, _ in checks]
    ctl = None
    for p, kind, f, err in checks:
        t0 = time.perf_counter()
        if f is None:
            results.append(TemporalResult(p, kind, False, message=err, fairness=fairness_text))
            continue
        if kind == "ltl":
            from .ltl import check_ltl
            K = kripke(False)
            try:
                r = check_ltl(K, f)
            except FormulaError as e:
                results.append(TemporalResult(p, kind, False, message=e.message, fairness=fairness_text))
                continue
            results.append(TemporalResult(p, kind, r.holds, nodes=r.nodes, loop=r.loop, fairness=fairness_text,
                                          explorer=explorer, K=K, seconds=time.perf_counter() - t0,
                                          stats={"product_states": r.product_states,
                                                 "automaton_states": r.automaton_states,
                                                 "kripke_nodes": K.n}))
            continue
        K = kripke(True)
        if ctl is None:
            from .ctl import CTL
            ctl = CTL(K)
        entry = _tree_entry(explorer, f)
        if entry is not None:
            # decided after the search, explained by the search tree's path (temporal/need.py)
            kind_, p_ = entry
            holds = kind_ == "ef" or ctl.sat(p_).find(0) < 0
            nodes, loop, KT = [], None, K
            if holds != (kind_ == "agt"):
                # the path of E[true U b]: f is that, or not(that)
                got = tree_path(explorer, K, ctl, f[2] if kind_ == "ef" else f[1][2])
                if got is not None:
                    nodes, loop, KT = got
            results.append(TemporalResult(p, kind, holds, nodes=nodes, loop=loop, fairness=fairness_text,
                                          explorer=explorer, K=KT, seconds=time.perf_counter() - t0,
                                          stats={"kripke_nodes": K.n}, witness=holds and bool(nodes)))
            continue
        holds, bad = ctl.check(f)
        nodes, loop, witness = [], None, False
        # from the initial node with the shortest path (the first of several equally short)
        if not holds:
            nodes, loop = ctl.explain(f, ctl.initial(f, False), False)
        elif has_existential_top(f):
            v0 = ctl.initial(f, True)
            if v0:
                nodes, loop = ctl.explain(f, v0, True)
                witness = True
        results.append(TemporalResult(p, kind, holds, nodes=nodes, loop=loop, fairness=fairness_text,
                                      explorer=explorer, K=K, seconds=time.perf_counter() - t0,
                                      stats={"kripke_nodes": K.n}, witness=witness))
    for r in results:
        r.stats["total_seconds"] = time.perf_counter() - t_start
        if not r.message:
            r.relative_to = relative_to
    return results
