"""``asmcheck check --html``: one self-contained HTML file (inline CSS and SVG, no scripts,
no external resources) with the summary table and, for every counterexample, a picture of
the last states before the violation and the whole trace as a table."""
from __future__ import annotations

from html import escape
from pathlib import Path

from ..version import __version__
from .gate import counts, cx_summary, lasso_renamed, renamed_note, step_header
from .trace import no_change_text, step_mark

LAST_STATES = 4          # states drawn in the picture
MAX_LINES = 24           # locations per box
CHAR_W = 7.2             # width of a character of the 12px monospace font, about
LINE_H = 16

CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2em; color: #222; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; margin-top: 2em; }
table { border-collapse: collapse; margin: 0.5em 0; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
th { background: #f3f3f3; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
code, pre, td.loc, .trace td { font-family: ui-monospace, Menlo, Consolas, monospace; font-size: 12px; }
tr.pass td.verdict { color: #1a7f37; } tr.fail td.verdict, tr.error td.verdict { color: #cf222e; font-weight: bold; }
tr.incomplete td.verdict { color: #9a6700; }
.gate-pass { color: #1a7f37; } .gate-fail, .gate-error { color: #cf222e; } .gate-incomplete { color: #9a6700; }
.chg { background: #fff3b0; font-weight: bold; }
.trace tr.last td { border-top: 2px solid #cf222e; }
.note { color: #555; } .mark { color: #9a6700; } .scroll { overflow-x: auto; }
pre { background: #f6f8fa; padding: 0.8em; overflow-x: auto; }
"""


def _svg(cx) -> str:
    """The last few states as boxes, top to bottom, joined by arrows labelled with the step's
    choices; the locations each state changed are highlighted; the violation is red."""
    steps = cx.steps[-LAST_STATES:]
    if not steps:
        return ""
    # the locations shown: those the shown steps changed (the first box's own changes not counted)
    keys: list = []
    for rec in steps[1:] if len(steps) > 1 else steps:
        for k in rec.changed:
            if k not in keys:
                keys.append(k)
    if not keys:
        keys = list(steps[-1].state)
    order = {k: i for i, k in enumerate(steps[-1].state)}
    keys.sort(key=lambda k: order.get(k, len(order)))
    more = max(len(keys) - MAX_LINES, 0)
    keys = keys[:MAX_LINES]
    lines_of = []
    for rec in steps:
        rows = [(f"{k} = {rec.state.get(k, 'undef')}", k in rec.changed and rec is not steps[0]) for k in keys]
        if more:
            rows.append((f"... and {more} more", False))
        lines_of.append(rows)
    width = max(len(t) for rows in lines_of for t, _ in rows)
    width = max(width, 12)
    box_w = int(width * CHAR_W + 20)
    last = steps[-1].number
    labels = [step_header(r) + ("  " + step_mark(cx, r) if step_mark(cx, r) else "") for r in steps[1:]]
    caption = ""
    if cx.kind == "lasso" and cx.loop_start is not None:
        again = f"again {renamed_note(cx)}" if lasso_renamed(cx) else "again"
        caption = f"state {last} is state {cx.loop_start} {again}: the loop repeats for ever"
    elif cx.kind == "state":
        caption = f"state {last} violates the property"
    text_w = int(max([len(x) for x in labels] + [len(caption) - 5], default=0) * CHAR_W)
    gap = 46
    x0, y = 10, 10
    parts = []
    total_w = x0 + max(box_w, 36 + text_w) + 20
    for i, (rec, rows) in enumerate(zip(steps, lines_of)):
        h = 24 + LINE_H * len(rows) + 6
        bad = rec.number == last and cx.kind == "state"
        stroke = "#cf222e" if bad else "#555"
        parts.append(f'<g id="s{rec.number}"><rect x="{x0}" y="{y}" width="{box_w}" height="{h}" rx="6" '
                     f'fill="#fff" stroke="{stroke}" stroke-width="{3 if bad else 1.5}"/>')
        parts.append(f'<text x="{x0 + 10}" y="{y + 17}" font-weight="bold">state {rec.number}'
                     f'{" (initial)" if rec.number == 0 else ""}</text>')
        for j, (t, chg) in enumerate(rows):
            ty = y + 24 + LINE_H * (j + 1) - 4
            if chg:
                parts.append(f'<rect x="{x0 + 6}" y="{ty - 12}" width="{int(len(t) * CHAR_W + 8)}" height="{LINE_H - 1}" '
                             f'fill="#fff3b0"/>')
            weight = ' font-weight="bold"' if chg else ""
            parts.append(f'<text x="{x0 + 10}" y="{ty}"{weight}>{escape(t)}</text>')
        parts.append("</g>")
        rec_y_end = y + h
        if i + 1 < len(steps):
            nxt = steps[i + 1]
            red = nxt.number == last and cx.kind == "step"
            color = "#cf222e" if red else "#555"
            ax = x0 + 24
            parts.append(f'<line x1="{ax}" y1="{rec_y_end}" x2="{ax}" y2="{rec_y_end + gap - 2}" stroke="{color}" '
                         f'stroke-width="{2.5 if red else 1.5}" marker-end="url(#{"arr-red" if red else "arr"})"/>')
            parts.append(f'<text x="{ax + 12}" y="{rec_y_end + gap / 2 + 4:.0f}" fill="{color}">'
                         f'{escape(labels[i])}</text>')
            y = rec_y_end + gap
        else:
            y = rec_y_end
    if caption:
        parts.append(f'<text x="{x0}" y="{y + 18}" fill="#cf222e">{escape(caption)}</text>')
        y += 24
    height = y + 10
    defs = ('<defs>'
            '<marker id="arr" markerWidth="10" markerHeight="8" refX="9" refY="4" orient="auto" markerUnits="userSpaceOnUse">'
            '<path d="M0,0 L10,4 L0,8 z" fill="#555"/></marker>'
            '<marker id="arr-red" markerWidth="10" markerHeight="8" refX="9" refY="4" orient="auto" markerUnits="userSpaceOnUse">'
            '<path d="M0,0 L10,4 L0,8 z" fill="#cf222e"/></marker></defs>')
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{total_w}" height="{height}" '
            f'viewBox="0 0 {total_w} {height}" font-family="ui-monospace, Menlo, Consolas, monospace" '
            f'font-size="12" role="img" aria-label="the last states of the counterexample">'
            + defs + "".join(parts) + "</svg>")


def _trace_table(cx) -> str:
    """The trace as a table: per step the same text as the text reports (the rule, its choices
    and the inputs it read, the violation or the lasso's marks), the locations it changed and the
    whole state."""
    rows = ['<table class="trace"><tr><th>step</th><th>rule and choices</th><th>changed locations</th>'
            '<th>state</th></tr>']
    last = cx.steps[-1].number if cx.steps else -1
    for rec in cx.steps:
        head = step_header(rec)
        head = head.split(": ", 1)[1] if ": " in head else ("initial state" if rec.number == 0 else head)
        mark = step_mark(cx, rec)
        changed = "<br>".join(f'<span class="chg">{escape(k)}</span> = {escape(v)}' for k, v in rec.changed.items())
        if not changed:
            changed = f'<span class="note">{escape(no_change_text(cx, rec) if rec.number else "")}</span>'
        state = "<br>".join(f"{escape(k)} = {escape(v)}" for k, v in rec.state.items())
        cls = ' class="last"' if rec.number == last else ""
        rows.append(f'<tr{cls}><td class="num">{rec.number}</td><td>{escape(head)}'
                    + (f' <span class="mark">{escape(mark)}</span>' if mark else "")
                    + f'</td><td>{changed}</td>'
                    f'<td><details><summary>{len(rec.state)} locations</summary>{state}</details></td></tr>')
    failing = getattr(cx, "failing", None)
    if failing is not None:
        head = step_header(failing).split(": ", 1)[-1]
        rows.append(f'<tr class="last"><td class="num">{failing.number}</td><td>{escape(head)} '
                    f'<span class="mark">&lt;- fails (the step cannot be made)</span></td>'
                    f'<td><span class="note">(the step cannot be made)</span></td><td></td></tr>')
    rows.append("</table>")
    if getattr(cx, "inputs_step", False) and len(cx.steps) > 1:
        rows.append(f'<p class="note">(step {last} only shows the monitored inputs and choices of state '
                    f'{last - 1}, which are part of its state for the property)</p>')
    return "\n".join(rows)


def _section(o, p, anchor: str) -> str:
    cx = p.counterexample
    status = {"pass": "violated, as the spec expects" if p.expected else
              "violated; tolerated (the spec declares other expected violations)",
              "fail": "violated"}.get(p.status, p.label)
    out = [f'<section id="{anchor}">',
           f"<h2>{escape(p.name)} &mdash; {escape(status)}</h2>",
           f'<p>Spec <code>{escape(o.name)}</code> (<code>{escape(o.path)}</code>)'
           + (f'; {escape(p.kind)} declared at <code>{escape(str(p.location))}</code>' if p.location else "")
           + ".</p>"]
    if p.text:
        out.append(f"<pre>{escape(p.text)}</pre>")
    if cx.fairness:
        out.append(f"<p>Under fairness: <code>{escape('; '.join(cx.fairness))}</code>.</p>")
    if p.message:
        out.append(f"<p>{escape(p.message)}</p>")
    if cx.steps:
        summary = cx_summary(cx) + ("; the last state violates the property" if cx.kind == "state" else "")
        out.append(f"<p>{escape(summary[:1].upper() + summary[1:])}. "
                   f"Highlighted: the locations each step changed.</p>")
        out.append(f'<div class="scroll">{_svg(cx)}</div>')
        out.append(f'<div class="scroll">{_trace_table(cx)}</div>')
    elif cx.text:
        out.append("<pre>" + escape("\n".join(cx.text)) + "</pre>")
    if cx.avalla:
        out.append("<details><summary>Avalla scenario"
                   + (f" (<code>{escape(cx.avalla_path)}</code>)" if cx.avalla_path else "")
                   + f"</summary><pre>{escape(cx.avalla)}</pre></details>")
    out.append("</section>")
    return "\n".join(out)


def html_report(outcomes, code: int, timings: bool = True, title: str = "asmcheck check") -> str:
    gate = {0: "pass", 1: "fail", 2: "error", 3: "incomplete"}[code]
    c = counts(outcomes)
    body = [f'<h1>{escape(title)}: <span class="gate-{gate}">{gate.upper()}</span> (exit {code})</h1>',
            f'<p>{c["specs"]} spec{"s" if c["specs"] != 1 else ""}, {c["properties"]} properties: {c["holds"]} hold, '
            f'{c["expected"]} violated as expected, {c["tolerated"]} tolerated, {c["failed"]} failed, '
            f'{c["incomplete"]} incomplete, {c["errors"]} input errors.</p>']
    head = "<tr><th>spec</th><th>property</th><th>verdict</th><th>states</th>" + \
           ("<th>seconds</th>" if timings else "") + "</tr>"
    rows = ['<table class="summary">', head]
    sections = []
    n = 0
    for o in outcomes:
        for p in o.properties:
            name = escape(p.name)
            if p.counterexample is not None:
                n += 1
                anchor = f"cx{n}"
                name = f'<a href="#{anchor}">{name}</a>'
                sections.append(_section(o, p, anchor))
            rows.append(f'<tr class="{p.status}"><td><code>{escape(o.path)}</code></td><td>{name}</td>'
                        f'<td class="verdict">{escape(p.label)}</td>'
                        f'<td class="num">{o.states:,}</td>'
                        + (f'<td class="num">{o.seconds:.2f}</td>' if timings else "") + "</tr>")
    rows.append("</table>")
    body += rows
    for o in outcomes:
        if o.error:
            body.append(f"<h2>Input error: {escape(o.path)}</h2><pre>{escape(o.error)}</pre>")
        for p in o.properties:
            if p.verdict == "holds" and p.expected:
                body.append(f"<p><b>{escape(o.path)}</b>: {escape(p.name)} holds, but the spec expects it to be "
                            f"violated" + (f" ({escape(str(p.expect_location))})" if p.expect_location else "")
                            + ".</p>")
            elif p.verdict == "unknown":
                body.append(f"<p><b>{escape(o.path)}</b>: {escape(p.message)}.</p>")
        if o.reason:
            body.append(f"<p><b>{escape(o.path)}</b>: incomplete: {escape(o.reason)}.</p>")
    body += sections
    body.append(f'<footer class="note"><p>Generated by asmcheck {escape(__version__)}.</p></footer>')
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{escape(title)}: {gate.upper()}</title>\n<style>{CSS}</style>\n</head>\n<body>\n"
            + "\n".join(body) + "\n</body>\n</html>\n")


def write(path: str, text: str) -> None:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(text, encoding="utf-8")
