"""The rule tree of a spec unfolded from its main rule, as AsmetaSMV unfolds it.

* every rule occurrence reachable from the main rule (blocks, skips, updates, macro calls and
  the bodies they call, the programs of the agents);
* the *referenced locations*: the locations denoted by the location terms of those rules
  (read or written) when each logical variable ranges over its whole domain, guards ignored;
  a macro parameter ranges over the values of its arguments; a location read by a derived
  function is referenced where that derived location is read.  Each referenced location
  records the rule occurrences whose evaluation reads or writes it;
* how often each declared rule is called while unfolding the main rule (calls in
  unreachable code count; under ``forall``/``choose`` once per element of the domain).
"""
from __future__ import annotations

import itertools
from collections import defaultdict

from ..errors import AsmError, NO_SPAN
from ..semantics import ir
from ..semantics import types as T
from ..semantics.analysis import free_uids
from ..semantics.choice import Chooser
from ..semantics.terms import Ctx

MAX_COMBOS = 4096
MAX_LOCATIONS = 20_000


class Unfolding:
    def __init__(self, machine):
        self.m = machine
        self.spec = machine.spec
        self.nodes: list = []                 # rule occurrences in unfolding order (each once)
        self._node_ids: dict = {}
        self.decl_of: dict = {}               # node -> the RuleDecl whose body holds it (None: main)
        self.refs: dict = defaultdict(set)    # location key -> rule nodes evaluating it
        self.written: dict = defaultdict(set)  # location key -> update nodes (may) writing it
        self.calls: dict = defaultdict(int)   # RuleDecl -> calls while unfolding
        self._closed_cache: dict = {}
        self._walked: set = set()
        self._derived_seen: set = set()
        self.ctx = Ctx(machine, {}, Chooser())
        self._stack: list = []
        self.run()

    # ------------------------------------------------------------------ values
    def values_of_type(self, t):
        try:
            return list(self.m.domain_values(t, self.ctx, NO_SPAN))
        except AsmError:
            return None

    def closed(self, t) -> bool:
        """No dynamic location is read (variables are fine): the term can be evaluated per binding."""
        c = self._closed_cache.get(t)
        if c is not None:
            return c
        ok = True

        def walk(x):
            nonlocal ok
            if not ok:
                return
            if isinstance(x, ir.Loc):
                f = x.func
                if f.kind not in ("static",) or (f.body is None and not (f.arity == 0)):
                    ok = False
                    return
                if f.body is not None and f not in seen:
                    seen.add(f)
                    walk(f.body)
            if isinstance(x, ir.Call) and x.name in ("program",):
                ok = False
                return
            if isinstance(x, ir.Term):
                for v in vars(x).values():
                    walk(v)
            elif isinstance(x, (list, tuple)):
                for v in x:
                    walk(v)
        seen: set = set()
        walk(t)
        self._closed_cache[t] = ok
        return ok

    def term_values(self, t, env: dict, want_type=None):
        """The possible values of term ``t`` (a list), or None when they cannot be enumerated."""
        if self.closed(t):
            uids = [u for u in free_uids(t) if u in env]
            if any(env[u] is None for u in uids):
                return self.values_of_type(want_type or t.type)
            combos = 1
            for u in uids:
                combos *= max(1, len(env[u]))
            if combos <= MAX_COMBOS:
                fn = self.m.term(t)
                out = []
                seen = set()
                for combo in itertools.product(*[env[u] for u in uids]):
                    self.ctx.env = dict(zip(uids, combo))
                    try:
                        v = fn(self.ctx)
                    except Exception:
                        return self.values_of_type(want_type or t.type)
                    k = (type(v) is bool, v) if _hashable(v) else repr(v)
                    if k not in seen:
                        seen.add(k)
                        out.append(v)
                self.ctx.env = {}
                return out
        return self.values_of_type(want_type or t.type)

    def range_values(self, rng, var, env):
        if isinstance(rng, ir.DomainTerm):
            return self.values_of_type(rng.domain)
        vals = self.term_values(rng, env) if self.closed(rng) else None
        if vals is not None and len(vals) == 1:
            coll = vals[0]
            try:
                from ..semantics.analysis import ordered
                return list(ordered(coll, NO_SPAN))
            except Exception:
                pass
        return self.values_of_type(var.type)

    # ------------------------------------------------------------------ locations
    def loc_keys(self, t: ir.Loc, env: dict) -> list:
        f = t.func
        if not t.args:
            return [f.index]
        uids = sorted(set().union(*[free_uids(a) for a in t.args]) & set(env))
        correlated = all(self.closed(a) for a in t.args) and all(env[u] is not None for u in uids)
        if correlated:
            combos = 1
            for u in uids:
                combos *= max(1, len(env[u]))
            if combos <= MAX_COMBOS:
                fns = [self.m.term(a) for a in t.args]
                out = []
                seen = set()
                for combo in itertools.product(*[env[u] for u in uids]):
                    self.ctx.env = dict(zip(uids, combo))
                    try:
                        args = tuple(fn(self.ctx) for fn in fns)
                    except Exception:
                        continue
                    if args not in seen:
                        seen.add(args)
                        out.append((f.index, args))
                self.ctx.env = {}
                return out
        per = []
        for a, dt in zip(t.args, f.domain):
            vals = self.term_values(a, env, dt)
            if vals is None:
                return []
            per.append(vals)
        n = 1
        for p in per:
            n *= max(1, len(p))
        if n > MAX_LOCATIONS:
            return []
        return [(f.index, tuple(c)) for c in itertools.product(*per)]

    def scan_term(self, t, env: dict, node) -> None:
        """Record the locations term ``t`` reads, as read by rule occurrence ``node``."""
        if t is None:
            return
        if isinstance(t, ir.Loc):
            f = t.func
            if f is not self.spec.self_func and not (f.kind == "static" and f.arity == 0 and f.body is None):
                keys = self.loc_keys(t, env)
                for k in keys:
                    self.refs[k].add(node)
                if f.body is not None and f.kind in ("derived", "static"):
                    for k in keys:
                        if (k, node) in self._derived_seen:
                            continue
                        self._derived_seen.add((k, node))
                        args = () if type(k) is int else k[1]
                        benv = {p.uid: [v] for p, v in zip(f.params or [], args)}
                        self.scan_term(f.body, benv, node)
        if isinstance(t, (ir.Quant, ir.Compr, ir.Let)):
            env = dict(env)
            for v, rng in t.bindings:
                if isinstance(t, ir.Let):
                    env[v.uid] = self.term_values(rng, env)
                else:
                    env[v.uid] = self.range_values(rng, v, env)
        for name, v in vars(t).items():
            if name in ("type", "span", "func", "impl"):
                continue
            if isinstance(v, ir.Term):
                self.scan_term(v, env, node)
            elif isinstance(v, (list, tuple)):
                for x in v:
                    if isinstance(x, ir.Term):
                        self.scan_term(x, env, node)
                    elif isinstance(x, tuple):
                        for y in x:
                            if isinstance(y, ir.Term):
                                self.scan_term(y, env, node)

    # ------------------------------------------------------------------ rules
    def add_node(self, r, decl):
        if id(r) not in self._node_ids:
            self._node_ids[id(r)] = len(self.nodes)
            self.nodes.append(r)
            self.decl_of[r] = decl

    def walk(self, r, env: dict, mult: int, decl) -> None:
        if r is None:
            return
        self.add_node(r, decl)
        if isinstance(r, ir.Update):
            for k in self.loc_keys(ir.Loc(r.func.codomain, r.span, r.func, r.args), env):
                self.refs[k].add(r)
                self.written[k].add(r)
            for a in r.args:
                self.scan_term(a, env, r)
            self.scan_term(r.value, env, r)
        elif isinstance(r, ir.UpdateVar):
            self.scan_term(r.value, env, r)
        elif isinstance(r, ir.Block):
            for x in r.rules:
                self.walk(x, env, mult, decl)
        elif isinstance(r, ir.If):
            self.scan_term(r.cond, env, r)
            self.walk(r.then, env, mult, decl)
            self.walk(r.other, env, mult, decl)
        elif isinstance(r, ir.SwitchRule):
            self.scan_term(r.subject, env, r)
            for c, b in r.cases:
                self.scan_term(c, env, r)
                self.walk(b, env, mult, decl)
            self.walk(r.other, env, mult, decl)
        elif isinstance(r, ir.LetRule):
            env = dict(env)
            for v, x in r.bindings:
                self.scan_term(x, env, r)
                env[v.uid] = self.term_values(x, env)
            self.walk(r.body, env, mult, decl)
        elif isinstance(r, (ir.Choose, ir.Forall)):
            env = dict(env)
            n = 1
            for v, rng in r.bindings:
                self.scan_term(rng, env, r)
                vals = self.range_values(rng, v, env)
                env[v.uid] = vals
                n *= len(vals) if vals is not None else 1
            self.scan_term(r.guard, env, r)
            self.walk(r.body, env, mult * n, decl)
            if isinstance(r, ir.Choose):
                self.walk(r.ifnone, env, mult, decl)
        elif isinstance(r, ir.Extend):
            env = dict(env)
            for v in r.vars:
                env[v.uid] = None
            self.walk(r.body, env, mult, decl)
        elif isinstance(r, ir.CallRule):
            rd = r.rule
            self.calls[rd] += mult
            benv = {}
            for p, a in zip(rd.params, r.args):
                self.scan_term(a, env, r)
                benv[p.uid] = self.term_values(a, env, p.type) if not isinstance(a, ir.VarRef) or \
                    a.var.uid not in env else env[a.var.uid]
            key = (rd, tuple((u, _freeze(v)) for u, v in sorted(benv.items())))
            if rd in self._stack or key in self._walked:
                # recursion, or the same call already unfolded: count the calls inside once more
                if rd not in self._stack:
                    self._count_calls(rd.body, mult)
                return
            self._walked.add(key)
            self._stack.append(rd)
            try:
                self.walk(rd.body, benv, mult, rd)
            finally:
                self._stack.pop()
        elif isinstance(r, ir.TurboReturn):
            self.walk(r.call, env, mult, decl)
            self.walk(r.target, env, mult, decl)
        elif isinstance(r, ir.TermCall):
            self.scan_term(r.term, env, r)
            for a in r.args:
                self.scan_term(a, env, r)
            for rd in self._rule_values():
                if rd not in self._stack:
                    self.calls[rd] += mult
                    key = (rd, "termcall")
                    if key in self._walked:
                        continue
                    self._walked.add(key)
                    self._stack.append(rd)
                    try:
                        self.walk(rd.body, {p.uid: self.values_of_type(p.type) for p in rd.params}, mult, rd)
                    finally:
                        self._stack.pop()
        elif isinstance(r, ir.Loop):
            self.scan_term(r.cond, env, r)
            self.walk(r.body, env, mult, decl)
        elif isinstance(r, ir.LocalRule):
            self.walk(r.init, env, mult, decl)
            self.walk(r.body, env, mult, decl)

    def _count_calls(self, r, mult) -> None:
        def walk(x, mult):
            if isinstance(x, ir.CallRule):
                self.calls[x.rule] += mult
                return
            if isinstance(x, (ir.Choose, ir.Forall)):
                n = 1
                for v, _ in x.bindings:
                    vals = self.values_of_type(v.type)
                    n *= len(vals) if vals else 1
                walk(x.body, mult * n)
                if isinstance(x, ir.Choose) and x.ifnone is not None:
                    walk(x.ifnone, mult)
                return
            if isinstance(x, ir.Rule):
                for v in vars(x).values():
                    walk(v, mult)
            elif isinstance(x, (list, tuple)):
                for v in x:
                    walk(v, mult)
        walk(r, mult)

    def _rule_values(self) -> list:
        """The rules a rule-valued term may run: the agents' programs and every rule named as a value."""
        out = []
        init = self.spec.default_init
        if init is not None:
            for ag in init.agents:
                if ag.rule not in out:
                    out.append(ag.rule)

        def walk(x, seen):
            if id(x) in seen:
                return
            seen.add(id(x))
            if isinstance(x, ir.RuleRef) and x.rule not in out:
                out.append(x.rule)
            if isinstance(x, (ir.Term, ir.Rule)):
                for v in vars(x).values():
                    walk(v, seen)
            elif isinstance(x, (list, tuple)):
                for v in x:
                    walk(v, seen)
        seen: set = set()
        for rd in self.spec.rules:
            walk(rd.body, seen)
        for f in self.spec.functions:
            if f.body is not None:
                walk(f.body, seen)
        return out

    def run(self) -> None:
        main = self.spec.main
        if main is None:
            return
        self._stack.append(main)
        self.walk(main.body, {}, 1, None)
        self._stack.pop()


def _hashable(v) -> bool:
    try:
        hash(v)
        return True
    except TypeError:
        return False


def _freeze(vals):
    if vals is None:
        return None
    out = []
    for v in vals:
        out.append((type(v) is bool, v) if _hashable(v) else repr(v))
    return tuple(out)
