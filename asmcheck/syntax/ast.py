"""Syntax tree of an AsmetaL file, as built from the lark parse tree.

Names are not resolved here; :mod:`asmcheck.semantics.resolve` turns this
tree into the typed IR.  Every node keeps the :class:`~asmcheck.errors.Span`
of the text it came from.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import Span


@dataclass(slots=True, eq=False)
class Node:
    span: Span


# ----------------------------------------------------------------- types
@dataclass(slots=True, eq=False)
class TypeExpr(Node):
    """A domain written in a signature: ``D``, ``Seq(D)``, ``Prod(A, B)``, ``Rule(D)``..."""

    name: str                      # domain name, or Prod/Seq/Powerset/Bag/Map/Rule
    args: list["TypeExpr"] = field(default_factory=list)
    structured: bool = False

    def __str__(self) -> str:
        if not self.structured:
            return self.name
        if self.name == "Rule" and not self.args:
            return "Rule"
        return f"{self.name}({', '.join(str(a) for a in self.args)})"


# ----------------------------------------------------------------- terms
class Term(Node):
    __slots__ = ()


@dataclass(slots=True, eq=False)
class Const(Term):
    kind: str       # int nat real char string bool undef
    value: object
    text: str


@dataclass(slots=True, eq=False)
class EnumLit(Term):
    name: str


@dataclass(slots=True, eq=False)
class VarRef(Term):
    name: str


@dataclass(slots=True, eq=False)
class Apply(Term):
    """``f``, ``f(a, b)``, an operator (``a + b`` is ``plus(a, b)``), ``agent.f``."""

    name: str
    args: list[Term] | None      # None: written without parentheses
    op: str | None = None        # operator symbol when written infix/prefix
    agent: str | None = None
    name_span: Span | None = None


@dataclass(slots=True, eq=False)
class DomainRef(Term):
    type: TypeExpr


@dataclass(slots=True, eq=False)
class TupleTerm(Term):
    items: list[Term]


@dataclass(slots=True, eq=False)
class CondTerm(Term):
    cond: Term
    then: Term
    other: Term | None


@dataclass(slots=True, eq=False)
class SwitchTerm(Term):
    subject: Term
    cases: list[tuple[Term, Term]]
    otherwise: Term | None


@dataclass(slots=True, eq=False)
class LetTerm(Term):
    bindings: list[tuple[str, Span, Term]]
    body: Term


@dataclass(slots=True, eq=False)
class Binding(Node):
    var: str
    range: Term


@dataclass(slots=True, eq=False)
class QuantTerm(Term):
    kind: str                   # forall exists exists_unique
    bindings: list[Binding]
    guard: Term | None


@dataclass(slots=True, eq=False)
class CollectionTerm(Term):
    kind: str                   # seq set bag
    items: list[Term]


@dataclass(slots=True, eq=False)
class RangeTerm(Term):
    kind: str                   # seq set bag
    start: Term
    end: Term
    step: Term | None


@dataclass(slots=True, eq=False)
class MapTerm(Term):
    pairs: list[tuple[Term, Term]]


@dataclass(slots=True, eq=False)
class ComprTerm(Term):
    kind: str                   # seq set bag map
    bindings: list[Binding]
    guard: Term | None
    body: Term
    body2: Term | None = None   # the value of a map comprehension


@dataclass(slots=True, eq=False)
class RuleAsTerm(Term):
    name: str
    types: list[TypeExpr]


# ----------------------------------------------------------------- rules
class Rule(Node):
    __slots__ = ()


@dataclass(slots=True, eq=False)
class SkipRule(Rule):
    pass


@dataclass(slots=True, eq=False)
class UpdateRule(Rule):
    location: Term              # Apply or VarRef
    value: Term


@dataclass(slots=True, eq=False)
class BlockRule(Rule):
    kind: str                   # par seq
    rules: list[Rule]


@dataclass(slots=True, eq=False)
class IfRule(Rule):
    cond: Term
    then: Rule
    other: Rule | None


@dataclass(slots=True, eq=False)
class SwitchRule(Rule):
    subject: Term
    cases: list[tuple[Term, Rule]]
    otherwise: Rule | None


@dataclass(slots=True, eq=False)
class LetRule(Rule):
    bindings: list[tuple[str, Span, Term]]
    body: Rule


@dataclass(slots=True, eq=False)
class ChooseRule(Rule):
    bindings: list[Binding]
    guard: Term | None
    body: Rule
    ifnone: Rule | None


@dataclass(slots=True, eq=False)
class ForallRule(Rule):
    bindings: list[Binding]
    guard: Term | None
    body: Rule


@dataclass(slots=True, eq=False)
class ExtendRule(Rule):
    domain: str
    domain_span: Span
    vars: list[tuple[str, Span]]
    body: Rule


@dataclass(slots=True, eq=False)
class CallRule(Rule):
    """``r_x[a, b]`` (macro) or ``r_x(a, b)`` (turbo)."""

    name: str
    args: list[Term]
    turbo: bool


@dataclass(slots=True, eq=False)
class TurboReturnRule(Rule):
    location: Term
    call: CallRule


@dataclass(slots=True, eq=False)
class TermCallRule(Rule):
    """A rule-valued term applied: ``f(p)[$c]`` or ``$r[]``."""

    term: Term
    args: list[Term]


@dataclass(slots=True, eq=False)
class LoopRule(Rule):
    kind: str                   # iterate while whilerec
    cond: Term | None
    body: Rule


@dataclass(slots=True, eq=False)
class LocalRule(Rule):
    decl: "FunctionDecl"
    init: Rule
    body: Rule


# ----------------------------------------------------------------- declarations
@dataclass(slots=True, eq=False)
class DomainDecl(Node):
    name: str
    kind: str                   # subset abstract enum basic any structured
    dynamic: bool = False
    base: TypeExpr | None = None
    elements: list[tuple[str, Span]] = field(default_factory=list)


@dataclass(slots=True, eq=False)
class FunctionDecl(Node):
    name: str
    kind: str                   # static derived controlled monitored shared out local
    dynamic: bool
    domain: TypeExpr | None
    codomain: TypeExpr


@dataclass(slots=True, eq=False)
class Formal(Node):
    name: str
    type: TypeExpr


@dataclass(slots=True, eq=False)
class DomainDef(Node):
    name: str
    body: Term


@dataclass(slots=True, eq=False)
class FunctionDef(Node):
    name: str
    params: list[Formal]
    body: Term
    name_span: Span | None = None


@dataclass(slots=True, eq=False)
class RuleDecl(Node):
    name: str
    params: list[Formal]
    body: Rule
    kind: str = "macro"         # macro turbo
    returns: TypeExpr | None = None


@dataclass(slots=True, eq=False)
class OverItem(Node):
    name: str
    type: TypeExpr | None = None
    has_parens: bool = False


@dataclass(slots=True, eq=False)
class Property(Node):
    kind: str                   # invariant ctl ltl invar justice compassion
    name: str | None
    body: Term
    body2: Term | None = None   # the second formula of COMPASSION
    over: list[OverItem] = field(default_factory=list)


@dataclass(slots=True, eq=False)
class AgentInit(Node):
    domain: str
    program: CallRule


@dataclass(slots=True, eq=False)
class InitBlock(Node):
    name: str
    default: bool
    domains: list[DomainDef]
    functions: list[FunctionDef]
    agents: list[AgentInit]


@dataclass(slots=True, eq=False)
class Import(Node):
    path: str
    names: list[tuple[str, Span]] | None


@dataclass(slots=True, eq=False)
class Spec(Node):
    name: str
    is_module: bool
    asyncr: bool
    imports: list[Import]
    export: list[tuple[str, Span]] | None     # None: nothing exported
    export_all: bool
    domains: list[DomainDecl]
    functions: list[FunctionDecl]
    domain_defs: list[DomainDef]
    function_defs: list[FunctionDef]
    rules: list[RuleDecl]
    properties: list[Property]
    main: RuleDecl | None
    inits: list[InitBlock]
    name_span: Span | None = None
