"""``asmcheck advise``: AsmetaMA's meta-properties, computed exactly over the explored configurations.

The checks and their statuses are those of ASMETA's model advisor (see docs/review.md);
AsmetaMA encodes each as a CTL formula for NuSMV, here each is read off the configurations
(:mod:`.space`) and the rule tree unfolded from the main rule (:mod:`.static`).
"""
from __future__ import annotations

from collections import defaultdict

from .. import __version__
from ..errors import AsmError
from ..semantics import ir
from ..semantics.values import show
from .common import (Sources, add_domain_options, all_locations, machine_options, use_import_path, codomain_values, load_spec, rule_where, user_domains,
                     user_functions)
from .observe import Observations, vkey
from .space import Space
from .static import Unfolding

# (id, check, AsmetaMA's name, MP group used by --mp)
CHECKS = [
    ("MP1", "InconsistentUpdate", "No inconsistent update is ever performed", "1"),
    ("MP2", "CondRuleIsComplete", "Every conditional rule must be complete", "2"),
    ("MP2", "CaseRuleIsComplete", "Every case rule without otherwise must be complete", "2"),
    ("MP3", "ChooseRuleIsEmpty", "Choose rule is always/sometimes/never not empty", "3"),
    ("MP3", "ForallRuleIsEmpty", "Forall rule is always/sometimes/never not empty", "3"),
    ("MP3", "CondRuleEvalToTrue", "Conditional rule eval to true", "3"),
    ("MP4", "TrivialUpdate", "No assignment is always trivial", "4"),
    ("MP5", "DomainAllUsed", "For every domain element e, there exists a location which has value e", "5"),
    ("MP6", "ContrLocTakesEveryValue", "Every controlled location can take any value in its codomain", "6"),
    ("MP7", "LocationCouldBeRemoved", "a location could be removed", "7"),
    ("MP7", "ContrLocIsUpdated", "a controlled location is never updated", "7"),
    ("MP7", "ContrLocCouldBeStatic", "a controlled location could be static", "7"),
    ("MP", "RuleIsReached", "Rule is reached", "rules"),
    ("MP", "MacroCallRuleIsReached", "Macro rule is reached", "rules"),
    ("MP", "MacroRuleCalled", "Macro rule has been called", "rules"),
    ("MP", "StatDerIsUsed", "Derived/Static location/function is used", "rules"),
]

# the statuses that make a check violated
VIOLATING = {
    "inconsistent", "incomplete", "never_executed", "always_empty", "never_then", "never_else",
    "never_then_else", "always_trivial", "could_be_reduced", "unuseful", "could_be_resized", "never_used",
    "initialized_and_never_used", "initialized_but_never_used", "used_only_in_unreachable_code",
    "initialized_but_used_only_in_unreachable_code", "never_updated", "could_be_static", "never_reached",
    "never_called",
}
_DYNAMIC = object()     # stands for the reachable code that reads or writes a location of an extend-made element

# checks a single configuration can prove violated (so they stand on a partial exploration)
EXISTENTIAL = {"InconsistentUpdate", "CondRuleIsComplete", "CaseRuleIsComplete"}


