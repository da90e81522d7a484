"""Static questions about IR terms and rules, shared by the engines and the properties."""
from __future__ import annotations


from ..errors import AsmRuntimeError
from . import ir
from . import types as T
from .values import (MapV, SetV)


def hkey(v):
    """A hashable stand-in for a value that keeps True apart from 1."""
    return (type(v) is bool, v)



def ordered(coll, span, var: str = "") -> list:
    if coll is None:
        # ASMETA's simulator stops here too (its evaluation of the range is not a collection)
        raise AsmRuntimeError(span, f"the range of {var} is undef" if var else "the range is undef")
    if isinstance(coll, SetV):
        return coll.ordered()
    if isinstance(coll, MapV):
        return [k for k, _ in coll]
    return list(coll)



def is_constant(t: ir.Term) -> bool:
    """A term with no variables and no dynamic function: its value never changes."""
    if isinstance(t, ir.Const):
        return True
    if isinstance(t, (ir.Collection, ir.TupleLit)):
        return all(is_constant(x) for x in t.items)
    if isinstance(t, ir.Range):
        return is_constant(t.start) and is_constant(t.end) and (t.step is None or is_constant(t.step))
    if isinstance(t, ir.Call) and t.name not in ("program",):
        return all(is_constant(x) for x in t.args)
    return False



def ir_nodes(roots):
    """Every IR term and rule under ``roots`` (a list of them), each once, parents first."""
    seen: set = set()
    stack = list(reversed(list(roots)))
    while stack:
        x = stack.pop()
        if isinstance(x, (ir.Term, ir.Rule)):
            if id(x) in seen:
                continue
            seen.add(id(x))
            yield x
            stack.extend(reversed(list(vars(x).values())))
        elif isinstance(x, (list, tuple)):
            stack.extend(reversed(x))


def free_uids(t) -> set:
    out = set()

    def walk(x):
        if isinstance(x, ir.VarRef):
            out.add(x.var.uid)
        if isinstance(x, (ir.Term, ir.Rule)):
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
    walk(t)
    return out



def abstract_codomain(f: ir.Function) -> bool:
    c = f.codomain
    return isinstance(c, T.Domain) and isinstance(T.root(c), T.Domain) and T.root(c).kind == "abstract"



def is_subdomain(d: T.Type, of: T.Type) -> bool:
    seen = 0
    while isinstance(d, T.Domain) and seen < 50:
        if d is of:
            return True
        if d.kind != "subset" or d.base is None:
            return False
        d = d.base
        seen += 1
    return d is of



def is_simple(t: ir.Term) -> bool:
    """Terms whose value cannot change within a step: constants and variables."""
    return isinstance(t, (ir.Const, ir.VarRef, ir.RuleRef, ir.DomainTerm)) or (
        isinstance(t, ir.Loc) and t.func.kind == "static" and all(is_simple(a) for a in t.args))



def has_sequencing(rd: ir.RuleDecl, seen=None) -> bool:
    """Could the body see a location change mid-step (seq, loops, nested calls that do)?"""
    seen = set() if seen is None else seen
    if rd in seen:
        return False
    seen.add(rd)
    found = False

    def walk(x):
        nonlocal found
        if found:
            return
        if isinstance(x, ir.Block) and x.kind == "seq" or isinstance(x, (ir.Loop, ir.LocalRule)):
            found = True
            return
        if isinstance(x, ir.CallRule):
            if has_sequencing(x.rule, seen):
                found = True
                return
        if isinstance(x, ir.TermCall):
            found = True
            return
        if isinstance(x, ir.Rule):
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
    walk(rd.body)
    return found



def mentions_monitored(t: ir.Term, seen=None) -> bool:
    seen = set() if seen is None else seen
    found = False

    def walk(x):
        nonlocal found
        if found:
            return
        if isinstance(x, ir.Loc):
            f = x.func
            if f.kind == "monitored":
                found = True
                return
            if f.body is not None and f not in seen:
                seen.add(f)
                walk(f.body)
        if isinstance(x, ir.Term):
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
    walk(t)
    return found




def infinite_ranges(t, bounded_ints: bool = False) -> list:
    """The ranges of quantifiers, comprehensions and choose terms in ``t`` (and in the definitions
    of the functions it reads) that are a whole infinite domain (Integer, Natural, Real, String):
    [(range term, domain)].  With ``bounded_ints``, Integer and Natural count as bounded."""
    infinite = {T.REAL, T.STRING} | (set() if bounded_ints else {T.INTEGER, T.NATURAL})
    out = []
    seen_funcs: set = set()
    seen: set = set()

    def walk(x):
        if isinstance(x, (ir.Term, ir.Rule)):
            if id(x) in seen:
                return
            seen.add(id(x))
            if isinstance(x, ir.Loc) and x.func.body is not None and x.func not in seen_funcs:
                seen_funcs.add(x.func)
                walk(x.func.body)
            for _, rg in getattr(x, "bindings", None) or ():
                if isinstance(rg, ir.DomainTerm) and rg.domain in infinite:
                    out.append((rg, rg.domain))
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
    walk(t)
    return out



def reads_functions(t) -> set:
    """The indexes of the functions a term reads (through the definitions of the derived and
    static functions it reads)."""
    out: set = set()
    seen_funcs: set = set()
    seen: set = set()

    def walk(x):
        if isinstance(x, (ir.Term, ir.Rule)):
            if id(x) in seen:
                return
            seen.add(id(x))
            if isinstance(x, ir.Loc):
                out.add(x.func.index)
                if x.func.body is not None and x.func not in seen_funcs:
                    seen_funcs.add(x.func)
                    walk(x.func.body)
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
    walk(t)
    return out
