"""The Kripke structure the temporal properties are checked on, derived from the
explorer's state graph.

AsmetaSMV (ASMETA's model checker) makes every monitored function a NuSMV state variable
and every ``choose`` variable too: a NuSMV state is an ASM state *together with the
inputs and choices of the step taken from it*, so ``ag(fin(j) implies ax(st(j) = FIN))``
reads ``fin(j)`` in the state where the step reads it.  asmcheck's explorer stores ASM
states only (the monitored values are drawn during the step), so:

* when no atomic proposition, fairness constraint or INVAR reads a monitored function
  and no agent fairness is asked for, the Kripke structure is the state graph itself
  (``mode == "state"``: one node per explored state);
* otherwise (``mode == "step"``) a node is an explored transition ``src -> dst`` together
  with the values of the atoms that read monitored functions, evaluated in ``src`` with
  the monitored values the step read (monitored locations the step did not read take
  every value of their domain, as free NuSMV variables do); its successors are all the
  nodes leaving ``dst``.  Nodes with the same ``(src, dst, atom values)`` are bisimilar
  and are stored once.  INVAR constraints (environment assumptions) drop the nodes that
  break them, as NuSMV's ``INVAR`` does.

  Since the successors of a node depend on its target only, nodes with the same target, the
  same atom values (those of the source's state atoms and the monitored ones) and sources
  that are both initial or both not are bisimilar too: the temporal checks run on that
  quotient (``build_kripke(quotient=True)``), at most (label classes) x (states) nodes
  instead of one per transition (examples/parking.asm: 98,320 instead of 86,093,442).
  Fairness sets are labels, so fair CTL and LTL verdicts are the same, and so are the
  shortest paths a breadth-first search finds.  On a path the source of a node is the
  target of the node before it (the first node's, its own: an initial state); the choices
  of its step are looked up from that source (:meth:`Kripke.picks_from`).  Agent fairness
  (``--fair``) reads the move of each step (source and target): its structure is not merged.

Successor lists are shared between nodes (every node leaving ``dst`` has the same
successors), so the structure keeps *successor classes*: ``cls[v]`` is the class of v's
successor list ``cls_succ[c]``; ``member_of[w]`` are the classes containing w and
``cls_nodes[c]`` the nodes whose successors are class c.  Backward searches walk these.
"""
from __future__ import annotations

from array import array
from bisect import bisect_left

from ..errors import AsmError, UsageError
from ..semantics.machine import Chooser, Ctx, Machine, ScriptChooser, Enumerator
from ..semantics.state import same_value
from ..semantics.values import show
from .classes import Classes
from .formula import Atoms
from ..semantics.choice import next_prefix


class AtomError(AsmError):
    pass


class Kripke:
    def __init__(self):
        self.mode = "state"
        self.n = 0
        self.sid: list[int] = []          # explored state of each node
        self.tgt: list[int] | None = None  # step mode: the state the node's step leads to
        self.picks: list | None = None     # step mode: the choices of the node's step
        self.vec: list | None = None       # step mode: values of the monitored atoms
        self.cls: list[int] = []
        self.cls_succ: list[list[int]] = []
        self._member_of: list[list[int]] | None = None
        self._cls_nodes: list[list[int]] | None = None
        self.init: list[int] = []
        self.label: dict[int, bytearray] = {}     # atom index -> node set
        self.justice: list[tuple[str, bytearray]] = []
        self.compassion: list[tuple[str, bytearray, bytearray]] = []
        self.edge_picks: dict = {}         # state mode: (src, dst) -> choices of one such step
        self.mon_atoms: list[int] = []
        self.mon_items: list = []          # step mode: the atoms of mon_atoms (what a trace replays)
        self.agent_info = None
        # halt nodes (a step fails there, see asmcheck.temporal): node -> (the state it stays in,
        # the choices of the failing step, the index of its error in the explorer's error_edges)
        self.halt: dict[int, tuple] = {}

    def succ(self, v: int) -> list[int]:
        return self.cls_succ[self.cls[v]]

    def picks_from(self, v: int, src: int):
        """Step mode: the choices of node v's step taken from state ``src`` (the target of the node
        before v on a path, or an initial state for the first): in the quotient a node stands
        for the steps from every source with the same labels."""
        h = self.halt.get(v)
        if h is not None:
            return h[1]
        at = getattr(self.picks, "at", None)
        return at(v, src) if at is not None else self.picks[v]

    # the backward lists, made when a backward search in Python first needs them (the compiled
    # kernel makes its own)
    @property
    def member_of(self) -> list[list[int]]:
        if self._member_of is None:
            _finish_classes(self)
        return self._member_of

    @property
    def cls_nodes(self) -> list[list[int]]:
        if self._cls_nodes is None:
            _finish_classes(self)
        return self._cls_nodes


