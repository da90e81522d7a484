"""Located errors and the source registry used to print them.

Every error asmcheck reports about a spec carries a :class:`Span` and is
printed as ``file:line:col: message`` followed by the source line and a caret.
"""
from __future__ import annotations

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

    def render(self) -> str:
        """``file:line:col: message``, the source line and a caret (and notes)."""
        out = [str(self)]
        out.extend(_quote(self.span))
        for span, note in self.notes:
            out.append(f"{span}: note: {note}" if span and span.line else f"note: {note}")
            out.extend(_quote(span))
        return "\n".join(out)


def _quote(span: Span | None) -> list[str]:
    if span is None or span.line == 0:
        return []
    text = SOURCES.line(span.path, span.line)
    if text is None:
        return []
    # Keep the caret under the right character: copy tabs from the line.
    prefix = "".join(c if c == "\t" else " " for c in text[: max(span.col - 1, 0)])
    width = 1
    if span.end_line == span.line and span.end_col > span.col:
        width = span.end_col - span.col
    return ["    " + text, "    " + prefix + "^" * min(width, max(1, len(text) - span.col + 1))]


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


class UsageError(Exception):
    """Bad command-line usage (exit code 2)."""
