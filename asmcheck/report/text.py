"""The gate's results as text: the table ``asmcheck check`` prints, the details of what went
wrong (with counterexamples) and the summary line."""
from __future__ import annotations

from .gate import ERROR, FAIL, INCOMPLETE, counts
from .trace import trace_lines, violation_head, violation_lines


def summary_table(outcomes, color: bool = False, timings: bool = True) -> list[str]:
    head = ["SPEC", "PROPERTY", "VERDICT", "STATES"] + (["SECONDS"] if timings else [])
    rows = []
    for o in outcomes:
        for p in o.properties:
            # (a spec not read, or not reached before a Ctrl-C, has no count of states)
            row = [o.path, p.name, p.label, f"{o.states:,}" if o.verdict != "error" and o.name else "-"]
            if timings:
                row.append(f"{o.seconds:.2f}")
            rows.append((row, p.status))
    widths = [max([len(head[i])] + [len(r[i]) for r, _ in rows]) for i in range(len(head))]

    def fmt(cells, status=None):
        parts = []
        for i, c in enumerate(cells):
            if i >= 3:
                parts.append(c.rjust(widths[i]))
            else:
                parts.append(c.ljust(widths[i]) if i < len(cells) - 1 else c)
        line = "  ".join(parts).rstrip()
        if color and status in (FAIL, ERROR):
            line = f"\x1b[1;31m{line}\x1b[0m"
        elif color and status == INCOMPLETE:
            line = f"\x1b[33m{line}\x1b[0m"
        return line
    out = [fmt(head)]
    out.extend(fmt(r, s) for r, s in rows)
    return out


def details(outcomes, color: bool = False, traces: str = "failing") -> list[str]:
    """What went wrong, spec by spec, with the counterexamples."""
    out = []
    for o in outcomes:
        if o.error:
            out.append("")
            out.append(f"ERROR {o.path}: the spec could not be checked" if getattr(o, "subject", "spec") == "spec"
                       else f"ERROR {o.path}: the {o.subject} does not apply")
            out.extend("  " + ln for ln in o.error.splitlines())
            continue
        for p in o.properties:
            show_trace = p.counterexample is not None and (
                traces == "all" or (traces == "failing" and p.status == FAIL))
            if p.status == PASS_STATUS and not show_trace:
                continue
            where = f" ({p.location})" if p.location else ""
            tag = {FAIL: "FAIL", ERROR: "ERROR", INCOMPLETE: "INCOMPLETE"}.get(p.status, "NOTE")
            head = f"{tag} {o.path}: "
            if p.verdict == "violated":
                cx = p.counterexample
                n = len(cx.steps) - 1 if cx and cx.steps else None
                rel = f" at {p.relative_to}" if getattr(p, "relative_to", None) is not None else None
                head += violation_head(p.name, p.kind, where, p.message, rel)
                if p.expected:
                    head += " (expected)"
                elif p.status != FAIL:
                    head += " (tolerated: the spec declares other expected violations)"
                if getattr(p, "decided_on", None) is not None:
                    head += f" (decided on the {p.decided_on:,} states explored)"
                out.append("")
                if show_trace and n is not None:
                    out.extend(violation_lines(head, cx, color, p.text, cx.fairness))
                elif show_trace:
                    out.append(head)
                    out.extend("  " + ln for ln in trace_lines(cx, color))
                else:
                    out.append(head)
                if show_trace:
                    if cx.avalla_path:
                        out.append(f"  Avalla scenario: {cx.avalla_path}")
            elif p.verdict == "holds" and p.expected:
                at = f" ({p.expect_location})" if p.expect_location else ""
                out.append("")
                out.append(head + f"{p.name}{where} holds, but the spec expects it to be violated{at}")
            elif p.verdict == "unknown":
                at = f"{p.expect_location}: " if p.expect_location else ""
                out.append("")
                out.append(head + at + p.message)
            elif p.status == ERROR:
                out.append("")
                out.append(head + f"{p.name}{where}: {p.label}" + (f": {p.message}" if p.message else ""))
            elif p.status == INCOMPLETE:
                why = o.reason or p.message
                out.append("")
                out.append(head + f"{p.name}: {p.label}" + (f" ({why})" if why else ""))
    return out


PASS_STATUS = "pass"


def summary_line(outcomes, code: int) -> list[str]:
    c = counts(outcomes)
    gate = {0: "PASS", 1: "FAIL", 2: "ERROR", 3: "INCOMPLETE"}[code]
    return [f"checked {c['specs']} spec{'s' if c['specs'] != 1 else ''}, {c['properties']} "
            f"propert{'ies' if c['properties'] != 1 else 'y'}: {c['holds']} hold, {c['expected']} violated as "
            f"expected, {c['tolerated']} tolerated, {c['failed']} failed, {c['incomplete']} incomplete, "
            f"{c['errors']} input error{'s' if c['errors'] != 1 else ''}",
            f"gate: {gate} (exit {code})"]


def check_text(outcomes, code: int, color: bool = False, timings: bool = True, traces: str = "failing",
               table: bool = True) -> str:
    """The text ``asmcheck check`` prints (``table=False``: without the table, which a terminal
    shows in colour)."""
    lines = summary_table(outcomes, color, timings) if table else []
    lines += details(outcomes, color, traces)
    lines.append("")
    lines += summary_line(outcomes, code)
    return "\n".join(lines) + "\n"