class Vectors:
    """The atom values of the nodes of a step-mode structure: bit k of ``bits[v]`` is atom k's
    (``bits`` None: ``n`` nodes without atoms); ``self[v]`` is the tuple of booleans the Python
    code compares.  Vectors appended later are kept as tuples."""

    def __init__(self, bits, nk: int, n: int = 0):
        self.bits, self.nk, self.n0 = bits, nk, (len(bits) if bits is not None else n)
        self.extra: list = []

    def __len__(self):
        return self.n0 + len(self.extra)

    def __getitem__(self, v):
        if v >= self.n0:
            return self.extra[v - self.n0]
        if self.bits is None:
            return ()
        x = self.bits[v]
        return tuple(bool(x >> k & 1) for k in range(self.nk))

    def append(self, vec):
        self.extra.append(tuple(vec))

    def __iter__(self):
        for v in range(len(self)):
            yield self[v]


def _finish_classes(K: Kripke) -> None:
    nc = len(K.cls_succ)
    member_of = [[] for _ in range(K.n)]
    cls_nodes = [[] for _ in range(nc)]
    for c, lst in enumerate(K.cls_succ):
        for w in lst:
            member_of[w].append(c)
    for v, c in enumerate(K.cls):
        cls_nodes[c].append(v)
    K._member_of, K._cls_nodes = member_of, cls_nodes


def _truth(v, atom) -> bool:
    # an undef proposition is false (NuSMV has no undef Boolean)
    return v is True


def state_labels(explorer, atoms: Atoms, which: list[int]) -> dict[int, bytearray]:
    """Atom index -> the explored states where it holds (atoms that read no monitored
    function)."""
    m = explorer.m
    S = explorer.n_states
    out = {i: bytearray(S) for i in which}
    if not which:
        return out
    fast = getattr(explorer, "state_labels", None)
    if fast is not None:
        labs = fast([atoms.items[i] for i in which])
        if labs is not None:
            return {i: bytearray(lab) for i, lab in zip(which, labs)}
    items = [(i, atoms.items[i]) for i in which]
    for sid in range(S):
        st = explorer.state(sid)
        ctx = Ctx(m, st, Chooser())
        for i, a in items:
            ctx.env = dict(a.env) if a.env else {}
            try:
                v = a.fn(ctx)
            except AsmError as e:
                raise AtomError(a.term.span, f"{a.text} cannot be evaluated in state {sid}: {e.message}") from None
            if v is True:
                out[i][sid] = 1
    return out


def joint_values(machine, items, state, mon) -> list[tuple]:
    """The distinct vectors of truth values of ``items`` (atoms) in ``state`` with the step's
    monitored values ``mon``; monitored locations the step did not read take every value."""
    out = []
    seen = set()
    prefix: list = []
    while True:
        ch = Enumerator(prefix)
        ctx = Ctx(machine, state, ch)
        if mon:
            ctx.mon = dict(mon)
        vec = []
        for a in items:
            ctx.env = dict(a.env) if a.env else {}
            try:
                vec.append(a.fn(ctx) is True)
            except AsmError as e:
                raise AtomError(a.term.span, f"{a.text} cannot be evaluated: {e.message}") from None
        t = tuple(vec)
        if t not in seen:
            seen.add(t)
            out.append(t)
        prefix = next_prefix(ch.log)
        if prefix is None:
            return out