class Review:
    """The explored configurations of one spec and the rule tree, ready for the checks."""

    def __init__(self, spec, options=None, *, max_states=None, max_seconds=None, extra_observer=None,
                 conditions=False):
        self.spec = spec
        self.obs = Observations()
        observer = self.obs
        if extra_observer is not None:
            def observer(c, a=self.obs, b=extra_observer):
                a(c)
                b(c)
        self.space = Space(spec, options, max_states=max_states, max_seconds=max_seconds, observer=observer,
                           conditions=conditions)
        self.space.run(on_state=self.obs.on_state)
        self.m = self.space.machine
        self.unf = Unfolding(self.m)
        self.src = Sources()
        self.refs = self._with_dynamic_locations()

    def _with_dynamic_locations(self) -> dict:
        """The referenced locations, plus the locations of elements ``extend`` made (the unfolding
        cannot name them): each one defined in a reachable state or written counts as referenced
        from reachable code."""
        from ..semantics import types as T
        refs = dict(self.unf.refs)
        dyn = set()
        for f in user_functions(self.spec):
            for t in f.domain:
                r = T.root(t) if isinstance(t, T.Domain) else None
                if isinstance(t, T.Domain) and (t.dynamic or (isinstance(r, T.Domain) and r.dynamic)):
                    dyn.add(f.index)
        if not dyn:
            return refs
        for k in list(self.obs.values) + list(self.obs.written):
            if type(k) is tuple and k[0] in dyn and k not in refs:
                refs[k] = {_DYNAMIC}
        return refs
    @property
    def incomplete(self):
        return self.space.incomplete

    def acts(self, node) -> int:
        if node is _DYNAMIC:
            return 1
        return self.obs.node_configs.get(id(node), 0)

    def loc(self, key) -> str:
        return self.m.location_text(key)

    def where(self, node, **extra):
        return rule_where(node, self.src, **extra)

    def nodes(self, *types):
        return [n for n in self.unf.nodes if isinstance(n, types)]

    def reachable_ref(self, key) -> bool:
        return any(self.acts(n) for n in self.refs.get(key, ()))

    def category(self, f) -> str:
        return f.kind if f.kind != "static" or f.body is not None else "static"

    def initialised(self) -> set:
        init = self.spec.default_init
        return {f for f, *_ in init.functions} if init is not None else set()

    # ------------------------------------------------------------------ the checks
    def _mp1_functions(self):
        """The function names of ``SPEC.forMP1`` beside the spec (one a line), which restrict MP1 to
        those functions as in AsmetaMA; None when there is no such file."""
        from pathlib import Path
        f = Path(self.spec.path).with_suffix(".forMP1")
        if not f.is_file():
            return None
        return {ln.strip() for ln in f.read_text(encoding="utf-8", errors="replace").splitlines() if ln.strip()}

    def InconsistentUpdate(self):
        out = []
        only = self._mp1_functions()
        for key, pairs in sorted(self.obs.clash_pairs.items(), key=lambda kv: self.loc(kv[0])):
            if only is not None and self.m.fname[key if type(key) is int else key[0]] not in only:
                continue
            na, va, nb, vb = self.obs.clash_example[key]
            first, second = sorted([(na.span.line, na.span.col, show(va)), (nb.span.line, nb.span.col, show(vb))])
            out.append({"kind": "location", "location": self.loc(key), "status": "inconsistent",
                        "pairs": len(pairs), "updates": [[first[0], first[2]], [second[0], second[2]]],
                        "category": "controlled"})
        return out

    def CondRuleIsComplete(self):
        out = []
        for n in self.nodes(ir.If):
            ok = n.other is not None or "else" not in self.obs.outcomes.get(id(n), ())
            out.append(self.where(n, status="complete" if ok else "incomplete"))
        return out

    def CaseRuleIsComplete(self):
        out = []
        for n in self.nodes(ir.SwitchRule):
            ok = n.other is not None or "none" not in self.obs.outcomes.get(id(n), ())
            out.append(self.where(n, status="complete" if ok else "incomplete"))
        return out

    def ChooseRuleIsEmpty(self):
        out = []
        for n in self.nodes(ir.Choose):
            seen = self.obs.outcomes.get(id(n), set())
            if not self.acts(n):
                st = "never_executed"
            elif seen == {1}:
                st = "always_not_empty"
            elif 1 in seen:
                st = "sometimes_empty"
            else:
                st = "always_empty"
            out.append(self.where(n, status=st))
        return out

    def ForallRuleIsEmpty(self):
        out = []
        total = self.obs.configs
        for n in self.nodes(ir.Forall):
            k = self.obs.forall_cfg.get(id(n), 0)
            st = "always_not_empty" if total and k == total else "sometimes_empty" if k else "always_empty"
            out.append(self.where(n, status=st))
        return out

    def CondRuleEvalToTrue(self):
        out = []
        for n in self.nodes(ir.If):
            seen = self.obs.outcomes.get(id(n), set())
            no_then = "then" not in seen
            no_else = n.other is not None and "else" not in seen
            st = "never_then_else" if no_then and no_else else "never_then" if no_then else \
                "never_else" if no_else else "ok"
            out.append(self.where(n, status=st))
        return out

    def TrivialUpdate(self):
        out = []
        done = set()
        for inst, (node, key) in self.obs.inst_fired.items():
            if inst in self.obs.inst_nontrivial or (id(node), key) in done:
                continue
            done.add((id(node), key))
            out.append((node.span.line, node.span.col, self.loc(key),
                        self.where(node, location=self.loc(key), status="always_trivial")))
        return [w for *_, w in sorted(out, key=lambda x: x[:3])]

    def DomainAllUsed(self):
        out = []
        m = self.m
        refs = self.refs
        funcs = self.m.functions
        for d in user_domains(self.spec):
            try:
                elems = list(m.domain_values(d, None, d.span))
            except AsmError:
                continue
            if not elems:
                continue
            used = set()
            for key in refs:
                if type(key) is int:
                    f, args = funcs[key], ()
                else:
                    f, args = funcs[key[0]], key[1]
                for t, a in zip(f.domain, args):
                    for e in _parts(t, a, d):
                        used.add(vkey(e))
                if f.codomain is not d and f.kind != "monitored" and _holds(f.codomain, d):
                    for v in self.obs.values_of(key):
                        if v[0] != "repr" and v[1] is not None:
                            used.update(vkey(e) for e in _parts(f.codomain, v[1], d))
                if f.codomain is d:
                    if f.kind == "monitored":
                        used.update(vkey(e) for e in elems)
                    elif f.kind == "static" and f.body is not None:
                        try:
                            used.add(vkey(self._static_value(f, args)))
                        except AsmError:
                            pass
                    else:
                        used.update(self.obs.values_of(key))
            u = [show(e) for e in elems if vkey(e) in used]
            nu = [show(e) for e in elems if vkey(e) not in used]
            st = "all_used" if not nu else "unuseful" if not u else "could_be_reduced"
            w = {"kind": "domain", "domain": d.name, "status": st, "used": u, "unused": nu}
            if d.span is not None and d.span.line:
                w.update({"path": _name(d.span.path), "line": d.span.line, "column": d.span.col})
            out.append(w)
        return out

    def _static_value(self, f, args):
        from ..semantics.terms import Ctx
        from ..semantics.choice import Chooser
        return self.m.term(ir.Loc(f.codomain, f.span, f, [ir.Const(t, f.span, a) for t, a in zip(f.domain, args)]))(
            Ctx(self.m, {}, Chooser()))

    def _controlled(self):
        return [f for f in user_functions(self.spec) if f.kind == "controlled"]

    def ContrLocTakesEveryValue(self):
        out = []
        init = self.initialised()
        for f in self._controlled():
            cod = codomain_values(self.m, f)
            if cod is None:
                continue
            codk = [vkey(v) for v in cod]
            keys = all_locations(self.m, f)
            refd = sorted((k for k in self.refs if (k == f.index if type(k) is int else k[0] == f.index)),
                          key=self.loc)
            union = set()
            locs = []
            for k in refd:
                vals = self.obs.values_of(k) - {(False, None)}
                union |= vals
                if len(vals) < len(set(codk)):
                    locs.append(self._loc_values(k, cod, vals, f))
            for k in (keys or []):
                if k not in self.refs:
                    st = "initialized_and_never_used" if f in init or f.kind == "controlled" else "never_used"
                    locs.append({"kind": "location", "location": self.loc(k), "status": st,
                                 "category": "controlled"})
            if not refd:
                fst = "never_used"
            elif len(union) < len(set(codk)):
                fst = "could_be_resized" if union else "never_used"
            else:
                fst = None
            if fst is not None:
                out.append({"kind": "function", "function": f.name, "status": fst, "category": "controlled",
                            "used": [show(v) for v, k in zip(cod, codk) if k in union],
                            "unused": [show(v) for v, k in zip(cod, codk) if k not in union],
                            "path": _name(f.span.path), "line": f.span.line, "column": f.span.col})
            out.extend(locs)
        return out

    def _loc_values(self, k, cod, vals, f):
        st = "could_be_resized" if vals else "never_used"
        return {"kind": "location", "location": self.loc(k), "status": st, "category": "controlled",
                "used": [show(v) for v in cod if vkey(v) in vals],
                "unused": [show(v) for v in cod if vkey(v) not in vals]}

    def LocationCouldBeRemoved(self):
        out = []
        init = self.initialised()
        for f in user_functions(self.spec):
            if f.kind not in ("controlled", "monitored"):
                continue
            keys = all_locations(self.m, f)
            if keys is None:
                continue
            explicit = f in init
            for k in keys:
                refs = self.refs.get(k)
                if not refs:
                    st = "initialized_but_never_used" if explicit else "never_used"
                elif not self.reachable_ref(k):
                    st = "initialized_but_used_only_in_unreachable_code" if explicit else \
                        "used_only_in_unreachable_code"
                else:
                    continue
                out.append({"kind": "location", "location": self.loc(k), "status": st, "category": f.kind})
        return out

    def ContrLocIsUpdated(self):
        out = []
        for f in self._controlled():
            keys = all_locations(self.m, f)
            if keys is None:
                keys = [k for k in self.refs if (k == f.index if type(k) is int else k[0] == f.index)]
            for k in keys:
                if k not in self.obs.written:
                    out.append({"kind": "location", "location": self.loc(k), "status": "never_updated",
                                "category": "controlled"})
        return out

    def ContrLocCouldBeStatic(self):
        out = []
        for f in self._controlled():
            keys = all_locations(self.m, f)
            refd = sorted((k for k in self.refs if (k == f.index if type(k) is int else k[0] == f.index)),
                          key=self.loc)
            static = [k for k in refd if len(self.obs.values_of(k)) == 1]
            if refd and len(static) == len(refd) and (keys is None or set(keys) <= set(refd)):
                out.append({"kind": "function", "function": f.name, "status": "could_be_static",
                            "category": "controlled", "path": _name(f.span.path), "line": f.span.line,
                            "column": f.span.col})
            for k in sorted(static, key=self.loc):
                (v,) = self.obs.values_of(k)
                out.append({"kind": "location", "location": self.loc(k), "status": "could_be_static",
                            "category": "controlled", "value": show(v[1]) if v[0] != "repr" else v[1]})
        return out

    def RuleIsReached(self, types=None):
        out = []
        total = self.obs.configs
        for n in self.unf.nodes:
            if types is not None and not isinstance(n, types):
                continue
            a = self.acts(n)
            st = "never_reached" if a == 0 else "always_reached" if a == total else "sometimes_reached"
            out.append(self.where(n, status=st))
        return out

    def MacroCallRuleIsReached(self):
        return self.RuleIsReached((ir.CallRule,))

    def MacroRuleCalled(self):
        out = []
        for rd in self.spec.rules:
            if rd is self.spec.main or rd.module in ("StandardLibrary",):
                continue
            n = self.unf.calls.get(rd, 0)
            out.append({"kind": "macro", "macro": rd.name, "status": "called" if n else "never_called",
                        "calls": n, "path": _name(rd.span.path), "line": rd.span.line, "column": rd.span.col})
        return out

    def StatDerIsUsed(self):
        out = []
        for f in user_functions(self.spec):
            if f.kind not in ("derived", "static") or f.body is None:
                continue
            keys = all_locations(self.m, f)
            if keys is None:
                continue
            sts = []
            locs = []
            for k in keys:
                refs = self.refs.get(k)
                st = "never_used" if not refs else "used" if self.reachable_ref(k) else \
                    "used_only_in_unreachable_code"
                sts.append(st)
                if st != "used":
                    locs.append({"kind": "location", "location": self.loc(k), "status": st, "category": f.kind})
            fst = "never_used" if all(s == "never_used" for s in sts) else \
                "used_only_in_unreachable_code" if all(s != "used" for s in sts) else None
            if fst is not None:
                out.append({"kind": "function", "function": f.name, "status": fst, "category": f.kind,
                            "path": _name(f.span.path), "line": f.span.line, "column": f.span.col})
            out.extend(locs)
        return out

    def _place(self, where: list) -> None:
        """Give each location finding a source position: its function's declaration (an
        inconsistent update: its first update site)."""
        funcs = None
        for w in where:
            if w.get("line") or w["kind"] not in ("location", "function"):
                continue
            if funcs is None:
                funcs = {f.name: f for f in user_functions(self.spec)}
            name = (w.get("location") or w.get("function") or "").split("(")[0]
            f = funcs.get(name)
            if w.get("status") == "inconsistent":
                key = next(k for k in self.obs.clash_example if self.loc(k) == w["location"])
                sp = min((self.obs.clash_example[key][0].span, self.obs.clash_example[key][2].span),
                         key=lambda x: (x.line, x.col))
            elif f is not None:
                sp = f.span
            else:
                continue
            if sp is not None and sp.line:
                w.update({"path": _name(sp.path), "line": sp.line, "column": sp.col})

    # ------------------------------------------------------------------ verdicts
    def run_checks(self, groups=None) -> list[dict]:
        out = []
        for mid, check, name, group in CHECKS:
            if groups is not None and group not in groups:
                continue
            where = getattr(self, check)()
            self._place(where)
            if where and all(w["kind"] == "rule" for w in where):
                where.sort(key=lambda w: (w["path"], w["line"], w["column"]))
            bad = any(w.get("status") in VIOLATING for w in where)
            if bad and (not self.incomplete or check in EXISTENTIAL):
                verdict = "violated"
            elif self.incomplete:
                verdict = "incomplete"
            else:
                verdict = "satisfied"
            out.append({"id": mid, "check": check, "name": name, "verdict": verdict, "where": where})
        return out


