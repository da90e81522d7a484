"""Located errors and the source registry used to print them.

Every error asmcheck reports about a spec carries a :class:`Span` and is
printed as ``file:line:col: message`` followed by the source line and a caret.
"""
from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True, slots=True)
class Span:
    """A region of a source file; lines and columns are 1-based."""

    path: str
    line: int
    col: int
    end_line: int = 0
    end_col: int = 0

    def __str__(self) -> str:
        return f"{self.path}:{self.line}:{self.col}"

    def short(self) -> str:
        return f"{Path(self.path).name}:{self.line}:{self.col}"


NO_SPAN = Span("<builtin>", 0, 0)


class SourceRegistry:
    """Text of every file read, so errors can quote the offending line."""

    def __init__(self) -> None:
        self._lines: dict[str, list[str]] = {}

    def add(self, path: str, text: str) -> None:
        self._lines[path] = text.split("\n")

    def line(self, path: str, line: int) -> str | None:
        lines = self._lines.get(path)
        if lines is None or not (1 <= line <= len(lines)):
            return None
        return lines[line - 1].rstrip("\r")


SOURCES = SourceRegistry()


def _rebuild_error(cls, args, state):
    err = cls.__new__(cls)
    Exception.__init__(err, *args)
    err.__dict__.update(state)
    return err


class AsmError(Exception):
    """An error in a spec (or in an input file) at a known position."""

    kind = "error"

    def __init__(self, span: Span | None, message: str, notes: list[tuple[Span | None, str]] | None = None):
        super().__init__(message)
        self.span = span
        self.message = message
        self.notes = notes or []

    def __str__(self) -> str:
        if self.span is None or self.span.line == 0:
            return self.message
        return f"{self.span}: {self.message}"

    def __reduce__(self):
        # pickled whole (the parallel search sends a step's error between processes): the
        # constructors of the subclasses differ, so the attributes travel, not the arguments
        return (_rebuild_error, (type(self), self.args, self.__dict__))

    def render(self) -> str:
        """``file:line:col: message``, the source line and a caret (and notes).

        Only the erroneous line is echoed (a window of it when it is long), and terminal
        control characters are shown as '?', so a hostile file cannot drive the terminal."""
        out = [clean_text(str(self))]
        out.extend(_quote(self.span))
        for span, note in self.notes:
            out.append(clean_text(f"{span}: note: {note}" if span and span.line else f"note: {note}"))
            out.extend(_quote(span))
        return "\n".join(out)

    def to_json(self) -> dict:
        """The error as ``{"error": {"file", "line", "col", "message"}}`` (None where unknown)."""
        span = self.span
        located = span is not None and span.line > 0
        return {"error": {
            "file": span.path if span is not None and span.path != NO_SPAN.path else None,
            "line": span.line if located else None,
            "col": span.col if located else None,
            "message": clean_text(self.message),
        }}


# C0 controls (but tab and newline), DEL, C1 controls, and the Unicode bidirectional overrides
_CONTROL = {c: "?" for c in list(range(0x00, 0x09)) + list(range(0x0b, 0x20)) + list(range(0x7f, 0xa0))
            + [0x061c, 0x200e, 0x200f] + list(range(0x202a, 0x202f)) + list(range(0x2066, 0x206a))}


def clean_text(text: str) -> str:
    """``text`` with terminal control characters (escape sequences, bells, carriage returns,
    bidirectional overrides) replaced by '?', one for one; tabs and newlines are kept."""
    return text.translate(_CONTROL)


QUOTE_WIDTH = 160       # at most this many characters of the erroneous line are echoed


