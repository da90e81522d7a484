"""Subcommands beyond ``parse``: simulate, conform, scenario, explore, check, bmc."""
from __future__ import annotations

import json
import sys

from .errors import AsmError, UsageError

EXIT_OK, EXIT_VIOLATED, EXIT_ERROR, EXIT_INCOMPLETE = 0, 1, 2, 3


def _load(path: str, options: dict | None = None):
    from .semantics.machine import Machine
    from .semantics.resolve import check_file

    spec = check_file(path)
    if spec is None:
        raise AsmError(None, f"{path}: the file is empty: nothing to run")
    if spec.main is None:
        raise AsmError(spec.root_module.syntax.span if spec.root_module.syntax else None,
                       f"{spec.name} has no main rule: nothing to run (is it a module?)")
    return spec, Machine(spec, options or {})


def parse_range(text: str) -> list:
    """``LO..HI`` (integers), or a comma-separated list of values."""
    if ".." in text:
        lo, hi = text.split("..", 1)
        try:
            return list(range(int(lo), int(hi) + 1))
        except ValueError:
            raise UsageError(f"bad range {text!r}: expected LO..HI with integers") from None
    out = []
    for part in text.split(","):
        p = part.strip()
        if p in ("true", "false"):
            out.append(p == "true")
            continue
        try:
            out.append(int(p))
        except ValueError:
            try:
                out.append(float(p))
            except ValueError:
                out.append(p.strip('"'))
    return out


def machine_options(args) -> dict:
    opts: dict = {}
    if getattr(args, "int_range", None):
        r = parse_range(args.int_range)
        opts["int_range"] = (min(r), max(r))
    mons = {}
    for item in getattr(args, "monitored", None) or []:
        if "=" not in item:
            raise UsageError(f"--monitored expects NAME=LO..HI or NAME=v1,v2,..., not {item!r}")
        name, rng = item.split("=", 1)
        mons[name.strip()] = parse_range(rng)
    if mons:
        opts["monitored_ranges"] = mons
    return opts


def _add_domain_options(p) -> None:
    p.add_argument("--int-range", metavar="LO..HI",
                   help="bound the Integer and Natural domains (for monitored functions and quantifiers over them)")
    p.add_argument("--monitored", action="append", metavar="NAME=LO..HI",
                   help="the values a monitored function ranges over (repeatable); also NAME=v1,v2,...")


# ----------------------------------------------------------------- simulate
def _choice_text(c) -> str:
    from .semantics.values import show
    if c.kind == "monitored":
        return f"{c.label} = {show(c.value)}"
    if isinstance(c.value, dict):
        binds = ", ".join(f"{k} = {show(v)}" for k, v in c.value.items())
        return f"{c.label}: {binds}"
    return f"{c.label}: {c.value!r}"


def cmd_simulate(args) -> int:
    from .semantics.printer import asmeta_state_lines, location_text, location_sort_key, show_asmeta
    from .semantics.state import is_dom_key
    from .semantics.values import show
    from .simulate import read_inputs, simulate

    if getattr(args, "swarm", None) is not None:
        from .parallel.cli import cmd_swarm
        from .props import spec_properties
        from .props.files import properties_for
        spec, machine = _load(args.file, machine_options(args))
        sp, stp = spec_properties(machine)
        es, est, temporal = properties_for(spec, machine, args.file, None)
        return cmd_swarm(args, spec, machine, sp + es, stp + est, temporal)
    spec, machine = _load(args.file, {**machine_options(args), "dedupe": False})
    inputs = read_inputs(args.input) if args.input else None
    if args.random and args.seed is None:
        args.seed = 0
    out = []
    code = EXIT_OK
    steps_json = []
    for st in simulate(machine, args.steps, seed=args.seed, random_choices=args.random, inputs=inputs):
        if args.format == "asmeta":
            if st.number == 0:
                pass
            else:
                for c in st.choices:
                    if c.kind == "monitored":
                        out.append(f"taking {show_asmeta(c.value)} for {c.label}")
                if st.monitored and st.error is None:
                    out.append(f"<State {st.number - 1} (monitored)>")
                    keys = sorted(st.monitored, key=lambda k: location_sort_key(machine, k))
                    for k in keys:
                        out.append(f"{_asmeta_loc(machine, k)}={show_asmeta(st.monitored[k])}")
                    out.append(f"</State {st.number - 1} (monitored)>")
                if st.error is None and not (st.violated and not st.changed and st.number > 0):
                    out.append(f"<State {st.number} (controlled)>")
                    out.extend(asmeta_state_lines(machine, st.state))
                    out.append(f"</State {st.number} (controlled)>")
        elif args.format == "json":
            steps_json.append({
                "step": st.number,
                "choices": [{"kind": c.kind, "label": c.label, "value": _json_value(c.value)} for c in st.choices],
                "changed": {location_text(machine, k) if not is_dom_key(k) else k[1]: _json_value(v)
                            for k, v in sorted(st.changed.items(), key=lambda kv: _key_order(machine, kv[0]))},
                "violated": [p.name for p in st.violated],
                "error": None if st.error is None else str(st.error),
            })
        else:
            head = "initial state" if st.number == 0 else f"step {st.number}"
            ch = "; ".join(_choice_text(c) for c in st.choices)
            out.append(head + (f"  [{ch}]" if ch else "") + ":")
            for k, v in sorted(st.changed.items(), key=lambda kv: _key_order(machine, kv[0])):
                if is_dom_key(k):
                    out.append(f"  {k[1]} = {{{', '.join(e.name for e in (v or ()))}}}")
                else:
                    out.append(f"  {location_text(machine, k)} = {show(v)}")
            if not st.changed and st.number > 0 and st.error is None and not st.violated:
                out.append("  (no change)")
        if st.error is not None:
            out.append(st.error.render())
            code = EXIT_VIOLATED
        if st.violated:
            for p in st.violated:
                out.append(f"{p.span}: invariant {p.name} is violated" +
                           (" in the initial state" if st.number == 0 else f" after step {st.number}"))
            code = EXIT_VIOLATED
    if args.format == "asmeta":
        out.append("Final state:")
        last = st.state
        out.extend(asmeta_state_lines(machine, last))
    if args.format == "json":
        print(json.dumps({"spec": spec.name, "steps": steps_json}, indent=2))
    else:
        print("\n".join(out))
    return code