# ----------------------------------------------------------------- agents (weak fairness)
def agent_moves(explorer, fair: list[str]):
    """For every explored state: (the agents enabled there, {dst: agents whose move leads
    to dst}).  An agent of DOMAIN moves in a step when it is the value chosen by the first
    ``choose`` of the step that binds an element of DOMAIN (``choose $t in Task with ...
    do program($t)``); with ``all`` every alternative of every ``choose`` rule is an agent
    (label, bindings).  The steps are enumerated again without merging the choose
    alternatives that have the same effect, so that every agent's move is seen."""
    m0 = explorer.m
    m = Machine(m0.spec, {**m0.options, "dedupe": False})
    doms = []
    use_all = False
    for name in fair:
        if name == "all":
            use_all = True
            continue
        dom = next((d for d in m.spec.domains if getattr(d, "name", None) == name), None)
        if dom is None:
            raise UsageError(f"--fair {name}: the spec has no domain {name}")
        st0 = explorer.state(0)
        try:
            elems = m.domain_values(dom, Ctx(m, st0, Chooser()), None)
        except AsmError as e:
            raise UsageError(f"--fair {name}: cannot list the elements of {name}: {e.message}") from None
        doms.append((name, list(elems)))
    agents: list = []
    agent_ix: dict = {}

    def agent_id(key, text):
        i = agent_ix.get(key)
        if i is None:
            i = agent_ix[key] = len(agents)
            agents.append((key, text))
        return i

    S = explorer.n_states
    enabled: list[frozenset] = []
    moves: list[dict] = []
    for sid in range(S):
        st = explorer.state(sid)
        en: set = set()
        mv: dict = {}
        # a failing branch is no move (the run halts there): an agent is enabled where it has a
        # well-defined move
        for log, ups, nxt, mon in m.successors(st, errors=[]):
            dst = _find(explorer, nxt)
            who = set()
            for dname, elems in doms:
                for c in log:
                    if c.kind != "choose" or not isinstance(c.value, dict):
                        continue
                    hit = [v for v in c.value.values() if any(same_value(v, e) for e in elems)]
                    if hit:
                        for v in hit:
                            who.add(agent_id((dname, _hkey(v)), f"{show(v)}"))
                        break
            if use_all:
                for c in log:
                    if c.kind == "choose":
                        b = c.value if isinstance(c.value, dict) else {"": c.value}
                        key = ("all", c.label, tuple((k, _hkey(v)) for k, v in sorted(b.items())))
                        text = f"{c.label}: " + ", ".join(f"{k} = {show(v)}" for k, v in sorted(b.items()))
                        who.add(agent_id(key, text))
            en |= who
            if dst is not None:
                mv.setdefault(dst, set()).update(who)
        enabled.append(frozenset(en))
        moves.append({d: frozenset(a) for d, a in mv.items()})
    return agents, enabled, moves


def _find(explorer, st: dict):
    """The id of the explored state equal to the successor ``st`` (as the step made it), or None."""
    find = getattr(explorer, "find", None)
    if find is not None:
        return find(st)
    return explorer.index.get(explorer.layout.freeze(explorer._norm(st)))


def _state_halts(K: Kripke, halts: list, ok_state, S: int) -> None:
    """State mode: one halt node per state where a step fails, labelled as that state, with a
    transition from the state and a loop on itself."""
    node_of: dict = {}
    sids = list(range(S))
    for src, picks, _mon, ix in halts:
        if not ok_state[src] or src in node_of:
            continue
        v = node_of[src] = len(sids)
        sids.append(src)
        K.halt[v] = (src, picks, ix)
        K.cls_succ[src] = K.cls_succ[src] + [v]
        K.cls.append(v)
        K.cls_succ.append([v])
    K.n = len(sids)
    K.sid = sids
    extra = sids[S:]
    for i, lab in list(K.label.items()):
        K.label[i] = bytearray(lab) + bytearray(lab[s] for s in extra)


class EdgePicks:
    """(src, dst) -> the choices of the first explored step from src to dst, looked up in the
    edge arrays (sources ascend, as the search expanded them) and taken from
    ``explorer.edges[i]`` only for the few steps a trace prints."""

    def __init__(self, explorer, src, dst):
        self.explorer = explorer
        self.src = src
        self.dst = dst
        self.index = None
        self.checked = False

    def __getitem__(self, key):
        a, b = key
        if not self.checked:
            # an explorer that records its edges in another order (a random walk's) is looked up
            # through an index of the first edge of each pair (made when a trace first asks)
            from . import kernel
            self.checked = True
            if not kernel.ascending(self.src):
                self.index = {}
                src, dst = self.src, self.dst
                for i in range(len(src)):
                    self.index.setdefault((src[i], dst[i]), i)
        if self.index is not None:
            i = self.index.get((a, b))
            if i is None:
                raise KeyError(key)
            return self.explorer.edges[i][2]
        src, dst = self.src, self.dst
        i = bisect_left(src, a)
        while i < len(src) and src[i] == a:
            if dst[i] == b:
                return self.explorer.edges[i][2]
            i += 1
        raise KeyError(key)

    def __contains__(self, key):
        try:
            self[key]
            return True
        except KeyError:
            return False


