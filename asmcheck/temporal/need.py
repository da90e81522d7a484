"""The successor lists the CTL check reads ("edge need").

The CTL structure of a spec whose atoms read no monitored function has a node for each state s and
each successor t of s (merged by the labels of s: :mod:`.kripke`); its labels are those of s, and
its successors are the nodes leaving t.  The value of a CTL formula at node (s, t) depends on t only
through the fixpoint steps taken there, and a fixpoint reads the list of state s only where it is
evaluated as a step:

* ``E[a U b]`` with ``a`` and ``b`` free of temporal operators: its value at (s, t) is
  ``b(s) or (a(s) and E(t))`` with ``E(x) = b(x) or (a(x) and E(u) for some successor u of x)``:
  it reads the lists of the states where ``a and not b`` holds;
* ``E[a U b]`` with ``a`` free of temporal operators and ``b`` not: the lists of the ``a`` states
  and those ``b`` reads;
* ``EG a`` with ``a`` free of temporal operators: the fair components of the subgraph of ``a``
  nodes, the lists of the ``a`` states;
* ``EX a``, and an ``E[.. U ..]`` or ``EG`` over a temporal operand: every list.

The witnesses and counterexamples (:meth:`asmcheck.temporal.ctl.CTL.explain`) read the same lists:
a breadth-first path for ``E[a U b]`` expands only ``a and not b`` nodes, a lasso of ``EG a`` stays
in ``a`` nodes, and the path that shows ``EG a`` false expands only ``a`` nodes.

So where the condition (the disjunction of what every subformula reads) does not hold, the search
keeps only the first entry of the state's list: every node leaving such a state has the same value
for every subformula (its target is never read), so the one node left stands for them all (it is
the first of them a breadth-first search meets), and the verdicts and the paths (state for state)
are those of the whole state graph.  Two top-level forms (also as
top-level conjuncts) are decided by the set of states alone, every stored state being reachable and
the source of a node:

* ``ag(p)`` (``not E[true U not p]``) holds iff every node satisfies ``p`` (for p free of temporal
  operators: every state), which needs only the lists p reads;
* ``ef(p)`` (``E[true U p]``) holds when every initial state satisfies ``p`` (known before the
  search; otherwise it reads the lists of the ``not p`` states).

``ag(p)`` reads nothing when so decided (``deferred``); otherwise the lists it reads (the ``p``
states) are recorded by the search again.  For p free of temporal operators the search itself
watches p and stops at the first state that breaks it, to start again with those lists (so a
broken ``ag(p)`` costs the search up to that state, not a whole second search).

Anything else needs every list (:data:`ALL`): LTL, fairness constraints, ``--fair``, ``--graph``,
INVAR constraints, atoms that read monitored functions, a formula that cannot be built.

With one initial state s0 (every stored state is reachable from it), a property that is exactly
``ag(p)`` or ``ef(b)`` (not a conjunct among others), with ``reads(b)`` not every list, reads only
what p or b reads (the entries ``"agt"``/``"ef"`` of :attr:`EdgeNeed.later`):

* ``ag(p)`` holds iff every node satisfies p; when a node breaks it, its counterexample (the path
  of ``E[true U not p]``) is the path of the search's own breadth-first tree to the first state,
  in the search's order, that a ``not p`` node leaves (:func:`asmcheck.temporal.tree_path` argues
  it is the path :meth:`~asmcheck.temporal.ctl.CTL.explain` finds on every list), so the search
  neither watches it nor runs again;
* ``ef(b)`` (``E[true U b]``) is *not* decided by the set of states: a node of s0 stands for one
  first step, and ``ef(b)`` must hold after every first step (s0 -> t1 where t1 only loops on
  itself, s0 -> t2 where b holds: violated although a state satisfies b).  It holds iff b holds
  at s0's node or every successor of s0 reaches a state a b node leaves; the check shows it with
  the edges it has (the tree's, the first entry of each list, the lists recorded:
  :func:`asmcheck.temporal.ef_shown`), and where they do not show it (violated, or reachable only
  through edges not kept) the search runs again recording the lists ``E[true U b]`` reads.  Its
  witness is the tree's path, as for ``ag``.
A run-time error (a failing step: a halt node, which the tree does not have) makes every such
``ef(b)`` and every such ``ag(p)`` broken read their lists again."""
from __future__ import annotations

