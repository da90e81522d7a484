"""Check a transcript of ASMETA's simulator against asmcheck's step relation.

A transcript (``java -jar AsmetaS.jar -n N -rnd X.asm``) lists, per step, the
monitored values the simulator drew (``taking V for loc``) and the controlled
locations after the step (``<State n (controlled)>`` blocks).  A step conforms
when one of asmcheck's successors of the current state, with those monitored
values, shows every printed location with the printed value.  Locations the
simulator did not print are not compared (it prints only what it has read or
written).  Several successors can match (different ``choose`` branches with the
same printed projection): all of them are followed.
"""
from __future__ import annotations

import os
import re
import stat
from dataclasses import dataclass, field

from .errors import AsmError, AsmRuntimeError, InconsistentUpdate, Span
from .semantics import types as T
from .semantics.machine import Machine, NoAlternative, Prune, TooManySuccessors, Undetermined, NO_VALUE
from .semantics.machine import Ctx, Chooser
from .semantics.printer import (asmeta_state_lines, location_text_asmeta, parse_asmeta_value, printable, show_asmeta,
                                split_top)
from .explore.canonical import walk_fresh
from .semantics.state import is_dom_key
from .semantics.values import AbstractValue, BagV, MapV, SeqV, SetV

MAX_FRONTIER = 64
ENUMERATE = 10_000      # successors enumerated per state before switching to random sampling
SAMPLES = 4_000


@dataclass
class TranscriptStep:
    number: int
    taking: dict            # location text -> value text (in read order)
    lines: list             # (line number, location text, value text)
    line_no: int


@dataclass
class Transcript:
    path: str
    steps: list
    requested: int | None
    stop: str | None = None          # "clash" when the run ended on an inconsistent update
    clash_text: str | None = None
    final: list = field(default_factory=list)


def _split_line(text: str):
    depth = 0
    for i, c in enumerate(text):
        if c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        elif c == "=" and depth == 0:
            return text[:i], text[i + 1:]
    return None


def read_transcript(path: str) -> Transcript:
    """The steps of a transcript; an input error (exit 2) when the file is not a regular file or
    holds no run of ASMETA's simulator (no ``<State n (controlled)>`` block, no ``Final state:``
    line and no inconsistent update)."""
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise AsmError(None, f"{path}: cannot read transcript: not a regular file")
        raw = open(path, "rb").read().decode("utf-8", errors="replace")
    except OSError as e:
        raise AsmError(None, f"{path}: cannot read transcript: {e.strerror or e}") from None
    lines = raw.splitlines()
    steps = []
    taking: dict = {}
    requested = None
    cur = None
    stop = None
    clash = None
    final: list = []
    in_final = False
    for no, line in enumerate(lines, 1):
        s = line.rstrip()
        if s.startswith("#"):
            m = re.search(r"-n\s+(\d+)", s)
            if m:
                requested = int(m.group(1))
            continue
        if in_final:
            parts = _split_line(s)
            if parts:
                final.append((no, parts[0], parts[1]))
            continue
        m = re.match(r"^taking (.*) for (.*)$", s)
        if m:
            # the simulator may ask twice for one location in a step (reads inside a seq
            # happen on a copy of the state): every value it was given is kept
            taking.setdefault(m.group(2), []).append(m.group(1))
            continue
        m = re.match(r"^<State (\d+) \(controlled\)>$", s)
        if m:
            cur = TranscriptStep(int(m.group(1)), taking, [], no)
            taking = {}
            continue
        m = re.match(r"^</State (\d+) \(controlled\)>$", s)
        if m:
            if cur is not None:
                steps.append(cur)
            cur = None
            continue
        if re.match(r"^</?State \d+ \(monitored\)>$", s):
            continue
        if s == "Final state:":
            in_final = True
            continue
        if cur is not None:
            parts = _split_line(s)
            if parts:
                cur.lines.append((no, parts[0], parts[1]))
            continue
        m = re.match(r"^(.*) updated to (.*) and (.*)$", s)
        if m:
            stop = "clash"
            clash = s
    if not steps and not in_final and stop is None and cur is None:
        raise AsmError(Span(path, 1, 1), "not a transcript of ASMETA's simulator: no '<State n (controlled)>' "
                                         "block, no 'Final state:' line (expected the output of "
                                         "java -jar AsmetaS.jar -n N SPEC.asm)")
    t = Transcript(path, steps, requested, stop, clash, final)
    t.pending_taking = taking
    return t


class _Fixed(dict):
    """Monitored location text -> predicate accepting the transcript's value."""


_REAL = re.compile(r"(?<![\w.])-?\d+\.\d+(?:E-?\d+)?(?![\w.])")