def _every_step(explorer, ok_state):
    """(src, dst, choices, monitored values or None) for every enumerated step between explored
    states, in the explorer's order.  An explorer whose edges hold every enumerated step (the
    Python explorer's, duplicates included) gives them; one that records each (src, dst) pair
    once (the native explorer) would hide the other steps from src to dst, whose monitored
    values may differ: there the Python step function enumerates the steps of each state."""
    if getattr(explorer, "engine", "") != "native":
        for src, dst, picks in explorer.edges:
            yield src, dst, picks, None
        return
    m = explorer.m
    for src in range(explorer.n_states):
        if not ok_state[src]:
            continue
        try:
            steps = m.successors(explorer.state(src), errors=[])     # a failing branch is no edge
        except AsmError as e:
            raise AtomError(None, f"the step from state {src} cannot be computed: {e.message}") from None
        for log, _ups, nxt, mon in steps:
            dst = _find(explorer, nxt)
            if dst is not None:
                yield src, dst, tuple(c.pick for c in log), mon


class _LazyPicks:
    """Node -> the choices of its step, worked out only for the few steps a trace prints
    (:meth:`pick`); the nodes added after the first :meth:`count` (halt nodes) keep theirs in
    ``extra``.  ``sid`` (when there is one) gives each node's source."""

    sid = None

    def __init__(self):
        self.extra: list = []        # the choices of the nodes added after these (halt nodes)

    def count(self) -> int:
        return len(self.sid)

    def __len__(self):
        return self.count() + len(self.extra)

    def append(self, picks):
        self.extra.append(picks)

    def __getitem__(self, v):
        return self.at(v, self.sid[v] if self.sid is not None and v < self.count() else None)

    def at(self, v, src):
        """The choices of the node's step taken from state ``src``."""
        n = self.count()
        if v >= n:
            return self.extra[v - n]
        return self.pick(v, src)

    def pick(self, v, src):
        raise NotImplementedError


class _PicksOfSteps(_LazyPicks):
    """Node -> the choices of the first step (of the Python step function) from the node's
    source to its target whose monitored values give the node's atom values."""

    def __init__(self, explorer, items, sid, tgt, vecs):
        super().__init__()
        self.explorer, self.items = explorer, items
        self.sid, self.tgt, self.vecs = sid, tgt, vecs

    def pick(self, v, src):
        ex = self.explorer
        m = ex.m
        st = ex.state(src)
        # the native engine's first step to the target, run once (NativeExplorer.guided_step: None
        # unless it leads there): when it gives the atom values, it is the first such step
        guided = getattr(ex, "guided_step", None)
        got = guided(src, self.tgt[v], st) if guided is not None else None
        if got is not None and self.vecs[v] in joint_values(m, self.items, st, got[3]):
            return tuple(c.pick for c in got[1])
        for log, _ups, nxt, mon in m.successors(st, errors=[]):
            if _find(ex, nxt) == self.tgt[v] and self.vecs[v] in joint_values(m, self.items, st, mon):
                return tuple(c.pick for c in log)
        raise AtomError(None, f"no step from state {src} to state {self.tgt[v]} gives the atoms' values")


class _PicksOfEdges(_LazyPicks):
    """Node -> the choices of its step (``explorer.edges[i][2]`` of the node's edge)."""

    def __init__(self, explorer, eix):
        super().__init__()
        self.explorer = explorer
        self.eix = eix

    def count(self) -> int:
        return len(self.eix)

    def pick(self, v, src):
        return self.explorer.edges[self.eix[v]][2]


class _EdgePicksOf(_LazyPicks):
    """Quotient node -> the choices of the first explored step from a source to the node's target
    (the explorer's edges, looked up by (source, target)); ``sid`` and ``tgt`` are set once the
    quotient is made."""

    def __init__(self, edge_picks):
        super().__init__()
        self.edge_picks = edge_picks
        self.sid = self.tgt = None

    def pick(self, v, src):
        return self.edge_picks[(src, self.tgt[v])]