def _parts(t, v, d):
    """The components of value ``v`` (of type ``t``) that belong to domain ``d``: ``v`` itself, or
    the matching components of a tuple of a product type."""
    from ..semantics import types as T
    if t is d:
        return [v]
    if isinstance(t, T.Struct) and t.kind == "Prod" and isinstance(v, tuple) and len(v) == len(t.args):
        out = []
        for ti, vi in zip(t.args, v):
            out.extend(_parts(ti, vi, d))
        return out
    return []


def _holds(t, d) -> bool:
    from ..semantics import types as T
    return isinstance(t, T.Struct) and t.kind == "Prod" and any(a is d or _holds(a, d) for a in t.args)


def _name(path: str) -> str:
    from pathlib import Path
    return Path(path).name


def advise(path: str, *, groups=None, options=None, max_states=None, max_seconds=None) -> dict:
    """The JSON document of ``asmcheck advise`` (``error`` set when the spec cannot be read or run)."""
    from pathlib import Path
    doc = {"tool": "asmcheck", "version": __version__, "path": path, "spec": Path(path).stem, "states": 0,
           "transitions": 0, "configurations": 0, "seconds": 0.0, "incomplete": None, "error": None,
           "meta_properties": []}
    try:
        spec = load_spec(path)
        doc["spec"] = spec.name
        rv = Review(spec, options, max_states=max_states, max_seconds=max_seconds)
    except AsmError as e:
        doc["error"] = {"message": e.message, **_span_json(e.span)}
        return doc
    doc.update({"states": rv.space.states, "transitions": rv.space.transitions,
                "configurations": rv.obs.configs, "failing_configurations": rv.obs.error_configs,
                "seconds": round(rv.space.seconds, 3), "incomplete": rv.incomplete})
    doc["meta_properties"] = rv.run_checks(groups)
    return doc