def _asmeta_loc(machine, k):
    from .semantics.printer import location_text_asmeta
    return location_text_asmeta(machine, k)


def _key_order(machine, k):
    from .semantics.printer import location_sort_key
    from .semantics.state import is_dom_key
    if is_dom_key(k):
        return ("~", 0, k[1])
    return location_sort_key(machine, k)


def _json_value(v):
    from .semantics.values import AbstractValue, BagV, EnumValue, MapV, RuleValue, SeqV, SetV, show
    if v is None or isinstance(v, (bool, int, float, str)):
        return v
    if isinstance(v, (EnumValue, AbstractValue)):
        return v.name
    if isinstance(v, SetV):
        return {"set": [_json_value(x) for x in v.ordered()]}
    if isinstance(v, SeqV):
        return {"seq": [_json_value(x) for x in v]}
    if isinstance(v, BagV):
        return {"bag": [_json_value(x) for x in v]}
    if isinstance(v, MapV):
        return {"map": [[_json_value(k), _json_value(x)] for k, x in v]}
    if isinstance(v, tuple):
        return {"tuple": [_json_value(x) for x in v]}
    if isinstance(v, dict):
        return {k: _json_value(x) for k, x in v.items()}
    if isinstance(v, RuleValue):
        return {"rule": v.rule.name}
    return show(v)


# ----------------------------------------------------------------- conform
def cmd_conform(args) -> int:
    from .conform import conform, read_transcript

    spec, machine = _load(args.file, machine_options(args))
    tr = read_transcript(args.transcript)
    res = conform(machine, tr)
    if res is None:
        print(f"{args.transcript}: conforms ({len(tr.steps)} step(s) checked"
              + (", ending on an inconsistent update" if tr.stop == "clash" else "") + ")")
        return EXIT_OK
    where = f"{args.transcript}:{res.line}" if res.line else args.transcript
    print(f"{where}: step {res.step} does not conform: {res.reason}")
    if res.location:
        print(f"  the transcript shows   {res.location}={res.expected}")
        print(f"  asmcheck allows        {res.location}=" + (" | ".join(res.allowed) if res.allowed else "(nothing)"))
    return EXIT_VIOLATED


def register(sub) -> None:
    p = sub.add_parser("simulate", help="run a spec step by step",
                       description="Run FILE for N steps and print what changed per step. choose takes the "
                                   "first candidate and monitored functions their first value, unless --random "
                                   "(or --seed) picks at random or --input gives the values.")
    p.add_argument("file", metavar="FILE")
    p.add_argument("-n", "--steps", type=int, default=10, metavar="N", help="number of steps (default 10)")
    p.add_argument("--seed", type=int, help="random choices, from this seed (reproducible)")
    p.add_argument("--random", action="store_true", help="random choices (seed 0 unless --seed)")
    p.add_argument("--input", metavar="FILE", help="monitored values: 'location = value' lines, '---' between steps")
    p.add_argument("--format", choices=["text", "asmeta", "json"], default="text",
                   help="text: changes per step; asmeta: ASMETA's <State n (controlled)> blocks; json")
    _add_domain_options(p)
    from .parallel.cli import add_simulate_options
    add_simulate_options(p)
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("conform", help="check a transcript of ASMETA's simulator against asmcheck",
                       description="Check that every step of an AsmetaS transcript (java -jar AsmetaS.jar -n N -rnd "
                                   "FILE) is a step asmcheck allows. Exit 0 when it conforms, 1 at the first step "
                                   "that does not, 2 on an input error.")
    p.add_argument("file", metavar="FILE.asm")
    p.add_argument("transcript", metavar="TRANSCRIPT")
    _add_domain_options(p)
    p.set_defaults(func=cmd_conform)

    from . import commands_explore
    commands_explore.register(sub)