from .formula import FALSE, TRUE, And, Not, Or, temporal_free

#: every list is read
ALL = "all"


def reads(f):
    """The condition (a formula over atoms) on the states whose lists the fixpoints of ``f`` and
    their paths read; :data:`ALL` for every state."""
    op = f[0]
    if op in ("true", "false", "ap"):
        return FALSE
    if op in ("not", "and", "or"):
        out = FALSE
        for x in f[1:]:
            r = reads(x)
            if r == ALL:
                return ALL
            out = Or(out, r)
        return out
    if op == "EU" and temporal_free(f[1]) and temporal_free(f[2]):
        return And(f[1], Not(f[2]))
    if op == "EU" and temporal_free(f[1]):
        # a temporal b: the steps are taken at a states (b's value at a node whose source is
        # outside a and outside what b reads does not depend on the node's target)
        r = reads(f[2])
        return ALL if r == ALL else Or(f[1], r)
    if op == "EG" and temporal_free(f[1]):
        return f[1]
    return ALL


def deferred(f):
    """("ag", p) for ``not E[true U not p]``, ("ef", p) for ``E[true U p]`` with p free of temporal
    operators; None otherwise."""
    if f[0] == "not" and f[1][0] == "EU" and f[1][1] == TRUE:
        return ("ag", Not(f[1][2]))
    if f[0] == "EU" and f[1] == TRUE and temporal_free(f[2]):
        return ("ef", f[2])
    return None


def whole(f):
    """("agt", p) for a property ``not E[true U not p]``, ("ef", b) for ``E[true U b]``, when what p
    or b reads is not every list (decided and explained with one initial state from the search's
    tree: see the module's text); None otherwise."""
    if f[0] == "not" and f[1][0] == "EU" and f[1][1] == TRUE and reads(f[1][2]) != ALL:
        return ("agt", Not(f[1][2]))
    if f[0] == "EU" and f[1] == TRUE and reads(f[2]) != ALL:
        return ("ef", f[2])
    return None


def conjuncts(f) -> list:
    """The top-level conjuncts of ``f``."""
    if f[0] == "and":
        return conjuncts(f[1]) + conjuncts(f[2])
    return [f]


class EdgeNeed:
    """What the CTL check of a run reads: ``cond`` the condition on the states whose lists are
    recorded (FALSE: none), ``later`` the top-level properties decided after the search, each with
    the condition it reads when they are not decided so: ("ag", p) the ``ag(p)`` conjuncts decided
    by the set of states (watched by the search when p is free of temporal operators), ("agt", p)
    and ("ef", b) the whole properties ``ag(p)`` and ``ef(b)`` of a structure with one initial
    state, explained from the search's tree (see the module's text)."""

    def __init__(self, cond, later):
        self.cond = cond
        self.later = later          # [(kind "ag"/"ef", p)]

    def atoms(self) -> list[int]:
        out: set = set()
        _atoms(self.cond, out)
        return sorted(out)

    # what an engine asks of the need (the explorer does not import this module: it sits below it)
    def watched(self) -> list:
        """The top-level ``ag(p)`` with p free of temporal operators: the search may watch them."""
        return [p for kind, p in self.later if kind == "ag" and temporal_free(p)]

    @staticmethod
    def atoms_of(ps) -> list[int]:
        """The atoms the formulas ``ps`` read."""
        out: set = set()
        for p in ps:
            _atoms(p, out)
        return sorted(out)

    @staticmethod
    def table_of_all(ps, ids: list[int]) -> bytearray:
        """The truth table over ``ids`` of the conjunction of ``ps``."""
        holds = FALSE
        for p in ps:
            holds = And(holds, p) if holds != FALSE else p
        return EdgeNeed(holds, []).table(ids)

    def after_broken(self, watch, atoms, machine, state) -> "EdgeNeed":
        """The need of the search run again after ``state`` broke some of the watched ``ag(p)``:
        the lists those properties read are recorded too, and they are no longer deferred."""
        broken = [p for p in watch if not at_initial(p, atoms, machine, [state])] or list(watch)
        cond = self.cond
        for p in broken:
            cond = Or(cond, later_cond("ag", p))
        rest = [(k, p) for k, p in self.later if not (k == "ag" and any(p is q for q in broken))]
        return EdgeNeed(cond, rest)

    def table(self, ids: list[int]) -> bytearray:
        """The condition's truth table over the atoms ``ids``: entry ``x`` for the assignment
        whose bit k is atom ids[k]."""
        out = bytearray(1 << len(ids))
        for x in range(len(out)):
            val = {a: bool(x >> k & 1) for k, a in enumerate(ids)}
            out[x] = 1 if evaluate(self.cond, val) else 0
        return out