class _PicksOfKeys(_LazyPicks):
    """Quotient node -> the choices of the step with the node's target and atom values taken from
    a source, found among the steps the structure was built from (``index``: (source, target,
    atom values) -> position in ``picks``)."""

    def __init__(self, picks, index, tgt, vecs, sid):
        super().__init__()
        self.picks, self.index, self.tgt, self.vecs, self.sid = picks, index, tgt, vecs, sid

    def pick(self, v, src):
        i = self.index.get((src, self.tgt[v], self.vecs[v]))
        if i is None:
            raise AtomError(None, f"no step from state {src} to state {self.tgt[v]} gives the atoms' values")
        return self.picks[i]


def _signatures(S: int, labs: list, init_sids) -> array:
    """What a node's label and initial flag read of its source state, one number a state: the
    state atoms' bits (numbered densely when there are more than 63 of them) and bit 63 for an
    initial state."""
    from . import kernel
    if len(labs) <= 63:
        sig = kernel.signatures(S, labs)
    else:
        ids: dict = {}
        sig = array("Q", (ids.setdefault(bytes(lab[s] for lab in labs), len(ids)) for s in range(S)))
    for s in init_sids:
        sig[s] |= 1 << 63
    return sig


def _quotient(K, S, steps, slab, st_atoms, init_sids, ok_state, explorer, mon_items, key_ix):
    """The bisimulation quotient of the step nodes (sid[i], tgt[i], vecs[i]).  Every node leaving a
    state has the same successors (the nodes leaving its target), so nodes with the same target,
    the same atom values (of the state atoms of their source and of the monitored atoms) and
    sources that are both initial or both not are bisimilar and one node stands for them: CTL
    and LTL verdicts (the fairness sets are labels) are the same, and so are the paths a
    breadth-first search finds, node for node (numbered by their first step, each state's
    successors in the order of its steps).  The source of a node on a path is the target of the
    node before it; the first node's, an initial state with its labels (the node's own source).
    ``steps``: [sid, tgt, picks, vecs] of the step nodes, emptied (the only reference to them).
    Returns (sid, tgt, picks, vecs, off, adj) of the quotient."""
    from . import kernel
    sid, tgt, picks_l, vecs = steps
    steps.clear()
    sig = _signatures(S, [slab[i] for i in st_atoms], init_sids)
    vb = None
    if mon_items:
        if vecs.bits is not None and not vecs.extra:
            vb = vecs.bits
        else:
            vb = array("q", (sum(1 << k for k, x in enumerate(vec) if x) for vec in vecs))
    first, off, adj = kernel.quotient(S, sid, tgt, vb, sig, ok_state)
    sid_q = kernel.take(sid, first, "I")
    tgt_q = kernel.take(tgt, first, "i")
    if vb is not None:
        vec_q = Vectors(kernel.take(vb, first, vb.typecode), len(mon_items))
    else:
        vec_q = Vectors(None, 0, len(first))
    del first, sid, tgt, vb, vecs      # the steps' arrays are freed here
    if isinstance(picks_l, _EdgePicksOf):
        picks_l.sid, picks_l.tgt = sid_q, tgt_q
        picks_q = picks_l
    elif isinstance(picks_l, _PicksOfSteps):
        picks_q = _PicksOfSteps(explorer, mon_items, sid_q, tgt_q, vec_q)
    else:
        picks_q = _PicksOfKeys(picks_l, key_ix, tgt_q, vec_q, sid_q)
    return sid_q, tgt_q, picks_q, vec_q, off, adj


def _quotient_by_source(explorer, S, mon_items, ok_state, need, slab, st_atoms, init_sids):
    """:func:`_quotient` of the steps the native explorer gives source by source (the atoms that
    read monitored functions evaluated by its compiled code), merged as they come without keeping
    them: (sid, tgt, vecs, off, adj), or None when the explorer or the kernel cannot."""
    from . import kernel
    each_fn = getattr(explorer, "step_atoms_each", None)
    each = each_fn(mon_items, ok_state) if each_fn is not None else None
    if each is None:
        return None
    sig = _signatures(S, [slab[i] for i in st_atoms], init_sids)
    got = kernel.quotient_by_source(S, sig, each, need)
    if got is None or each.failed:
        return None
    fsrc, fdst, fvec, off, adj = got
    bits = fvec if len(mon_items) > 8 else array("B", fvec)
    return fsrc, fdst, Vectors(bits, len(mon_items)), off, adj


