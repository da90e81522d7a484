"""Choosers: how a step resolves its nondeterminism.

A step asks its chooser which alternative to take at each choice point (a ``choose``
rule, a monitored location).  A simulation takes one alternative; the enumerating
choosers let :meth:`Machine.successors` re-run the step with every prefix of choices.
"""
from __future__ import annotations

import random
from dataclasses import dataclass

from ..errors import AsmRuntimeError
from . import types as T
from .state import same_value
from .values import show


@dataclass
class Choice:
    """One choice point of a step, as recorded for traces."""

    kind: str            # "choose" or "monitored"
    label: str           # the choose rule's position, or the monitored location
    n: int               # number of alternatives
    index: int           # the alternative taken
    value: object        # the value taken (monitored) or the variable bindings (choose)
    pick: int = -1       # its position among all the options (== index unless restricted)
    nested: list | None = None   # choices made inside a choose body (enumerating choosers)

    def __post_init__(self):
        if self.pick < 0:
            self.pick = self.index



NO_VALUE = object()


def java_draw(rng, dom):
    """A random element of Natural, Integer or Real with the distributions of ASMETA's simulator
    (RuleEvaluator.InfiniteCollection.getRndValue): a Natural in [0, 2^31 - 1), an Integer over the
    32-bit ints, a Real in [0, 1)."""
    if dom is T.NATURAL:
        return rng.randrange(0, (1 << 31) - 1)
    if dom is T.INTEGER:
        return rng.randrange(-(1 << 31), 1 << 31)
    if dom is T.REAL:
        return rng.random()
    return NO_VALUE



class Chooser:
    """Takes the first alternative at every choice point."""

    # Enumerating choosers see one alternative per distinct effect of a choose rule
    # (its bindings are local to its body, so only the effect can matter afterwards).
    enumerates = False
    memo = None

    def sub(self, prefix):
        return Enumerator(prefix)

    def __init__(self):
        self.log: list[Choice] = []

    def value(self, label, dom):
        """A monitored value from an infinite domain (only a simulation can pick one)."""
        return NO_VALUE

    #: the random source of :meth:`draw` (None: this chooser cannot draw)
    rng = None

    def draw(self, label, var, dom):
        """A value for the variable ``var`` of a choose rule over Integer, Natural or Real, drawn
        as ASMETA's simulator draws it (``NO_VALUE`` when this chooser does not draw)."""
        if self.rng is None:
            return NO_VALUE
        v = java_draw(self.rng, dom)
        if v is not NO_VALUE:
            self.log.append(Choice("choose", label, 0, 0, {var: v}))
        return v

    def draw_options(self, dom):
        """The values an enumerating chooser tries for a choose over the infinite ``dom`` (None:
        it has none, and the choose cannot be enumerated)."""
        return None

    def choose(self, kind, label, options, values_repr=None) -> int:
        self.log.append(Choice(kind, label, len(options), 0, options[0] if options else None))
        return 0



class DrawingChooser(Chooser):
    """Takes the first alternative, and draws (from a seeded source) the values of a choose over
    an infinite domain, where there is no first."""

    def __init__(self, seed: int = 0):
        super().__init__()
        self.rng = random.Random(seed)

    def choose(self, kind, label, options, values_repr=None) -> int:
        return Chooser.choose(self, kind, label, options, values_repr)



class RandomChooser(Chooser):
    def __init__(self, seed: int):
        super().__init__()
        self.rng = random.Random(seed)

    def choose(self, kind, label, options, values_repr=None) -> int:
        i = self.rng.randrange(len(options))
        self.log.append(Choice(kind, label, len(options), i, options[i]))
        return i

    def value(self, label, dom):
        r = T.root(dom)
        if r is T.NATURAL:
            v = self.rng.randrange(0, 101)
        elif r is T.INTEGER:
            v = self.rng.randrange(-100, 101)
        elif r is T.REAL:
            v = round(self.rng.uniform(-100, 100), 3)
        elif r is T.STRING:
            v = "s" + str(self.rng.randrange(100))
        else:
            return NO_VALUE
        self.log.append(Choice("monitored", label, 0, 0, v))
        return v



class ScriptChooser(Chooser):
    """Replays a recorded sequence of choice indexes; extra choice points take 0."""

    enumerates = True

    def __init__(self, indexes):
        super().__init__()
        self.indexes = list(indexes)

    def choose(self, kind, label, options, values_repr=None) -> int:
        pos = len(self.log)
        i = self.indexes[pos] if pos < len(self.indexes) else 0
        if isinstance(i, tuple):
            i = i[1]
        if i >= len(options):
            raise AsmRuntimeError(None, f"replay: choice {pos} has {len(options)} alternatives, the trace asks for "
                                        f"number {i}")
        self.log.append(Choice(kind, label, len(options), i, options[i]))
        return i



