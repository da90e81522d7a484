"""Typed intermediate representation: names resolved, every node typed and located.

Built by :mod:`asmcheck.semantics.resolve`; read by the step compiler
(:mod:`asmcheck.semantics.compile`), by property checkers and by the Z3 engine.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import NO_SPAN, Span
from .types import Type


# ----------------------------------------------------------------- declarations
@dataclass(eq=False)
class Function:
    name: str
    kind: str                      # static derived controlled monitored shared out local
    domain: list[Type]             # argument types (empty for 0-ary)
    codomain: Type
    module: str
    span: Span = NO_SPAN
    params: list["Var"] | None = None   # of a definition (static/derived)
    body: "Term | None" = None          # definition body
    index: int = -1                     # position in the spec's function table

    __hash__ = object.__hash__

    @property
    def arity(self) -> int:
        return len(self.domain)

    @property
    def qualname(self) -> str:
        return f"{self.module}::{self.name}"

    @property
    def is_dynamic(self) -> bool:
        return self.kind in ("controlled", "monitored", "shared", "out", "local")

    @property
    def is_location(self) -> bool:
        """Its values live in the state (not computed from a definition)."""
        return self.kind in ("controlled", "shared", "out", "local", "monitored") or (
            self.kind == "static" and self.body is None)

    def __repr__(self) -> str:
        return f"<Function {self.name}/{self.arity}>"


@dataclass(eq=False)
class RuleDecl:
    name: str
    params: list["Var"]
    module: str
    span: Span = NO_SPAN
    kind: str = "macro"             # macro turbo
    returns: Type | None = None
    body: "Rule | None" = None

    __hash__ = object.__hash__

    @property
    def qualname(self) -> str:
        return f"{self.module}::{self.name}"

    def __repr__(self) -> str:
        return f"<Rule {self.name}/{len(self.params)}>"


@dataclass(eq=False)
class Var:
    name: str
    type: Type
    span: Span = NO_SPAN
    uid: int = 0

    __hash__ = object.__hash__

    def __repr__(self) -> str:
        return self.name


# ----------------------------------------------------------------- terms
@dataclass(eq=False)
class Term:
    type: Type
    span: Span


@dataclass(eq=False)
class Const(Term):
    value: object


@dataclass(eq=False)
class VarRef(Term):
    var: Var


@dataclass(eq=False)
class Loc(Term):
    """A user function applied: a location read, a static/derived evaluation."""

    func: Function
    args: list[Term]


@dataclass(eq=False)
class Call(Term):
    """A StandardLibrary function applied."""

    name: str
    args: list[Term]
    impl: object
    op: str | None = None          # operator symbol, for printing


@dataclass(eq=False)
class Temporal(Term):
    """A CTL/LTL operator (only meaningful inside a temporal property)."""

    op: str
    args: list[Term]


@dataclass(eq=False)
class StepOp(Term):
    """In a step property: next(t), updated(loc), changed(loc), updatedBy(agent, loc)."""

    op: str
    args: list[Term]


@dataclass(eq=False)
class DomainTerm(Term):
    domain: Type


@dataclass(eq=False)
class Cond(Term):
    cond: Term
    then: Term
    other: Term | None


@dataclass(eq=False)
class Switch(Term):
    subject: Term
    cases: list[tuple[Term, Term]]
    other: Term | None


@dataclass(eq=False)
class Let(Term):
    bindings: list[tuple[Var, Term]]
    body: Term


@dataclass(eq=False)
class Quant(Term):
    kind: str                       # forall exists exists_unique
    bindings: list[tuple[Var, Term]]
    guard: Term | None


@dataclass(eq=False)
class Compr(Term):
    kind: str                       # set seq bag map
    bindings: list[tuple[Var, Term]]
    guard: Term | None
    body: Term
    body2: Term | None = None


@dataclass(eq=False)
class Collection(Term):
    kind: str                       # set seq bag
    items: list[Term]


@dataclass(eq=False)
class Range(Term):
    kind: str
    start: Term
    end: Term
    step: Term | None


@dataclass(eq=False)
class MapLit(Term):
    pairs: list[tuple[Term, Term]]


@dataclass(eq=False)
class TupleLit(Term):
    items: list[Term]


@dataclass(eq=False)
class RuleRef(Term):
    rule: RuleDecl


# ----------------------------------------------------------------- rules
@dataclass(eq=False)
class Rule:
    span: Span


@dataclass(eq=False)
class Skip(Rule):
    pass


@dataclass(eq=False)
class Update(Rule):
    func: Function
    args: list[Term]
    value: Term


@dataclass(eq=False)
class UpdateVar(Rule):
    var: Var
    value: Term


@dataclass(eq=False)
class Block(Rule):
    kind: str                       # par seq
    rules: list[Rule]


@dataclass(eq=False)
class If(Rule):
    cond: Term
    then: Rule
    other: Rule | None


@dataclass(eq=False)
class SwitchRule(Rule):
    subject: Term
    cases: list[tuple[Term, Rule]]
    other: Rule | None


@dataclass(eq=False)
class LetRule(Rule):
    bindings: list[tuple[Var, Term]]
    body: Rule


@dataclass(eq=False)
class Choose(Rule):
    bindings: list[tuple[Var, Term]]
    guard: Term | None
    body: Rule
    ifnone: Rule | None


@dataclass(eq=False)
class Forall(Rule):
    bindings: list[tuple[Var, Term]]
    guard: Term | None
    body: Rule


@dataclass(eq=False)
class Extend(Rule):
    domain: Type
    vars: list[Var]
    body: Rule


@dataclass(eq=False)
class CallRule(Rule):
    rule: RuleDecl
    args: list[Term]
    turbo: bool


@dataclass(eq=False)
class TurboReturn(Rule):
    target: Rule                    # an Update or UpdateVar whose value is filled by the call
    call: CallRule


@dataclass(eq=False)
class TermCall(Rule):
    term: Term
    args: list[Term]


@dataclass(eq=False)
class Loop(Rule):
    kind: str                       # iterate while whilerec
    cond: Term | None
    body: Rule


@dataclass(eq=False)
class LocalRule(Rule):
    func: Function
    init: Rule
    body: Rule


# ----------------------------------------------------------------- properties and the spec
@dataclass(eq=False)
class Property:
    kind: str                       # invariant ctl ltl invar justice compassion step
    name: str
    body: Term
    span: Span
    body2: Term | None = None
    over: list[str] = field(default_factory=list)
    source: str = "spec"            # spec, or the property file it came from
    expect: str | None = None       # "violated" for seeded-bug specs


@dataclass(eq=False)
class AgentInit:
    domain: Type
    rule: RuleDecl
    args: list[Term]
    span: Span


@dataclass(eq=False)
class InitState:
    name: str
    default: bool
    domains: list[tuple[Type, Term]]
    functions: list[tuple[Function, list[Var], Term, Span]]
    agents: list[AgentInit]
    span: Span


@dataclass(eq=False)
class Spec:
    name: str
    path: str
    asyncr: bool
    functions: list[Function]          # every user function of the spec and its imports
    domains: list[Type]                # every declared domain (enum, abstract, subset)
    rules: list[RuleDecl]
    main: RuleDecl | None
    inits: list[InitState]
    properties: list[Property]
    modules: list[str] = field(default_factory=list)
    static_elements: dict = field(default_factory=dict)   # abstract Domain -> [AbstractValue]
    self_func: Function | None = None
    result_func: Function | None = None
    scope: object = None
    # functions declared by `local` rules: numbered after ``functions``; they hold values only
    # within the step that runs the rule, never in a state
    local_functions: list[Function] = field(default_factory=list)

    @property
    def default_init(self) -> InitState | None:
        for i in self.inits:
            if i.default:
                return i
        return None


# ----------------------------------------------------------------- the rule call graph
def called_rules(rule: "Rule | Term | None") -> list[RuleDecl]:
    """The rule declarations a rule (or term) calls, in order of appearance, each once:
    ``r[...]`` and ``r(...)`` calls, and rules written as terms (``<<r>>``, conservatively)."""
    out: list[RuleDecl] = []
    seen: set[int] = set()
    todo: list = [rule]
    while todo:
        x = todo.pop()
        if isinstance(x, (CallRule, RuleRef)):
            if id(x.rule) not in seen:
                seen.add(id(x.rule))
                out.append(x.rule)
            if isinstance(x, CallRule):
                todo.extend(reversed(x.args))
            continue
        if isinstance(x, (Rule, Term)):
            todo.extend(reversed([v for k, v in vars(x).items() if k not in ("span", "type")]))
        elif isinstance(x, (list, tuple)):
            todo.extend(reversed(x))
        # RuleDecl, Function, Var, types and values are not entered
    return out


def recursive_rules(rules: list[RuleDecl]) -> list[RuleDecl]:
    """The rules that can call themselves, directly or through other rules (the rules of a
    cycle of the call graph), in the order of ``rules``.  Iterative (Tarjan), linear."""
    edges = {id(r): [c for c in called_rules(r.body)] for r in rules}
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    on_stack: set[int] = set()
    stack: list[RuleDecl] = []
    cyclic: set[int] = set()
    counter = 0
    for root in rules:
        if id(root) in index:
            continue
        work = [(root, 0)]
        while work:
            node, i = work.pop()
            nid = id(node)
            if i == 0:
                index[nid] = low[nid] = counter
                counter += 1
                stack.append(node)
                on_stack.add(nid)
            succ = edges.get(nid, [])
            if i < len(succ):
                work.append((node, i + 1))
                nxt = succ[i]
                if id(nxt) not in index:
                    work.append((nxt, 0))
                elif id(nxt) in on_stack:
                    low[nid] = min(low[nid], index[id(nxt)])
                continue
            if low[nid] == index[nid]:
                comp = []
                while True:
                    w = stack.pop()
                    on_stack.discard(id(w))
                    comp.append(w)
                    if w is node:
                        break
                if len(comp) > 1 or any(c is node for c in edges.get(nid, [])):
                    cyclic.update(id(c) for c in comp)
            if work:
                parent = work[-1][0]
                low[id(parent)] = min(low[id(parent)], low[nid])
    return [r for r in rules if id(r) in cyclic]