def _span_json(span) -> dict:
    if span is None or not getattr(span, "line", 0):
        return {}
    return {"path": span.path, "line": span.line, "column": span.col}


# ---------------------------------------------------------------------- text
def _finding_text(w: dict) -> str:
    what = w.get("text") or w.get("location") or w.get("function") or w.get("domain") or w.get("macro") or ""
    if w["kind"] == "rule" and w.get("location"):
        what = w["text"]
    pos = f"{w['path']}:{w['line']}:{w['column']}  " if w.get("line") else ""
    extra = ""
    if "pairs" in w:
        extra = f" ({w['pairs']} pair{'s' if w['pairs'] != 1 else ''} of updates: " + ", ".join(
            f"line {ln} := {v}" for ln, v in w["updates"]) + ")"
    elif w.get("unused") and w["status"] != "all_used":
        extra = " (never: " + ", ".join(w["unused"][:12]) + (" ..." if len(w["unused"]) > 12 else "") + ")"
    elif "calls" in w:
        extra = f" ({w['calls']} calls)"
    if w["kind"] == "rule":
        loc = f" [{w['location']}]" if w.get("location") and w["rule"] == "update" else ""
        return f"{pos}{what}{loc}: {w['status']}{extra}"
    return f"{pos}{w['kind']} {what}: {w['status']}{extra}"