class InputChooser(Chooser):
    """Monitored values from a table (location text -> value); choose takes the first."""

    def __init__(self, values: dict, fallback: Chooser | None = None):
        super().__init__()
        self.values = values
        self.fallback = fallback

    def value(self, label, dom):
        if label in self.values:
            v = self.values[label]
            self.log.append(Choice("monitored", label, 0, 0, v))
            return v
        if self.fallback is not None:
            v = self.fallback.value(label, dom)
            if v is not NO_VALUE:
                self.log.append(self.fallback.log.pop())
            return v
        return NO_VALUE

    def draw(self, label, var, dom):
        if self.fallback is None:
            return NO_VALUE
        v = self.fallback.draw(label, var, dom)
        if v is not NO_VALUE:
            self.log.append(self.fallback.log.pop())
        return v

    def choose(self, kind, label, options, values_repr=None) -> int:
        if kind == "monitored" and label in self.values:
            want = self.values[label]
            for i, o in enumerate(options):
                if same_value(o, want):
                    self.log.append(Choice(kind, label, len(options), i, o))
                    return i
            raise AsmRuntimeError(None, f"the value {show(want)} given for {label} is not in its domain")
        if self.fallback is not None:
            i = self.fallback.choose(kind, label, options, values_repr)
            self.log.append(self.fallback.log.pop())
            return i
        self.log.append(Choice(kind, label, len(options), 0, options[0] if options else None))
        return 0



class Enumerator(Chooser):
    """Follows a prefix of alternative numbers, then takes the first; records what it saw.

    ``fixed`` maps a monitored location's text to a predicate on candidate values: only
    the values it accepts are alternatives (used to follow a transcript).  ``Choice.index``
    is the number of the alternative among those allowed, ``Choice.pick`` its position
    among all the options.
    """

    enumerates = True

    def __init__(self, prefix, fixed=None, parse=None):
        super().__init__()
        self.prefix = prefix
        self.fixed = fixed
        self.parse = parse

    def sub(self, prefix):
        return Enumerator(prefix, self.fixed, self.parse)

    memo = None

    def choose(self, kind, label, options, values_repr=None) -> int:
        pos = len(self.log)
        i = self.prefix[pos] if pos < len(self.prefix) else 0
        allowed = None
        if self.fixed is not None and kind == "monitored" and label in self.fixed:
            ok = self.fixed[label]
            allowed = [j for j, o in enumerate(options) if ok(o)]
            if not allowed:
                raise NoAlternative(None, f"no value of {label} matches the one given")
        if allowed is None:
            self.log.append(Choice(kind, label, len(options), i, options[i], i))
            return i
        j = allowed[i]
        self.log.append(Choice(kind, label, len(allowed), i, options[j], j))
        return j

    def draw_options(self, dom):
        # a transcript's numbers (``fixed.numbers``: dom -> values) for a choose over an infinite domain
        numbers = getattr(self.fixed, "numbers", None)
        return numbers.get(dom) if numbers else None

    def value(self, label, dom):
        if self.parse is not None and self.fixed is not None and label in self.fixed:
            v = self.parse(label, dom)
            if v is not NO_VALUE:
                self.log.append(Choice("monitored", label, 1, 0, v, 0))
                return v
        return NO_VALUE



class Prune(Exception):
    """Raised by a ``prune`` check: this sequence of choices cannot lead where wanted."""



class TooManySuccessors(AsmRuntimeError):
    """The successors of one state exceed the given bound."""



class Sampler(Enumerator):
    """Random alternatives (within ``fixed``), for searching huge branchings."""

    enumerates = False

    def __init__(self, rng, fixed=None, parse=None):
        super().__init__([], fixed, parse)
        self.rng = rng

    def choose(self, kind, label, options, values_repr=None) -> int:
        self.prefix = [c.index for c in self.log] + [self.rng.randrange(self._count(kind, label, options))]
        return super().choose(kind, label, options, values_repr)

    def _count(self, kind, label, options):
        if self.fixed is not None and kind == "monitored" and label in self.fixed:
            ok = self.fixed[label]
            n = sum(1 for o in options if ok(o))
            return max(n, 1)
        return len(options)



class DeadlineReached(Exception):
    """The machine's ``deadline`` (a ``time.monotonic()`` value) passed inside a step.

    Not an :class:`AsmError`: the step did not fail, it was stopped; a caller that gives a
    deadline turns this into an incomplete result."""



class NoAlternative(AsmRuntimeError):
    """A transcript asks for a value the spec does not allow."""


def next_prefix(log) -> list | None:
    """The next sequence of choices to try after the one recorded in ``log`` (an enumerating
    chooser's): the last choice point with an untried alternative takes its next one, and the
    choice points after it start again.  None when every sequence has been tried."""
    j = len(log) - 1
    while j >= 0 and log[j].index + 1 >= log[j].n:
        j -= 1
    if j < 0:
        return None
    return [c.index for c in log[:j]] + [log[j].index + 1]