def _quotient_recorded(explorer, S, mon_items, ok_state, need, slab, st_atoms, init_sids, cache, key):
    """:func:`_quotient_by_source` of the steps the native search recorded while it searched
    (``explorer.step_quotient``: no edges kept, no step run again), or None when it did not record
    them for these atoms.  The result is kept in ``cache`` for a second structure with the same atoms
    (LTL and CTL both in step mode)."""
    got = cache.get(("recorded", key))
    if got is not None:
        return got
    fn = getattr(explorer, "step_quotient", None)
    if fn is None:
        return None
    sig = _signatures(S, [slab[i] for i in st_atoms], init_sids)
    res = fn(mon_items, sig, ok_state, need)
    if res is None:
        return None
    fsrc, fdst, fvec, off, adj = res
    if mon_items:
        vecs = Vectors(fvec, len(mon_items))        # (one byte a node with at most 8 atoms)
    else:
        vecs = Vectors(None, 0, len(fsrc))
    got = cache[("recorded", key)] = (fsrc, fdst, vecs, off, adj)
    return got


class _PicksBetween(_LazyPicks):
    """Quotient node -> the choices of the first step of the Python step function from a source to
    the node's target (``explorer.picks_between``), for the steps a trace prints."""

    def __init__(self, explorer, sid, tgt):
        super().__init__()
        self.explorer, self.sid, self.tgt = explorer, sid, tgt

    def pick(self, v, src):
        return self.explorer.picks_between(src, self.tgt[v])


def _hkey(v):
    try:
        hash(v)
        return (type(v).__name__, v)
    except TypeError:
        return (type(v).__name__, repr(v))