def real_text(text: str) -> str:
    """A value text with its reals rounded to 12 significant digits.  ASMETA builds differ in how
    they count a Real interval: older ones add the step in doubles ({-0.8 : 0.8} holds
    0.19999999999999996), newer ones in decimal (0.2), as asmcheck does; a transcript from
    either conforms."""
    if "." not in text:
        return text
    return _REAL.sub(lambda m: format(float(m.group(0)), ".12g"), text)


_INT = re.compile(r"(?<![\w.])-?\d+(?![\w.])")
MAX_NUMBERS = 64


def _numbers(texts) -> dict:
    """Candidate values of a choose over Integer, Natural or Real, which the simulator draws at
    random: the numbers the step's block shows (a drawn value that reaches the state is printed
    there), then 0 (a drawn value that leaves no trace can be any)."""
    ints: set = set()
    reals: set = set()
    for t in texts:
        for m in _REAL.finditer(t):
            reals.add(float(m.group(0)))
        for m in _INT.finditer(t):
            ints.add(int(m.group(0)))
    ints_l = sorted(ints)[:MAX_NUMBERS]
    reals_l = sorted(reals)[:MAX_NUMBERS]
    return {T.INTEGER: ints_l + [0] * (0 not in ints), T.NATURAL: [i for i in ints_l if i >= 0] + [0] * (0 not in ints),
            T.REAL: reals_l + [0.0] * (0.0 not in reals)}


def _fixed_from(taking: dict, lines=()) -> _Fixed:
    fx = _Fixed()
    for loc, vals in taking.items():
        norm = {real_text(v) for v in vals}
        fx[loc] = (lambda v, vals=vals, norm=norm: show_asmeta(v) in vals or real_text(show_asmeta(v)) in norm)
    fx.numbers = _numbers([v for _, _, v in lines] + [v for vals in taking.values() for v in vals])
    return fx


def _pruner(machine, step, before):
    """Cut choices whose updates the block contradicts: the simulator prints every location it
    has updated, and (outside seq) the value it got.  Updates that involve an element made in
    this step are not judged (the simulator may have named the new elements differently)."""
    printed: dict = {}
    for _, loc, val in step.lines:
        printed.setdefault(loc, set()).add(val)
    existing = set()
    for k, v in before.items():
        if is_dom_key(k):
            existing.update(v)

    def is_new(x):
        t = type(x)
        if t is AbstractValue:
            return x.serial > 0 and x not in existing
        if t in (tuple, SeqV, SetV, BagV):
            return any(is_new(y) for y in x)
        if t is MapV:
            return any(is_new(a) or is_new(b) for a, b in x)
        return False

    def prune(key, value, depth):
        if not printable(machine, key):
            return
        if (type(key) is tuple and is_new(key[1])) or is_new(value):
            return
        t = location_text_asmeta(machine, key)
        vals = printed.get(t)
        if vals is None:
            raise Prune()
        if depth == 0:
            shown = show_asmeta(value)
            if shown not in vals and real_text(shown) not in {real_text(x) for x in vals}:
                raise Prune()
    return prune


def _parser(taking: dict, machine=None):
    def parse(label, dom):
        texts = taking.get(label)
        if not texts:
            return NO_VALUE
        text = texts[0]
        try:
            return parse_asmeta_value(text, dom, machine)
        except (ValueError, IndexError):
            return NO_VALUE
    return parse


@dataclass
class Mismatch:
    step: int
    line: int
    location: str
    expected: str
    allowed: list          # what asmcheck allows for that location (texts)
    reason: str = ""


def _state_text(machine: Machine, state: dict) -> dict:
    """Location text -> sorted list of value texts (two modules may declare the same name)."""
    out = _state_text_plain(machine, state)
    doms: dict = {}
    for k, v in state.items():
        if is_dom_key(k) and v:
            doms.setdefault(k[1], set()).update(e.name for e in v)
    for d, els in machine.static_elements.items():
        if els:
            doms.setdefault(d.name, set()).update(e.name for e in els)
    for name, names in doms.items():
        out.setdefault(name, []).append("{" + ",".join(sorted(names)) + "}")
        out[name].sort()
    return out


def _lazy_text(machine, state, loc: str):
    """The value text of a location whose function has a lazily evaluated init (not yet stored)."""
    if "(" not in loc or not loc.endswith(")"):
        return None
    name, _, rest = loc.partition("(")
    args = split_top(rest[:-1])
    for f in machine.functions:
        if f.name == name and f.index in machine.lazy and f.arity == len(args):
            try:
                vals = tuple(parse_asmeta_value(a, t, machine) for a, t in zip(args, f.domain))
            except (ValueError, IndexError):
                continue
            if (f.index, vals) in state:
                return show_asmeta(state[(f.index, vals)])
            ctx = Ctx(machine, state, Chooser())
            try:
                return show_asmeta(machine._lazy_default(f.index)(ctx, vals))
            except AsmError:
                return None
    return None