def evaluate(f, val: dict) -> bool:
    op = f[0]
    if op == "true":
        return True
    if op == "false":
        return False
    if op == "ap":
        return val[f[1]]
    if op == "not":
        return not evaluate(f[1], val)
    if op == "and":
        return evaluate(f[1], val) and evaluate(f[2], val)
    if op == "or":
        return evaluate(f[1], val) or evaluate(f[2], val)
    raise ValueError(op)


def _atoms(f, out: set) -> None:
    if f[0] == "ap":
        out.add(f[1])
    for x in f[1:]:
        if isinstance(x, tuple):
            _atoms(x, out)


def at_initial(f, atoms, machine, states) -> bool:
    """Whether ``f`` (free of temporal operators) holds in every one of ``states`` (False when an atom
    cannot be evaluated)."""
    from ..errors import AsmError
    from ..semantics.machine import Chooser, Ctx
    ids: set = set()
    _atoms(f, ids)
    for st in states:
        val = {}
        for i in ids:
            a = atoms.items[i]
            ctx = Ctx(machine, st, Chooser())
            ctx.env = dict(a.env) if a.env else {}
            try:
                val[i] = a.fn(ctx) is True
            except AsmError:
                return False
        if not evaluate(f, val):
            return False
    return bool(states)


def edge_need(checks, atoms, justice, compassion, invars, used, fair=(), graph=False, machine=None, initial=()):
    """The :class:`EdgeNeed` of the LTL/CTL properties ``checks`` ((prop, kind, formula, error) as
    :func:`asmcheck.temporal.formulas` gives them), or :data:`ALL`.  ``initial``: the initial states
    (``ef(p)`` reads nothing when every one satisfies ``p``)."""
    if graph or fair or justice or compassion or invars:
        return ALL
    if any(atoms.items[i].monitored for i in used):
        return ALL
    cond = FALSE
    later = []
    for _p, kind, f, err in checks:
        if f is None or err or kind != "ctl":
            return ALL
        w = whole(f) if len(initial) == 1 and machine is not None else None
        if w is not None and not (w[0] == "ef" and temporal_free(w[1]) and at_initial(w[1], atoms, machine, initial)):
            # decided and explained after the search (the tree's path): reads what p or b reads
            r = reads(w[1])
            cond = Or(cond, r)
            later.append(w)
            continue
        # a property holds where each of its top-level conjuncts does (forall $x with ag(..) is one)
        for c in conjuncts(f):
            d = deferred(c)
            if d is not None and d[0] == "ag":
                # decided by p's value at every node (p reads what it reads)
                r = reads(d[1])
                if r == ALL:
                    return ALL
                cond = Or(cond, r)
                later.append(d)
                continue
            if d is not None and machine is not None and at_initial(d[1], atoms, machine, initial):
                continue
            r = reads(c)
            if r == ALL:
                return ALL
            cond = Or(cond, r)
    if cond == TRUE:
        return ALL
    return EdgeNeed(cond, later)


def later_cond(kind: str, p):
    """The lists ``ag(p)`` reads when a node breaks p: those of ``E[true U not p]``; those ``ef(p)``
    reads when the edges kept do not show it: those of ``E[true U p]``."""
    return reads(("EU", TRUE, p if kind == "ef" else Not(p)))


def state_set(f, labs: dict, n: int) -> bytearray:
    """The states (of ``n``) where ``f``, free of temporal operators, holds; ``labs``: atom -> the
    states where it holds."""
    from .graph import b_and, b_not, b_or, full
    op = f[0]
    if op == "true":
        return full(n)
    if op == "false":
        return bytearray(n)
    if op == "ap":
        return bytearray(labs[f[1]])
    if op == "not":
        return b_not(state_set(f[1], labs, n))
    if op == "and":
        return b_and(state_set(f[1], labs, n), state_set(f[2], labs, n))
    if op == "or":
        return b_or(state_set(f[1], labs, n), state_set(f[2], labs, n))
    raise ValueError(op)
