"""Rules: the compilation of IR rules into closures that build update sets (mixed into :class:`Machine`)."""
from __future__ import annotations


from ..errors import AsmError, AsmRuntimeError
from . import ir
from . import types as T
from .state import UpdateSet, apply_in_place, dom_key, same_value
from .values import (RuleValue, fresh_value, show)
from .analysis import has_sequencing, hkey, is_simple, mentions_monitored
from .choice import NO_VALUE, Chooser, Prune, next_prefix
from .terms import MISSING, Ctx, Thunk


MAX_LOOP = 10_000


class RuleExecutor:
    """Compiles IR rules into closures ``fn(ctx) -> UpdateSet``; mixed into :class:`Machine`."""

    # -------------------------------------------------------------- rules
    def rule_fn(self, rd: ir.RuleDecl):
        """The compiled body of a declared rule (compiled once, recursion allowed)."""
        fn = self._rule_cache.get(rd)
        if fn is None:
            holder = {}
            self._rule_cache[rd] = lambda ctx, ups: holder["f"](ctx, ups)
            try:
                compiled = self.rule(rd.body)
            except BaseException:
                # (a body too deep for this thread's stack is compiled again on a deeper one)
                del self._rule_cache[rd]
                raise
            name = rd.name

            def run(ctx, ups):
                saved = ctx.rule
                ctx.rule = name
                try:
                    compiled(ctx, ups)
                finally:
                    ctx.rule = saved
            holder["f"] = run
            self._rule_cache[rd] = run
            fn = run
        return fn

    def rule(self, r: ir.Rule):
        fn = getattr(self, "r_" + type(r).__name__)(r)
        # options["rule_hook"](ir rule, closure) -> closure: observes rule activations (coverage,
        # model review); looked up at compile time only, so it costs nothing when absent
        hook = self.options.get("rule_hook")
        return fn if hook is None else hook(r, fn)

    def r_Skip(self, r):
        return lambda ctx, ups: None

    def r_Update(self, r: ir.Update):
        f = r.func
        idx = f.index
        args = [self.term(a) for a in r.args]
        val = self.term(r.value)
        span = r.span
        machine = self
        check = self._range_check(f, span)
        if not args:
            def upd0(ctx, ups):
                v = val(ctx)
                if check is not None:
                    check(ctx, v)
                if ctx.prune is not None:
                    ctx.prune(idx, v, ctx.depth)
                ups.add(idx, v, span, ctx.self_, ctx.rule, machine)
            return upd0

        def upd(ctx, ups):
            v = val(ctx)
            key = (idx, tuple(a(ctx) for a in args))
            if check is not None:
                check(ctx, v)
            if ctx.prune is not None:
                ctx.prune(key, v, ctx.depth)
            ups.add(key, v, span, ctx.self_, ctx.rule, machine)
        return upd

    def _range_check(self, f: ir.Function, span):
        """Values assigned to a location whose codomain is a finite subset domain must belong to it."""
        cod = f.codomain
        if not (isinstance(cod, T.Domain) and cod.kind == "subset" and cod.definition is not None):
            return None
        machine = self
        cache = {}

        def check(ctx, v):
            if v is None:
                return
            allowed = cache.get("s")
            if allowed is None:
                allowed = set(machine.domain_values(cod, ctx, span))
                cache["s"] = allowed
            if v not in allowed:
                raise AsmRuntimeError(span, f"value out of domain: {show(v)} is not in {cod.name} "
                                            f"(the codomain of {f.name})")
        return check

    def r_UpdateVar(self, r: ir.UpdateVar):
        uid = r.var.uid
        val = self.term(r.value)
        span = r.span
        machine = self

        def updvar(ctx, ups):
            cur = ctx.env.get(uid)
            v = val(ctx)
            if type(cur) is Thunk and cur.loc is not None:
                # a macro parameter bound to a location: update that location
                idx, argfns = cur.loc
                saved_env, saved_self = ctx.env, ctx.self_
                ctx.env, ctx.self_ = cur.env, cur.self_
                try:
                    vals = tuple(a(ctx) for a in argfns)
                finally:
                    ctx.env, ctx.self_ = saved_env, saved_self
                ups.add(idx if not vals else (idx, vals), v, span, ctx.self_, ctx.rule, machine)
                return
            ctx.env[uid] = v
        return updvar

    def r_Block(self, r: ir.Block):
        rules = [self.rule(x) for x in r.rules]
        machine = self
        if r.kind == "par":
            def par(ctx, ups):
                for x in rules:
                    x(ctx, ups)
            return par

        def seq(ctx, ups):
            saved = ctx.st
            work = dict(saved)
            ctx.st = work
            ctx.depth += 1
            local = UpdateSet()
            try:
                for x in rules:
                    sub = UpdateSet()
                    x(ctx, sub)
                    apply_in_place(work, sub, machine.keep_undef)
                    merge_seq(local, sub)
            finally:
                ctx.st = saved
                ctx.depth -= 1
            ups.merge_par(local, machine)
        return seq

    def r_If(self, r: ir.If):
        c = self.term(r.cond)
        a = self.rule(r.then)
        b = self.rule(r.other) if r.other is not None else None
        span = r.cond.span

        def if_(ctx, ups):
            g = c(ctx)
            if g is True:
                a(ctx, ups)
            elif g is False:
                if b is not None:
                    b(ctx, ups)
            else:
                raise AsmRuntimeError(span, "the guard is undef")
        return if_

    def r_SwitchRule(self, r: ir.SwitchRule):
        subj = self.term(r.subject)
        cases = [(self.term(c), self.rule(b)) for c, b in r.cases]
        other = self.rule(r.other) if r.other is not None else None

        def switch(ctx, ups):
            v = subj(ctx)
            for c, b in cases:
                if same_value(v, c(ctx)):
                    b(ctx, ups)
                    return
            if other is not None:
                other(ctx, ups)
        return switch

    def r_LetRule(self, r: ir.LetRule):
        binds = [(v.uid, self.term(x)) for v, x in r.bindings]
        body = self.rule(r.body)

        def let(ctx, ups):
            env = ctx.env
            saved = dict(env)
            try:
                for uid, x in binds:
                    env[uid] = x(ctx)
                body(ctx, ups)
            finally:
                env.clear()
                env.update(saved)
        return let

    def r_Choose(self, r: ir.Choose):
        ranges = self._ranges(r.bindings)
        guard = self.term(r.guard) if r.guard is not None else None
        body = self.rule(r.body)
        ifnone = self.rule(r.ifnone) if r.ifnone is not None else None
        uids = [v.uid for v, _ in r.bindings]
        names = [v.name for v, _ in r.bindings]
        span = r.span
        gspan = r.guard.span if r.guard is not None else r.span
        label = f"choose at {span.short()}"
        machine = self
        dedupe = self.dedupe
        node = object()

        # variables over Integer, Natural or Real: a simulation draws their values (ASMETA's
        # simulator does so when the guard is the constant true), an enumeration cannot
        infinite = [i for i, (_, rg) in enumerate(r.bindings)
                    if isinstance(rg, ir.DomainTerm) and rg.domain in (T.INTEGER, T.NATURAL, T.REAL)]
        draw_choose = self._drawing_choose(r, ranges, guard, body, ifnone, infinite) if infinite else None

        pure = not (r.guard is not None and mentions_monitored(r.guard)) and not any(
            mentions_monitored(rg) for _, rg in r.bindings)
        NONE = ()

        def candidates(ctx):
            cands = []
            if guard is None and len(ranges) == 1:
                return [(x,) for x in ranges[0][1](ctx)]
            for _ in machine._iter_bindings(ctx, ranges):
                if guard is not None:
                    g = guard(ctx)
                    if g is None:
                        raise AsmRuntimeError(gspan, "the choose condition is undef")
                    if not g:
                        continue
                cands.append(tuple(ctx.env[u] for u in uids))
            return cands

        def choose(ctx, ups):
            ch = ctx.chooser
            if draw_choose is not None and draw_choose(ctx, ups):
                return
            if dedupe and ch.enumerates:
                memo = ch.memo
                key = None
                outcomes = None
                if memo is not None and pure and ctx.st is ctx.base:
                    try:
                        key = (node, tuple(ctx.env.items()), tuple(ctx.mon.items()),
                               tuple(ctx.fresh.items()), ctx.self_)
                        outcomes = memo.get(key)
                    except TypeError:
                        key = None
                if outcomes is None:
                    cands = candidates(ctx)
                    outcomes = machine._choose_outcomes(ctx, cands, uids, names, body) if cands else NONE
                    if key is not None:
                        memo[key] = outcomes
                if not outcomes and outcomes is not NONE:
                    raise Prune()
                if outcomes is NONE:
                    if ifnone is not None:
                        ifnone(ctx, ups)
                    return
                if len(outcomes) == 1:
                    i = 0
                else:
                    i = ch.choose("choose", label, [o[3] for o in outcomes])
                    ch.log[-1].nested = outcomes[i][5]
                sub, mon_after, fresh_after, bindings, exc, nested = outcomes[i]
                if exc is not None:
                    raise exc
                ctx.mon = dict(mon_after)
                ctx.fresh = dict(fresh_after)
                ups.merge_par(sub, machine)
                return
            cands = candidates(ctx)
            if not cands:
                if ifnone is not None:
                    ifnone(ctx, ups)
                return
            options = [dict(zip(names, c)) for c in cands]
            i = ch.choose("choose", label, options) if len(cands) > 1 else first_alternative(ctx, label, options)
            env = ctx.env
            saved = {u: env[u] for u in uids if u in env}
            try:
                for u, v in zip(uids, cands[i]):
                    env[u] = v
                body(ctx, ups)
            finally:
                for u in uids:
                    if u in saved:
                        env[u] = saved[u]
                    else:
                        env.pop(u, None)
        return choose

    def _drawing_choose(self, r: ir.Choose, ranges, guard, body, ifnone, infinite):
        """The part of a choose rule over Integer, Natural or Real that draws: returns a function
        ``(ctx, ups) -> bool`` (False when the chooser does not draw, or --int-range bounds the
        integers, so the ordinary enumeration applies)."""
        label = f"choose at {r.span.short()}"
        doms = [r.bindings[i][1].domain for i in infinite]
        names = [r.bindings[i][0].name for i in infinite]
        uids = [r.bindings[i][0].uid for i in infinite]
        rest = [rg for i, rg in enumerate(ranges) if i not in infinite]
        rest_uids = [v.uid for i, (v, _) in enumerate(r.bindings) if i not in infinite]
        rest_names = [v.name for i, (v, _) in enumerate(r.bindings) if i not in infinite]
        true_guard = r.guard is None or (isinstance(r.guard, ir.Const) and r.guard.value is True)
        d0 = doms[0]
        gspan = r.guard.span if r.guard is not None else r.span
        machine = self

        def drawing(ctx, ups):
            if machine.int_range is not None and all(d is not T.REAL for d in doms):
                return False
            ch = ctx.chooser
            if ch.rng is None and type(ch).draw is Chooser.draw and ch.draw_options(d0) is None:
                return False
            env = ctx.env
            saved = {u: env[u] for u in uids + rest_uids if u in env}
            try:
                for u, name, d in zip(uids, names, doms):
                    opts = ch.draw_options(d)
                    if opts is not None:
                        # an enumerating chooser with candidate values (those a transcript shows)
                        v = opts[ch.choose("choose", label, [{name: x} for x in opts])] if len(opts) > 1 \
                            else opts[0]
                    else:
                        v = ch.draw(label, name, d)
                    if v is NO_VALUE:
                        return False
                    if not true_guard:
                        if ch.log and ch.log[-1].label == label:
                            ch.log.pop()        # the value drawn is not used
                        raise AsmRuntimeError(gspan, f"choose over the infinite domain {d} with a guard: ASMETA's "
                                                     f"simulator draws a value only when the guard is true (bound "
                                                     f"the range with a subset domain or an interval)")
                    env[u] = v
                if rest:
                    cands = [tuple(env[u] for u in rest_uids) for _ in machine._iter_bindings(ctx, rest)]
                    if not cands:
                        if ifnone is not None:
                            ifnone(ctx, ups)
                        return True
                    i = ch.choose("choose", label, [dict(zip(rest_names, c)) for c in cands]) \
                        if len(cands) > 1 else 0
                    for u, v in zip(rest_uids, cands[i]):
                        env[u] = v
                body(ctx, ups)
            finally:
                for u in uids + rest_uids:
                    if u in saved:
                        env[u] = saved[u]
                    else:
                        env.pop(u, None)
            return True
        return drawing

    def _choose_outcomes(self, ctx, cands, uids, names, body):
        """The distinct effects of a choose body over all candidates and nested choices:
        [(update set, monitored cache after, fresh counters after, bindings, error, nested log)]."""
        outcomes = []
        seen = {}
        env = ctx.env
        saved_vals = {u: env[u] for u in uids if u in env}
        outer_ch, outer_mon, outer_fresh = ctx.chooser, ctx.mon, ctx.fresh
        try:
            for cand in cands:
                for u, v in zip(uids, cand):
                    env[u] = v
                prefix: list = []
                while True:
                    self.tick()
                    sub_ch = outer_ch.sub(prefix)
                    ctx.chooser = sub_ch
                    ctx.mon = dict(outer_mon)
                    ctx.fresh = dict(outer_fresh)
                    sub = UpdateSet()
                    exc = None
                    pruned = False
                    try:
                        body(ctx, sub)
                    except AsmError as e:
                        exc = e
                    except Prune:
                        pruned = True
                    if pruned:
                        prefix = next_prefix(sub_ch.log)
                        if prefix is None:
                            break
                        continue
                    new_mon = tuple((k, v) for k, v in ctx.mon.items() if k not in outer_mon)
                    if exc is None:
                        key = (frozenset((k, hkey(u.value), u.agent) for k, u in sub.locs.items()),
                               tuple(sub.fresh), new_mon)
                    else:
                        key = ("error", str(exc), new_mon)
                    if key not in seen:
                        seen[key] = len(outcomes)
                        outcomes.append((sub, ctx.mon, ctx.fresh, dict(zip(names, cand)), exc, sub_ch.log))
                    prefix = next_prefix(sub_ch.log)
                    if prefix is None:
                        break
        finally:
            ctx.chooser, ctx.mon, ctx.fresh = outer_ch, outer_mon, outer_fresh
            for u in uids:
                if u in saved_vals:
                    env[u] = saved_vals[u]
                else:
                    env.pop(u, None)
        if not outcomes and ctx.prune is not None:
            raise Prune()
        return outcomes

    def r_Forall(self, r: ir.Forall):
        ranges = self._ranges(r.bindings)
        guard = self.term(r.guard) if r.guard is not None else None
        body = self.rule(r.body)
        gspan = r.guard.span if r.guard is not None else r.span
        machine = self

        def forall(ctx, ups):
            for _ in machine._iter_bindings(ctx, ranges):
                if guard is not None:
                    g = guard(ctx)
                    if g is None:
                        raise AsmRuntimeError(gspan, "the forall condition is undef")
                    if not g:
                        continue
                body(ctx, ups)
        return forall

    def r_Extend(self, r: ir.Extend):
        dom = r.domain
        name = dom.name
        uids = [v.uid for v in r.vars]
        body = self.rule(r.body)
        machine = self

        def extend(ctx, ups):
            env = ctx.env
            saved = {u: env[u] for u in uids if u in env}
            try:
                for u in uids:
                    el = machine.fresh_element(ctx, name)
                    ups.fresh.append((name, el))
                    env[u] = el
                body(ctx, ups)
            finally:
                for u in uids:
                    if u in saved:
                        env[u] = saved[u]
                    else:
                        env.pop(u, None)
        return extend

    def fresh_element(self, ctx: Ctx, domain: str):
        k = ctx.fresh.get(domain)
        if k is None:
            existing = ctx.st.get(dom_key(domain), ())
            k = 1 + max((e.serial for e in existing), default=0)
        ctx.fresh[domain] = k + 1
        return fresh_value(domain, k)

    def r_CallRule(self, r: ir.CallRule):
        rd = r.rule
        args = [self.term(a) for a in r.args]
        uids = [p.uid for p in rd.params]
        machine = self
        by_name = not r.turbo and has_sequencing(rd)
        # how each argument is passed: 0 value, 1 by name, 2 variable (its binding as is),
        # 3 location by name (updatable through the parameter)
        modes = []
        locs = []
        for a in r.args:
            if r.turbo:
                modes.append(0)
                locs.append(None)
            elif isinstance(a, ir.VarRef):
                modes.append(2)
                locs.append(a.var.uid)
            elif isinstance(a, ir.Loc) and a.func.is_location and a.func.kind != "monitored" and not (
                    a.func.kind == "static"):
                modes.append(3)
                locs.append((a.func.index, [self.term(x) for x in a.args]))
            elif (by_name and not is_simple(a)) or mentions_monitored(a):
                # by name: evaluated where the body uses it (a monitored location the body does
                # not read is not read, as in the simulator, which substitutes macro arguments)
                modes.append(1)
                locs.append(None)
            else:
                modes.append(0)
                locs.append(None)
        plan = list(zip(args, modes, locs))
        body_holder = {}

        def call(ctx, ups):
            fn = body_holder.get("f")
            if fn is None:
                fn = machine.rule_fn(rd)
                body_holder["f"] = fn
            vals = []
            env = ctx.env
            for a, mode, extra in plan:
                if mode == 0:
                    vals.append(a(ctx))
                elif mode == 2:
                    v = env.get(extra, MISSING)
                    vals.append(a(ctx) if v is MISSING else v)
                elif mode == 3:
                    vals.append(Thunk(a, env, ctx.self_, extra))
                else:
                    vals.append(Thunk(a, env, ctx.self_))
            saved = ctx.env
            ctx.env = dict(zip(uids, vals))
            try:
                fn(ctx, ups)
            finally:
                ctx.env = saved
        return call

    def r_TurboReturn(self, r: ir.TurboReturn):
        call = self.rule(r.call)
        target = r.target
        res_idx = self.spec.result_func.index
        machine = self
        if isinstance(target, ir.Update):
            f = target.func
            idx = f.index
            args = [self.term(a) for a in target.args]
            span = target.span

            def tret(ctx, ups):
                sub = UpdateSet()
                call(ctx, sub)
                u = sub.locs.get(res_idx)
                v = u.value if u is not None else None
                ups.merge_par(sub, machine)
                key = idx if not args else (idx, tuple(a(ctx) for a in args))
                ups.add(key, v, span, ctx.self_, ctx.rule, machine)
            return tret
        uid = target.var.uid

        def tret_var(ctx, ups):
            sub = UpdateSet()
            call(ctx, sub)
            u = sub.locs.get(res_idx)
            ups.merge_par(sub, machine)
            ctx.env[uid] = u.value if u is not None else None
        return tret_var

    def r_TermCall(self, r: ir.TermCall):
        term = self.term(r.term)
        args = [self.term(a) for a in r.args]
        span = r.span
        machine = self

        def tcall(ctx, ups):
            rv = term(ctx)
            if rv is None:
                raise AsmRuntimeError(span, "the rule to run is undef")
            if not isinstance(rv, RuleValue):
                raise AsmRuntimeError(span, f"{show(rv)} is not a rule")
            rd = rv.rule
            vals = [a(ctx) for a in args] if args else list(rv.args)
            if len(vals) != len(rd.params):
                raise AsmRuntimeError(span, f"{rd.name} takes {len(rd.params)} argument(s), not {len(vals)}")
            saved_env, saved_self = ctx.env, ctx.self_
            ctx.env = dict(zip([p.uid for p in rd.params], vals))
            if rv.agent is not None:
                ctx.self_ = rv.agent
            try:
                machine.rule_fn(rd)(ctx, ups)
            finally:
                ctx.env, ctx.self_ = saved_env, saved_self
        return tcall

    def r_Loop(self, r: ir.Loop):
        cond = self.term(r.cond) if r.cond is not None else None
        body = self.rule(r.body)
        span = r.span
        kind = r.kind

        machine = self

        max_loop = self.max_loop
        tick = self.tick

        def loop(ctx, ups):
            saved = ctx.st
            work = dict(saved)
            ctx.st = work
            ctx.depth += 1
            local = UpdateSet()
            try:
                for _ in range(max_loop):
                    tick()
                    if cond is not None:
                        g = cond(ctx)
                        if g is None:
                            raise AsmRuntimeError(r.cond.span, "the loop condition is undef")
                        if not g:
                            break
                    sub = UpdateSet()
                    body(ctx, sub)
                    if cond is None and all(same_value(work.get(k), u.value)
                                            for k, u in sub.locs.items()) and not sub.fresh:
                        break
                    apply_in_place(work, sub, machine.keep_undef)
                    merge_seq(local, sub)
                else:
                    raise AsmRuntimeError(span, f"the {kind} at {span.short()} did not end after {max_loop} "
                                                f"iterations in one step (raise the bound with --max-loop)")
            finally:
                ctx.st = saved
                ctx.depth -= 1
            ups.merge_par(local, machine)
        return loop

    def r_LocalRule(self, r: ir.LocalRule):
        init = self.rule(r.init)
        body = self.rule(r.body)
        machine = self

        fidx = r.func.index

        def local(ctx, ups):
            saved = ctx.st
            work = dict(saved)
            ctx.st = work
            try:
                sub = UpdateSet()
                init(ctx, sub)
                apply_in_place(work, sub, machine.keep_undef)
                inner = UpdateSet()
                body(ctx, inner)
            finally:
                ctx.st = saved
            # the local function lives within this rule only: its updates stay here
            for k in [k for k in inner.locs if (k if type(k) is int else k[0]) == fidx]:
                del inner.locs[k]
            ups.merge_par(inner, machine)
        return local


def merge_seq(ups: UpdateSet, sub: UpdateSet) -> None:
    ups.locs.update(sub.locs)
    ups.fresh.extend(sub.fresh)



def first_alternative(ctx, label, options):
    return 0