def _matches(machine, state, lines) -> tuple[bool, tuple | None]:
    text = _state_text(machine, state)
    want: dict = {}
    first: dict = {}
    for no, loc, val in lines:
        want.setdefault(loc, []).append(val)
        first.setdefault(loc, no)
    for loc, vals in want.items():
        ours = text.get(loc, [])
        if not ours and machine.lazy:
            lz = _lazy_text(machine, state, loc)
            if lz is not None:
                ours = [lz]
        exp = sorted(vals)
        if exp == ["undef"] and not ours:
            continue
        if ours != exp and not (len(exp) == 1 and exp[0] in ours) and not _same_reals(ours, exp):
            return False, (first[loc], loc, exp[0] if len(exp) == 1 else ",".join(exp),
                           ",".join(ours) if ours else "undef")
    return True, None


def _same_reals(ours: list, exp: list) -> bool:
    o = sorted(real_text(x) for x in ours)
    e = sorted(real_text(x) for x in exp)
    return o == e or (len(e) == 1 and e[0] in o)


def conform(machine: Machine, transcript: Transcript):
    """None when the transcript conforms, else a Mismatch for the first step that does not."""
    first = transcript.steps[0].taking if transcript.steps else getattr(transcript, "pending_taking", {})
    try:
        frontier = []
        seen0 = set()
        for log, st in machine.initial_states(fixed=_fixed_from(first), parse=_parser(first, machine)):
            k = _freeze(st)
            if k not in seen0:
                seen0.add(k)
                frontier.append(st)
    except Undetermined as e:
        return Mismatch(0, 0, "", "", [], f"cannot follow the initial state: {e.message}")
    except NoAlternative as e:
        return Mismatch(0, 0, "", "", [], f"initial state: {e.message}")
    for step in transcript.steps:
        fixed = _fixed_from(step.taking, step.lines)
        nxt = []
        seen = set()
        misses = []
        for st in frontier:
            early = _follow(machine, st, step, fixed, True, nxt, seen, misses)
            if early is not None:
                return early
        if not nxt and not any(d is not None for d, _ in misses):
            # every choice was cut early: follow them to the end once more, for a better message
            for st in frontier:
                try:
                    _follow(machine, st, step, fixed, False, nxt, seen, misses)
                except TooManySuccessors:
                    break
        if not nxt:
            diffs = [d for d, _ in misses if d is not None]
            if diffs:
                no, loc, val, _ = diffs[0]
                allowed = sorted({d[3] for d in diffs if d[1] == loc})
                return Mismatch(step.number, no, loc, val, allowed,
                                f"no successor of step {step.number - 1} shows {loc}={val}")
            reason = next((m for _, m in misses if m), "no successor")
            return Mismatch(step.number, step.line_no, "", "", [], reason)
        frontier = nxt[:MAX_FRONTIER]
    if transcript.stop == "clash":
        taking = getattr(transcript, "pending_taking", {})
        fixed = _fixed_from(taking)
        for st in frontier:
            try:
                machine.successors(st, fixed=fixed, parse=_parser(taking, machine))
            except InconsistentUpdate:
                return None
            except AsmError:
                continue
        return Mismatch(len(transcript.steps) + 1, 0, "", "", [],
                        f"the simulator stopped on '{transcript.clash_text}', asmcheck finds no inconsistent update")
    return None


def _follow(machine, st, step, fixed, use_prune, nxt, seen, misses):
    """Add to ``nxt`` the successors of ``st`` that show the block; record why others do not."""
    errors: list = []
    try:
        try:
            # a sequence of choices that fails (a choose over a range that is undef there, say) is
            # not the step the simulator made, which did not fail: it is skipped
            succ = machine.successors(st, limit=ENUMERATE, fixed=fixed, parse=_parser(step.taking, machine),
                                      prune=_pruner(machine, step, st) if use_prune else None, errors=errors)
        except TooManySuccessors:
            if not use_prune:
                raise
            succ = _first_matches(machine, st, step, fixed)
        if not succ and errors:
            raise errors[0]
    except NoAlternative as e:
        misses.append((None, e.message))
        return None
    except Undetermined as e:
        return Mismatch(step.number, step.line_no, "", "", [], f"cannot follow: {e.message}")
    except InconsistentUpdate as e:
        misses.append((None, f"asmcheck finds an inconsistent update: {e.message}"))
        return None
    except AsmRuntimeError as e:
        misses.append((None, f"asmcheck stops with an error: {e}"))
        return None
    printed = {loc for _, loc, _ in step.lines}
    for log, ups, new, mon in succ:
        # the simulator prints every location it has updated: a successor that
        # updates a controlled location the block does not show is not this step
        fresh_now = {e for _, e in ups.fresh}
        hidden = [k for k in ups.locs if printable(machine, k)
                  and location_text_asmeta(machine, k) not in printed
                  and not (type(k) is tuple and any(a in fresh_now for a in k[1]))]
        if hidden:
            k = hidden[0]
            misses.append(((step.line_no, location_text_asmeta(machine, k), "(not printed)",
                            show_asmeta(ups.locs[k].value)), None))
            continue
        ok, diff = _matches(machine, new, step.lines)
        if not ok and ups.fresh:
            # the simulator may have made the new elements in another order:
            # compare up to a renaming of this step's new elements
            renamed = _match_renamed(machine, st, new, ups, step.lines)
            if renamed is not None:
                new, ok = renamed, True
        if ok:
            key = _freeze(new)
            if key not in seen:
                seen.add(key)
                nxt.append(new)
        else:
            misses.append((diff, None))
    return None