def _quote(span: Span | None) -> list[str]:
    if span is None or span.line == 0:
        return []
    text = SOURCES.line(span.path, span.line)
    if text is None:
        return []
    col = max(span.col - 1, 0)
    width = 1
    if span.end_line == span.line and span.end_col > span.col:
        width = span.end_col - span.col
    lead = ""
    if len(text) > QUOTE_WIDTH:
        # a window of the line around the column
        start = max(0, min(col - QUOTE_WIDTH // 3, len(text) - QUOTE_WIDTH))
        shown = text[start:start + QUOTE_WIDTH]
        lead = "..." if start > 0 else ""
        tail = "..." if start + QUOTE_WIDTH < len(text) else ""
        col -= start
        text = shown + tail
        width = min(width, max(1, len(shown) - col))
    text = clean_text(text)
    # Keep the caret under the right character: copy tabs from the line.
    prefix = " " * len(lead) + "".join(c if c == "\t" else " " for c in text[:col])
    return ["    " + lead + text, "    " + prefix + "^" * min(width, max(1, len(text) - col))]


_DECLARATIONS = frozenset({"Function", "Var", "Domain", "RuleDecl", "Spec", "Module", "FunctionDecl",
                           "DomainDecl", "InitState", "AgentInit", "Property"})


def located_recursion_error(exc: BaseException, path: str | None = None) -> "AsmError":
    """A RecursionError raised while processing a spec, as a located error.

    Looks at what the interrupted frames were working on: when rules were being called,
    the error points at the first rule of the cycle of rules that call one another (or the
    rule that calls itself) and names the cycle; otherwise it points at the innermost spec
    construct being processed."""
    frames = []
    tb = exc.__traceback__
    while tb is not None:
        frames.append(tb.tb_frame)
        tb = tb.tb_next
    raw: list[tuple[str, Span]] = []        # rules being called, outermost first (one per frame)
    inner: Span | None = None
    for fr in frames:
        act = None
        for v in list(fr.f_locals.values()):
            sp = getattr(v, "span", None)
            if not isinstance(sp, Span) or sp.line <= 0:
                continue
            kind = type(v).__name__
            if kind not in _DECLARATIONS:
                inner = sp              # a term or a rule being worked on (not a declaration)
            if act is None and kind == "RuleDecl":
                act = (getattr(v, "name", "?"), sp)
            elif act is None and kind == "CallRule" and getattr(v, "rule", None) is not None:
                act = (getattr(v.rule, "name", "?"), getattr(v.rule, "span", sp) or sp)
        if act is not None:
            raw.append(act)
    runs: list[tuple[str, Span]] = []       # consecutive frames of one rule taken as one
    for act in raw:
        if not runs or runs[-1][0] != act[0]:
            runs.append(act)
    names = [r[0] for r in runs]
    for i, name in enumerate(names):
        if name in names[i + 1:]:
            cycle = names[i:names.index(name, i + 1) + 1]
            return AsmError(runs[i][1], f"the rules {' -> '.join(cycle)} call one another without end (or more "
                                        f"deeply than asmcheck can follow)")
    if raw:
        counts = Counter(a[0] for a in raw)
        name, times = counts.most_common(1)[0]
        span = next(a[1] for a in raw if a[0] == name)
        if times > 20:
            return AsmError(span, f"the rule {name} calls itself without end (or more deeply than asmcheck "
                                  f"can follow)")
    if inner is not None:
        return AsmError(inner, "the spec nests too deeply here (recursion limit reached)")
    where = f"{path}: " if path else ""
    return AsmError(None, f"{where}the spec nests too deeply (recursion limit reached)")


class AsmSyntaxError(AsmError):
    kind = "syntax error"


class AsmTypeError(AsmError):
    """A name, arity or type error found while resolving a spec."""

    kind = "type error"


class AsmRuntimeError(AsmError):
    """An error while running a step (inconsistent update, undef guard, ...)."""

    kind = "runtime error"


class InconsistentUpdate(AsmRuntimeError):
    pass


class Terminated(KeyboardInterrupt):
    """The process was asked to stop (SIGTERM, as ``timeout`` and CI runners send it): handled as
    Ctrl-C is, with a partial report, and named so."""


def interrupt_reason(exc=None) -> str:
    """How a report names the interruption ``exc``."""
    return "interrupted (SIGTERM)" if isinstance(exc, Terminated) else "interrupted (Ctrl-C)"


class UsageError(Exception):
    """Bad command-line usage (exit code 2)."""