def advise_text(doc: dict) -> list[str]:
    if doc.get("error"):
        e = doc["error"]
        where = f"{e.get('path')}:{e.get('line')}:{e.get('column')}: " if e.get("line") else ""
        return [f"advise {doc['path']}: error: {where}{e['message']}"]
    lines = [f"advise {doc['spec']} ({doc['path']}): {doc['states']} states, {doc['transitions']} transitions, "
             f"{doc['configurations']} configurations"
             + (f", {doc['failing_configurations']} of them fail" if doc.get("failing_configurations") else "")]
    if doc.get("incomplete"):
        lines.append(f"exploration incomplete ({doc['incomplete']}): checks that need every state are undecided")
    mps = doc["meta_properties"]
    bad = [e for e in mps if e["verdict"] == "violated"]
    lines.append("")
    for e in bad:
        vs = [w for w in e["where"] if w.get("status") in VIOLATING]
        lines.append(f"{e['id']} {e['check']} violated ({e['name']}): {len(vs)} finding{'s' if len(vs) != 1 else ''}")
        for w in vs:
            lines.append("  " + _finding_text(w))
        lines.append("")
    for verdict in ("incomplete", "satisfied"):
        es = [e for e in mps if e["verdict"] == verdict]
        if es:
            lines.append(f"{verdict}: " + ", ".join(f"{e['id']} {e['check']}" for e in es))
    return lines