# ----------------------------------------------------------------- the structure
def build_kripke(explorer, atoms: Atoms, used: set[int], invars: list[int], justice: list[tuple[str, int]],
                 compassion: list[tuple[str, int, int]], fair: list[str], step: bool = True,
                 cache: dict | None = None, halts: list | None = None, quotient: bool = False) -> Kripke:
    """``used``: the atoms the formulas read; ``invars``: atoms that every node must satisfy;
    ``justice``: (text, atom); ``compassion``: (text, atom p, atom q); ``fair``: --fair
    domains.  ``step=False`` asks for the state graph itself when it is enough (no
    monitored atom, no agent fairness): LTL needs only the paths, which are the same in
    both; CTL needs ``step=True``, since a NuSMV state holds the choices of its step, so
    that ``ef(p)`` in an initial state must hold for *every* first step.

    ``halts``: the steps that fail, [(state id, choices, monitored values it read, index)];
    each is a transition from its state to a *halt node* that carries the same state (and,
    in step mode, the monitored values the failing step read) and loops on itself: the run
    stops at the error and stays in its last well-defined state for ever (the Kripke
    structure keeps every path infinite).  Halts with the same node contents are one node.

    ``quotient`` (step mode without agent fairness): the bisimulation quotient of the steps
    (:func:`_quotient`, what :func:`asmcheck.temporal.check_temporal` checks); False: one node
    per step."""
    m = explorer.m
    K = Kripke()
    all_atoms = sorted(set(used) | set(invars) | {a for _, a in justice} |
                       {a for _, p, q in compassion for a in (p, q)})
    mon_atoms = [i for i in all_atoms if atoms.items[i].monitored]
    st_atoms = [i for i in all_atoms if not atoms.items[i].monitored]
    K.mon_atoms = mon_atoms
    S = explorer.n_states
    cache = {} if cache is None else cache
    key = tuple(st_atoms)
    slab = cache.get(("slab", key))
    if slab is None:
        slab = cache[("slab", key)] = state_labels(explorer, atoms, st_atoms)
    st_invars = [i for i in invars if i in slab]
    init_sids = [s for s in range(S) if explorer.parent[s] == -1]
    ok_state = bytearray(b"\x01") * S
    for i in st_invars:
        ok_state = bytearray(x & y for x, y in zip(ok_state, slab[i]))
    agents = None
    if fair:
        info = cache.get("agents")
        if info is None:
            info = cache["agents"] = agent_moves(explorer, fair)
        agents, enabled, moves = K.agent_info = info
    from . import kernel
    if not mon_atoms and not fair and not step:
        # ---- state mode: the explored graph itself, its successor lists as two arrays
        K.mode = "state"
        K.n = S
        K.sid = range(S)
        src_a, dst_a = explorer.edge_arrays()
        K.edge_picks = EdgePicks(explorer, src_a, dst_a)
        off, adj = kernel.csr(S, src_a, dst_a, ok_state)
        K.cls = array("i", range(S))
        K.cls_succ = Classes(off, adj)
        K.init = [s for s in init_sids if ok_state[s]]
        for i, lab in slab.items():
            K.label[i] = lab
        if halts:
            _state_halts(K, halts, ok_state, S)
    else:
        # ---- step mode: one node per (transition, values of the monitored atoms), the nodes
        # as arrays (their state, target, atom values), numbered source by source
        K.mode = "step"
        mon_items = K.mon_items = [atoms.items[i] for i in mon_atoms]
        mon_inv = [k for k, i in enumerate(mon_atoms) if i in invars]
        key_ix: dict = {}
        sid, tgt = array("I"), array("i")
        picks_l: list = []
        vecs = Vectors(None, 0)
        cur_src, cur_state = -1, None
        merge = quotient and agents is None and len(mon_items) <= 63
        need = 0
        for k in mon_inv:
            need |= 1 << k
        # the quotient merged from the steps the search recorded as it went (no edges kept)
        recorded = _quotient_recorded(explorer, S, mon_items, ok_state, need, slab, st_atoms, init_sids,
                                      cache, tuple(all_atoms)) if merge else None
        if recorded is not None:
            pass
        elif not mon_items and merge:
            # no atom reads a monitored function: the quotient of the explored transitions, read
            # from the edge arrays as they are (a pair recorded twice is one node)
            src_a, dst_a = explorer.edge_arrays()
            sid, tgt = src_a, dst_a
            picks_l = _EdgePicksOf(EdgePicks(explorer, src_a, dst_a))
            vecs = Vectors(None, 0, len(sid))
        elif not mon_items:
            # no atom reads a monitored function: one node per distinct explored transition,
            # read from the edge arrays; the choices of a node's step are looked up only for
            # the steps a trace prints
            src_a, dst_a = explorer.edge_arrays()
            off0, _ = kernel.group(S, src_a) if len(src_a) else (array("i", [0]), None)
            once = getattr(explorer, "engine", "") == "native" and not halts and (
                not S or max(off0[v + 1] - off0[v] for v in range(S)) <= 4096)
            if once and len(ok_state) and ok_state.find(0) < 0:
                # the native search records each (src, dst) pair once (it tells apart 4096
                # successors of a state): every edge is a node
                sid = kernel._u32(src_a)
                tgt = array("i", dst_a)
                eix = range(len(sid))
            else:
                seen: set = set()
                eix = array("I")
                for i, (src, dst) in enumerate(zip(src_a, dst_a)):
                    if not ok_state[src]:
                        continue
                    key = src * S + dst
                    if key in seen:
                        continue
                    seen.add(key)
                    sid.append(src)
                    tgt.append(dst)
                    eix.append(i)
                del seen
            picks_l = _PicksOfEdges(explorer, eix)
            vecs = Vectors(None, 0, len(sid))
        streamed = _quotient_by_source(explorer, S, mon_items, ok_state, need, slab, st_atoms,
                                       init_sids) if merge and mon_items and recorded is None else recorded
        fast = getattr(explorer, "step_atoms", None) if mon_items and streamed is None else None
        recs = fast(mon_items, ok_state) if fast is not None else None
        if streamed is not None:
            # the compiled code merged the steps as it gave them (source by source)
            sid, tgt, vecs, off, adj = streamed
            if halts:
                # halt nodes are appended: the arrays a cache may hold for another structure stay
                tgt = array("i", tgt)
                vecs = Vectors(vecs.bits, vecs.nk, len(vecs))
            picks_l = (_PicksOfSteps(explorer, mon_items, sid, tgt, vecs) if mon_items
                       else _PicksBetween(explorer, sid, tgt))
            recs = True
        elif recs is not None:
            # the compiled code gave (src, dst, atom values) for every step, each once
            rs, rd, rv = recs
            if need:
                keep = [i for i in range(len(rs)) if rv[i] & need == need]
                rs = array("I", [rs[i] for i in keep])
                rd = array("i", [rd[i] for i in keep])
                rv = array(rv.typecode, [rv[i] for i in keep])
            sid, tgt, vecs = rs, rd, Vectors(rv, len(mon_items))
            picks_l = _PicksOfSteps(explorer, mon_items, sid, tgt, vecs)
            recs = rs = rd = rv = True         # the arrays live on as sid, tgt, vecs only
        elif mon_items:
            vecs = Vectors(None, len(mon_items), 0)
        for src, dst, picks, mon in (_every_step(explorer, ok_state) if mon_items and recs is None else ()):
            if not ok_state[src]:
                continue
            if mon_items:
                if src != cur_src:
                    cur_src, cur_state = src, explorer.state(src)
                if mon is None:
                    try:
                        ch = ScriptChooser(picks)
                        _, _, ctx = m.step(cur_state, ch)
                    except AsmError as e:
                        raise AtomError(None, f"the step from state {src} cannot be replayed: {e.message}") from None
                    mon = ctx.mon
                vs = joint_values(m, mon_items, cur_state, mon)
            else:
                vs = [()]
            for vec in vs:
                if any(not vec[k] for k in mon_inv):
                    continue
                key = (src, dst, vec)
                if key in key_ix:
                    continue
                key_ix[key] = len(sid)
                sid.append(src)
                tgt.append(dst)
                picks_l.append(picks)
                vecs.append(vec)
        if streamed is not None:
            pass
        elif merge:
            steps = [sid, tgt, picks_l, vecs]
            sid = tgt = picks_l = vecs = None          # the steps' arrays are freed once merged
            sid, tgt, picks_l, vecs, off, adj = _quotient(K, S, steps, slab, st_atoms, init_sids, ok_state,
                                                          explorer, mon_items, key_ix)
        else:
            # the nodes leaving each explored state (its successor class)
            off, adj = kernel.group(S, sid)
        nbase = len(sid)
        # the halt nodes: (state, values of the monitored atoms in the failing step), each its
        # own successor class (it loops on itself)
        halt_nodes: list = []
        for src, picks, mon, ix in (halts or ()):
            if not ok_state[src]:
                continue
            vs = joint_values(m, mon_items, explorer.state(src), mon) if mon_items else [()]
            for vec in vs:
                if any(not vec[k] for k in mon_inv):
                    continue
                key = (src, None, vec)
                if key in key_ix:
                    continue
                if sid is getattr(explorer, "edge_src", None) or len(sid) == nbase:
                    sid = array("I", sid)        # not the explorer's own array
                v = key_ix[key] = len(sid)
                sid.append(src)
                tgt.append(-1)
                picks_l.append(picks)
                vecs.append(vec)
                K.halt[v] = (src, picks, ix)
                halt_nodes.append(v)
        K.n = len(sid)
        K.sid, K.tgt, K.picks, K.vec = sid, tgt, picks_l, vecs
        if isinstance(picks_l, (_PicksOfSteps, _PicksBetween)):
            picks_l.sid = sid
        # successor classes: one per explored state (the nodes leaving it), one per halt node
        K.cls = array("i", tgt) if halt_nodes else tgt
        # (the recorded lists may be 16-bit targets read through a table of nodes: a tuple)
        K.cls_succ = Classes(off, *adj) if isinstance(adj, tuple) else Classes(off, adj)
        for v in halt_nodes:
            s_ = sid[v]
            K.cls_succ[s_] = K.cls_succ[s_] + [v]
        for v in halt_nodes:
            K.cls[v] = len(K.cls_succ)
            K.cls_succ.append([v])
        K.init = list(dict.fromkeys(v for s in init_sids for v in K.cls_succ[s]))
        for i, lab in slab.items():
            K.label[i] = kernel.gather(sid, lab)
        for k, i in enumerate(mon_atoms):
            if vecs.bits is not None and not vecs.extra:
                K.label[i] = kernel.bit(vecs.bits, k)
            else:
                K.label[i] = bytearray(1 if vec[k] else 0 for vec in vecs)
    for text, a in justice:
        K.justice.append((text, K.label[a]))
    for text, p, q in compassion:
        K.compassion.append((text, K.label[p], K.label[q]))
    if agents is not None:
        for ai, (key, text) in sorted(enumerate(agents), key=lambda x: (str(x[1][0][0]), x[1][1])):
            lab = bytearray(K.n)
            for v in range(K.n):
                s = K.sid[v]
                # a halted run makes no move: no agent is enabled in it
                if v in K.halt or ai not in enabled[s] or ai in moves[s].get(K.tgt[v], ()):
                    lab[v] = 1
            K.justice.append((f"weak fairness of {text}", lab))
    return K