def _first_matches(machine, st, step, fixed):
    """Random search for successors that match (too many choice sequences to enumerate)."""
    found = []
    printed = {loc for _, loc, _ in step.lines}
    for item in machine.sample_successors(st, SAMPLES, seed=step.number, fixed=fixed,
                                          parse=_parser(step.taking, machine)):
        log, ups, new, mon = item
        if any(printable(machine, k) and location_text_asmeta(machine, k) not in printed for k in ups.locs):
            continue
        if _matches(machine, new, step.lines)[0]:
            found.append(item)
            if len(found) >= 4:
                break
    if not found:
        raise NoAlternative(None, f"no successor found among {SAMPLES} random choice sequences "
                                  f"(too many to enumerate)")
    return found


def _match_renamed(machine, before, new, ups, lines):
    """``new`` with this step's new elements renamed so that it shows ``lines``, or None.

    Each new element first gets the names it may take: a name is ruled out when a location
    that mentions this element (and no other new one) would print differently from the
    transcript under it.  The assignments left are then tried, distinct names per domain."""
    from .semantics.values import fresh_value, rename_state
    printed_doms = {}
    want: dict = {}
    for _, loc, val in lines:
        want.setdefault(loc, []).append(val)
        if val.startswith("{") and "(" not in loc:
            printed_doms[loc] = set(val[1:-1].split(",")) if val != "{}" else set()
    ours_all = []
    names: dict = {}
    for dom in sorted({d for d, _ in ups.fresh}):
        ours = [e for d, e in ups.fresh if d == dom]
        old = {e.name for e in before.get(("#dom", dom), ())}
        theirs = sorted(n for n in printed_doms.get(dom, set()) if n not in old and "!" in n)
        if len(theirs) != len(ours):
            return None
        for o in ours:
            names[o] = [fresh_value(dom, int(t.partition("!")[2])) for t in theirs]
        ours_all.extend(ours)
    if not ours_all:
        return None
    fresh = set(ours_all)
    # the entries of the state that mention exactly one new element
    alone: dict = {o: [] for o in ours_all}
    for k, v in new.items():
        if is_dom_key(k):
            continue
        found: list = []
        if type(k) is tuple:
            walk_fresh(k[1], found)
        walk_fresh(v, found)
        found = {e for e in found if e in fresh}
        if len(found) == 1:
            alone[found.pop()].append((k, v))
    cands = {}
    for o in ours_all:
        ok = []
        for t in names[o]:
            text = _state_text_plain(machine, rename_state(dict(alone[o]), {o: t}))
            if all(sorted(want[loc]) == vals or (len(want[loc]) == 1 and want[loc][0] in vals)
                   for loc, vals in text.items() if loc in want):
                ok.append(t)
        if not ok:
            return None
        cands[o] = ok
    order = sorted(ours_all, key=lambda o: len(cands[o]))
    budget = [5040]

    def search(i, used, mapping):
        if budget[0] <= 0:
            return None
        if i == len(order):
            budget[0] -= 1
            cand = rename_state(new, mapping)
            return cand if _matches(machine, cand, lines)[0] else None
        o = order[i]
        for t in cands[o]:
            if t in used:
                continue
            mapping[o] = t
            used.add(t)
            got = search(i + 1, used, mapping)
            if got is not None:
                return got
            used.discard(t)
            del mapping[o]
        return None

    return search(0, set(), {})


def _state_text_plain(machine: Machine, state: dict) -> dict:
    """Location text -> sorted value texts, for locations only (no domains)."""
    out: dict = {}
    for k, v in state.items():
        if not is_dom_key(k) and printable(machine, k):
            out.setdefault(location_text_asmeta(machine, k), []).append(show_asmeta(v))
    for k in out:
        out[k].sort()
    return out


def _freeze(state: dict):
    return frozenset((k, v if not isinstance(v, (list, dict)) else repr(v)) for k, v in state.items())