def add_advise_options(p) -> None:
    p.add_argument("file")
    p.add_argument("--format", choices=["text", "json"], default="text")
    p.add_argument("--mp", default=None, help="the checks to run: 1..7 and 'rules' (comma-separated; "
                                              "default: all 16)")
    p.add_argument("--max-states", type=int, default=200_000)
    p.add_argument("--max-seconds", type=float, default=None)
    add_domain_options(p)


def run_advise(args) -> int:
    import json
    import sys
    try:
        options = machine_options(args)
    except ValueError as e:
        sys.stderr.write(f"asmcheck advise: {e}\n")
        return 2
    if getattr(args, "import_path", None):
        use_import_path(args.import_path)
    groups = None
    if args.mp:
        groups = {g.strip().lower().removeprefix("mp") for g in args.mp.split(",") if g.strip()}
        bad = groups - {"1", "2", "3", "4", "5", "6", "7", "rules", "all"}
        if bad:
            sys.stderr.write(f"asmcheck advise: --mp takes 1..7 and rules, not {', '.join(sorted(bad))}\n")
            return 2
        if "all" in groups:
            groups = None
    doc = advise(args.file, groups=groups, options=options, max_states=args.max_states,
                 max_seconds=args.max_seconds)
    if args.format == "json":
        sys.stdout.write(json.dumps(doc, indent=1) + "\n")
    else:
        sys.stdout.write("\n".join(advise_text(doc)) + "\n")
    if doc.get("error"):
        return 2
    if any(e["verdict"] == "violated" for e in doc["meta_properties"]):
        return 1
    if any(e["verdict"] == "incomplete" for e in doc["meta_properties"]):
        return 3
    return 0
