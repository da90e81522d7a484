"""``asmcheck lsp``: the AsmetaL language server (pygls, over stdio).

Diagnostics, document symbols, go to definition, find references, hover,
completion, and code lenses that explore or simulate a spec.  Positions in
LSP are 0-based; asmcheck's are 1-based: a diagnostic at LSP line L, character
C is the error the command line prints at ``file:L+1:C+1``.
"""
from __future__ import annotations

import asyncio
import hashlib
import os
import threading
import uuid
from dataclasses import dataclass
from pathlib import Path

from lsprotocol import types as lsp
from pygls.lsp.server import LanguageServer
from pygls.protocol import LanguageServerProtocol
from pygls.uris import from_fs_path, to_fs_path

from .. import __version__
from ..errors import AsmError, Span, UsageError
from ..semantics import resolve as R
from ..syntax import ast as A
from . import analysis as AN
from . import library as L
from . import runs
from .incremental import IncrementalParser, warm_up

CMD_EXPLORE = "asmcheck.explore"
CMD_COUNTEREXAMPLE = "asmcheck.showCounterexample"
CMD_SIMULATE = "asmcheck.simulate"
CONTENT_REQUEST = "asmcheck/textDocumentContent"
SOURCE = "asmcheck"
RUN_SOURCE = "asmcheck explore"


@dataclass
class Doc:
    uri: str
    path: str
    version: int | None
    analysis: AN.Analysis
    good: AN.Analysis | None        # the last analysis whose declarations were complete


def _range(sp: Span) -> lsp.Range:
    end_line, end_col = AN.span_end(sp)
    if (end_line, end_col) <= (sp.line, sp.col):
        end_line, end_col = sp.line, sp.col + 1
    return lsp.Range(lsp.Position(sp.line - 1, max(sp.col - 1, 0)),
                     lsp.Position(end_line - 1, max(end_col - 1, 0)))


def _place_range(p: AN.Place) -> lsp.Range:
    return lsp.Range(lsp.Position(p.line - 1, p.col - 1), lsp.Position(p.end_line - 1, p.end_col - 1))


def _uri_of(where: str) -> str:
    if where.startswith(L.SCHEME + ":"):
        return where
    return from_fs_path(os.path.abspath(where))


def _path_of(uri: str) -> str | None:
    if not uri.startswith("file:"):
        return None
    return to_fs_path(uri)


class _Protocol(LanguageServerProtocol):
    """pygls' protocol, which also stops a run whose request the client cancels ($/cancelRequest)."""

    def _handle_cancel_notification(self, msg_id):
        ev = self._server.request_events.get(msg_id)
        if ev is not None:
            ev.set()
        super()._handle_cancel_notification(msg_id)


class AsmServer(LanguageServer):
    def __init__(self) -> None:
        super().__init__("asmcheck", __version__, protocol_cls=_Protocol)
        self.request_events: dict = {}                           # request id -> event of its run
        self.docs: dict[str, Doc] = {}
        self.settings = runs.Settings()
        self.root_dir: str | None = None
        self.texts = AN.Texts()
        self.outcomes: dict[str, runs.ExploreOutcome] = {}       # spec uri -> last Explore
        self.run_diags: dict[str, dict[str, list[lsp.Diagnostic]]] = {}   # target uri -> spec uri -> diags
        self.virtual: dict[str, str] = {}                        # asmcheck: uri -> text
        self.cancel_events: dict[str, threading.Event] = {}      # progress token -> event
        self.run_lock = threading.Lock()
        self.parsers: dict[str, IncrementalParser] = {}
        self.base_import_path: list[str] = []                    # asmcheck lsp -I DIR

    # ------------------------------------------------------------- settings
    def apply_settings(self, raw) -> None:
        if not isinstance(raw, dict):
            return
        raw = raw.get("asmetal", raw)
        if not isinstance(raw, dict):
            return
        s = runs.Settings()
        base = self.root_dir or os.getcwd()
        ip = raw.get("importPath") or []
        if isinstance(ip, str):
            ip = [ip]
        s.import_path = list(self.base_import_path) + [
            os.path.abspath(os.path.join(base, os.path.expanduser(d))) for d in ip if d]
        s.int_range = raw.get("intRange") or None
        mon = raw.get("monitored") or []
        if isinstance(mon, dict):
            mon = [f"{k}={v}" for k, v in sorted(mon.items())]
        s.monitored = [str(m) for m in mon]
        if raw.get("exploreTimeLimit") is not None:
            s.explore_seconds = float(raw["exploreTimeLimit"])
        if raw.get("simulateSteps") is not None:
            s.simulate_steps = int(raw["simulateSteps"])
        self.settings = s
        R.set_import_path(s.import_path)      # for the diagnostics; runs give it to asmcheck.load

    # ------------------------------------------------------------- analysis
    def analyse(self, uri: str, text: str, version: int | None) -> Doc | None:
        path = _path_of(uri)
        if path is None:
            return None
        self.texts.open[os.path.abspath(path)] = text
        parser = self.parsers.get(uri)
        if parser is None and os.environ.get("ASMCHECK_LSP_INCREMENTAL") != "0":   # "0": whole texts (to measure)
            parser = self.parsers[uri] = IncrementalParser(path)
        an = AN.analyse(path, text, parser)
        old = self.docs.get(uri)
        good = an if an.root is not None else (old.good if old else None)
        doc = Doc(uri, path, version, an, good)
        self.docs[uri] = doc
        self.publish(uri)
        return doc

    def publish(self, uri: str) -> None:
        diags: list[lsp.Diagnostic] = []
        doc = self.docs.get(uri)
        if doc is not None:
            for p in doc.analysis.problems:
                related = [lsp.DiagnosticRelatedInformation(lsp.Location(_uri_of(sp.path), _range(sp)), msg)
                           for sp, msg in p.related if sp is not None and sp.line]
                diags.append(lsp.Diagnostic(_range(p.span), p.message, severity=lsp.DiagnosticSeverity.Error,
                                            source=SOURCE, related_information=related or None))
        for spec_uri in sorted(self.run_diags.get(uri, {})):
            diags.extend(self.run_diags[uri][spec_uri])
        self.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(
            uri=uri, diagnostics=diags, version=doc.version if doc else None))

    def doc(self, uri: str) -> Doc | None:
        d = self.docs.get(uri)
        if d is None:
            path = _path_of(uri)
            if path is None:
                return None
            text = self.texts.get(path)
            if text is None:
                return None
            an = AN.analyse(path, text)
            d = Doc(uri, path, None, an, an if an.root is not None else None)
        return d

    def text_of(self, uri: str) -> str | None:
        if uri.startswith(L.SCHEME + ":"):
            if uri in self.virtual:
                return self.virtual[uri]
            lib = L.library_of_uri(uri)
            return lib.text if lib else None
        d = self.docs.get(uri)
        if d is not None:
            return d.analysis.text
        p = _path_of(uri)
        return self.texts.get(p) if p else None


server = AsmServer()


# ----------------------------------------------------------------- lifecycle and sync
@server.feature(lsp.INITIALIZE)
def initialize(ls: AsmServer, params: lsp.InitializeParams):
    root = params.root_uri and _path_of(params.root_uri)
    if not root and params.workspace_folders:
        root = _path_of(params.workspace_folders[0].uri)
    ls.root_dir = root or None
    if params.initialization_options:
        ls.apply_settings(params.initialization_options)
    # load the declaration parser's tables now, not at the first edit
    threading.Thread(target=warm_up, name="asmcheck-lsp-warm-up", daemon=True).start()


@server.feature(lsp.WORKSPACE_DID_CHANGE_CONFIGURATION)
def did_change_configuration(ls: AsmServer, params: lsp.DidChangeConfigurationParams):
    ls.apply_settings(params.settings)
    for uri, d in list(ls.docs.items()):
        ls.analyse(uri, d.analysis.text, d.version)


@server.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: AsmServer, params: lsp.DidOpenTextDocumentParams):
    td = params.text_document
    ls.analyse(td.uri, td.text, td.version)


@server.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: AsmServer, params: lsp.DidChangeTextDocumentParams):
    td = ls.workspace.get_text_document(params.text_document.uri)
    ls.analyse(td.uri, td.source, params.text_document.version)


@server.feature(lsp.TEXT_DOCUMENT_DID_SAVE)
def did_save(ls: AsmServer, params: lsp.DidSaveTextDocumentParams):
    td = ls.workspace.get_text_document(params.text_document.uri)
    ls.analyse(td.uri, td.source, td.version)
    # the open specs that import the saved file read it again
    saved = os.path.abspath(_path_of(td.uri) or "")
    for uri, d in list(ls.docs.items()):
        if uri != td.uri and d.analysis.loader is not None and saved in d.analysis.loader.modules:
            ls.analyse(uri, d.analysis.text, d.version)


@server.feature(lsp.TEXT_DOCUMENT_DID_CLOSE)
def did_close(ls: AsmServer, params: lsp.DidCloseTextDocumentParams):
    uri = params.text_document.uri
    d = ls.docs.pop(uri, None)
    ls.parsers.pop(uri, None)
    if d is not None:
        ls.texts.open.pop(os.path.abspath(d.path), None)
    ls.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(uri=uri, diagnostics=[]))


# ----------------------------------------------------------------- symbols
def _symbol(name, kind, detail, full: lsp.Range, sel: lsp.Range, children=None):
    return lsp.DocumentSymbol(name=name, kind=kind, range=full, selection_range=sel, detail=detail,
                              children=children or None)


def _full(sp: Span, end: tuple[int, int]) -> lsp.Range:
    start = lsp.Position(sp.line - 1, sp.col - 1)
    e = max(end, (sp.line, sp.col + 1))
    return lsp.Range(start, lsp.Position(e[0] - 1, e[1] - 1))


_PROP_KIND = {"invariant": "invariant", "ctl": "CTLSPEC", "ltl": "LTLSPEC", "invar": "INVAR",
              "justice": "JUSTICE", "compassion": "COMPASSION"}


def document_symbols(syn: A.Spec, text: str) -> list[lsp.DocumentSymbol]:
    out = []
    for d in syn.domains:
        if d.kind == "structured" or not d.span.line:
            continue
        sel = _range(d.span)
        if d.kind == "enum":
            kids = [_symbol(el, lsp.SymbolKind.EnumMember, d.name, _range(sp), _range(sp)) for el, sp in d.elements]
            end = max((AN.span_end(sp) for _, sp in d.elements), default=AN.span_end(d.span))
            out.append(_symbol(d.name, lsp.SymbolKind.Enum, "enum domain", _full(d.span, end), sel, kids))
        else:
            detail = {"subset": "domain subsetof " + str(d.base) if d.base is not None else "domain",
                      "abstract": "abstract domain", "basic": "basic domain", "any": "anydomain"}.get(d.kind, d.kind)
            if d.dynamic:
                detail = "dynamic " + detail
            out.append(_symbol(d.name, lsp.SymbolKind.Class, detail, sel, sel))
    for f in syn.functions:
        dom = f"{f.domain} -> " if f.domain is not None else ""
        kind = lsp.SymbolKind.Constant if f.kind == "static" else lsp.SymbolKind.Function
        out.append(_symbol(f.name, kind, f"{f.kind}: {dom}{f.codomain}", _range(f.span), _range(f.span)))
    for r in syn.rules:
        params = ", ".join(f"{p.name} in {p.type}" for p in r.params)
        detail = ("main rule" if r is syn.main else "turbo rule" if r.kind == "turbo" else "rule") + (
            f"({params})" if params else "")
        out.append(_symbol(r.name, lsp.SymbolKind.Method, detail, _full(r.span, AN.node_end(r)), _range(r.span)))
    for i, p in enumerate(syn.properties):
        name = p.name or f"{_PROP_KIND.get(p.kind, p.kind)} (line {p.span.line})"
        full = _range(p.span)
        sel = _prop_name_range(p, text) or full
        out.append(_symbol(name, lsp.SymbolKind.Property, _PROP_KIND.get(p.kind, p.kind), full, sel))
    out.sort(key=lambda s: (s.range.start.line, s.range.start.character))
    return out


def _prop_name_range(p: A.Property, text: str) -> lsp.Range | None:
    if not p.name:
        return None
    lines = text.split("\n")
    for ln in range(p.span.line, min(p.span.line + 3, len(lines) + 1)):
        s = lines[ln - 1]
        start = p.span.col - 1 if ln == p.span.line else 0
        i = s.find(p.name, start)
        if i >= 0:
            return lsp.Range(lsp.Position(ln - 1, i), lsp.Position(ln - 1, i + len(p.name)))
    return None


@server.feature(lsp.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
def doc_symbols(ls: AsmServer, params: lsp.DocumentSymbolParams):
    d = ls.doc(params.text_document.uri)
    if d is None:
        if params.text_document.uri.startswith(L.SCHEME + ":"):
            return []
        return None
    an = d.analysis if d.analysis.syntax is not None else d.good
    if an is None or an.syntax is None:
        return []
    return document_symbols(an.syntax, an.text)


# ----------------------------------------------------------------- names under the cursor
def _target(ls: AsmServer, uri: str, pos: lsp.Position):
    """(doc, analysis, token, declarations or a binder) for the name at a position."""
    d = ls.doc(uri)
    if d is None:
        return None
    text = d.analysis.text
    tok = AN.token_at(text, pos.line + 1, pos.character + 1)
    if tok is None:
        return d, None, None, []
    an = d.analysis if d.analysis.root is not None else d.good
    if tok.name.startswith("$"):
        syn = d.analysis.syntax or (d.good.syntax if d.good else None)
        b = AN.vars_in_scope(AN.binders(syn), tok.line, tok.col).get(tok.name)
        return d, an, tok, b
    if an is None:
        return d, an, tok, []
    return d, an, tok, AN.lookup(an.root.scope, tok.name)


def _import_target(d: Doc, pos: lsp.Position) -> str | None:
    an = d.analysis if d.analysis.root is not None else d.good
    if an is None:
        return None
    for mod, _, ispan in an.root.imports:
        if ispan.line - 1 <= pos.line <= (ispan.end_line or ispan.line) - 1:
            if mod.library is not None:
                return L.library_uri(mod.library)
            return _uri_of(mod.path)
    return None


@server.feature(lsp.TEXT_DOCUMENT_DEFINITION)
def definition(ls: AsmServer, params: lsp.DefinitionParams):
    hit = _target(ls, params.text_document.uri, params.position)
    if hit is None:
        return None
    d, an, tok, found = hit
    if tok is None or (isinstance(found, list) and not found):
        target = _import_target(d, params.position)       # on an import clause: the module it reads
        if target is not None:
            z = lsp.Range(lsp.Position(0, 0), lsp.Position(0, 0))
            return [lsp.Location(target, z)]
        return None
    if isinstance(found, AN.Binder):
        return [lsp.Location(params.text_document.uri, _range(found.span))]
    if not found:
        return None
    idx = AN.Index(an)
    out = []
    for obj in found:
        pl = idx.place(obj)
        if pl is not None:
            loc = lsp.Location(_uri_of(pl.where), _place_range(pl))
            if loc not in out:
                out.append(loc)
    return out or None


def _analyses(ls: AsmServer, first: AN.Analysis) -> list[AN.Analysis]:
    out = [first]
    for d in ls.docs.values():
        a = d.analysis if d.analysis.root is not None else d.good
        if a is not None and a is not first:
            out.append(a)
    return out


def references_of(ls: AsmServer, an: AN.Analysis, name: str, places: set) -> list[lsp.Location]:
    seen = set()
    out = []
    for a in _analyses(ls, an):
        idx = AN.Index(a)
        mods = [m for m in a.loader.modules.values() if m.syntax is not None]
        if a.loader.time is not None:
            mods.append(a.loader.time)
        for m in mods:
            if m is a.root:
                where, text = a.path, a.text
            elif m.path.startswith("<"):
                where = L.library_uri(m.path[1:-1])
                text = ls.texts.get(where)
            else:
                where, text = m.path, ls.texts.get(m.path)
            if text is None:
                continue
            uri = _uri_of(where)
            for t in AN.tokens(text):
                if t.name != name:
                    continue
                key = (uri, t.line, t.col)
                if key in seen:
                    continue
                objs = AN.lookup(m.scope, name)
                if any(idx.place(o) in places for o in objs):
                    seen.add(key)
                    out.append(lsp.Location(uri, lsp.Range(lsp.Position(t.line - 1, t.col - 1),
                                                           lsp.Position(t.line - 1, t.end_col - 1))))
    out.sort(key=lambda l: (l.uri, l.range.start.line, l.range.start.character))
    return out


@server.feature(lsp.TEXT_DOCUMENT_REFERENCES)
def references(ls: AsmServer, params: lsp.ReferenceParams):
    hit = _target(ls, params.text_document.uri, params.position)
    if hit is None:
        return None
    d, an, tok, found = hit
    if tok is None:
        return None
    if isinstance(found, AN.Binder):
        syn = d.analysis.syntax or (d.good.syntax if d.good else None)
        bs = AN.binders(syn)
        out = []
        for t in AN.tokens(d.analysis.text):
            if t.name == tok.name and AN.vars_in_scope(bs, t.line, t.col).get(t.name) == found:
                if not params.context.include_declaration and (t.line, t.col) == (found.span.line, found.span.col):
                    continue
                out.append(lsp.Location(params.text_document.uri, lsp.Range(
                    lsp.Position(t.line - 1, t.col - 1), lsp.Position(t.line - 1, t.end_col - 1))))
        return out
    if not found or an is None:
        return None
    idx = AN.Index(an)
    places = {idx.place(o) for o in found} - {None}
    out = references_of(ls, an, tok.name, places)
    if not params.context.include_declaration:
        decl = {(_uri_of(p.where), p.line - 1, p.col - 1) for p in places}
        out = [l for l in out if (l.uri, l.range.start.line, l.range.start.character) not in decl]
    return out


@server.feature(lsp.TEXT_DOCUMENT_HOVER)
def hover(ls: AsmServer, params: lsp.HoverParams):
    hit = _target(ls, params.text_document.uri, params.position)
    if hit is None:
        return None
    d, an, tok, found = hit
    if tok is None or not found:
        return None
    rng = lsp.Range(lsp.Position(tok.line - 1, tok.col - 1), lsp.Position(tok.line - 1, tok.end_col - 1))
    if isinstance(found, AN.Binder):
        return lsp.Hover(lsp.MarkupContent(lsp.MarkupKind.Markdown, f"```asmetal\n{found.detail}\n```"), rng)
    idx = AN.Index(an)
    parts = []
    for obj in found:
        block = f"```asmetal\n{AN.describe(obj)}\n```"
        mod = AN.module_of(obj)
        if mod:
            block += f"\n\n*{mod}*"
        pl = idx.place(obj)
        if pl is not None:
            text = ls.texts.get(pl.where) if not pl.where == os.path.abspath(d.path) else d.analysis.text
            doc = AN.doc_comment(text or "", pl.line) if text else ""
            if doc:
                block += "\n\n" + doc
        if block not in parts:
            parts.append(block)
        if len(parts) >= 8:
            parts.append(f"... and {len(found) - 8} more")
            break
    return lsp.Hover(lsp.MarkupContent(lsp.MarkupKind.Markdown, "\n\n---\n\n".join(parts)), rng)


_ITEM_KIND = {"function": lsp.CompletionItemKind.Function, "rule": lsp.CompletionItemKind.Method,
              "domain": lsp.CompletionItemKind.Class, "enum": lsp.CompletionItemKind.EnumMember}


@server.feature(lsp.TEXT_DOCUMENT_COMPLETION, lsp.CompletionOptions(trigger_characters=["$"]))
def completion(ls: AsmServer, params: lsp.CompletionParams):
    d = ls.doc(params.text_document.uri)
    if d is None:
        return None
    line, col = params.position.line + 1, params.position.character + 1
    items: list[lsp.CompletionItem] = []
    syn = d.analysis.syntax or (d.good.syntax if d.good else None)
    for name, b in sorted(AN.vars_in_scope(AN.binders(syn), line, col).items()):
        items.append(lsp.CompletionItem(label=name, kind=lsp.CompletionItemKind.Variable, detail=b.detail,
                                        sort_text="0" + name))
    an = d.analysis if d.analysis.root is not None else d.good
    if an is not None:
        scope = an.root.scope
        for kind in AN.KINDS:
            for name in sorted(getattr(scope, kind)):
                objs = getattr(scope, kind)[name]
                if not objs:
                    continue
                items.append(lsp.CompletionItem(label=name, kind=_ITEM_KIND[AN.kind_of(objs[0])],
                                                detail=AN.describe(objs[0]), sort_text="1" + name))
    return lsp.CompletionList(is_incomplete=False, items=items)


# ----------------------------------------------------------------- code lenses and runs
@server.feature(lsp.TEXT_DOCUMENT_CODE_LENS)
def code_lens(ls: AsmServer, params: lsp.CodeLensParams):
    uri = params.text_document.uri
    d = ls.doc(uri)
    if d is None:
        return []
    an = d.analysis if d.analysis.syntax is not None else d.good
    if an is None or an.syntax is None or an.syntax.is_module or an.syntax.main is None:
        return []
    syn = an.syntax
    out = []
    main_r = _range(syn.main.span)
    outcome = ls.outcomes.get(uri)
    out.append(lsp.CodeLens(main_r, lsp.Command("Explore", CMD_EXPLORE, arguments=[uri])))
    out.append(lsp.CodeLens(main_r, lsp.Command(f"Simulate {ls.settings.simulate_steps} steps", CMD_SIMULATE, arguments=[uri])))
    own = {p.name for p in syn.properties if p.name}
    if outcome is not None:
        for v in outcome.verdicts:
            if v.trace is not None and v.name not in own:
                out.append(lsp.CodeLens(main_r, lsp.Command(f"Show counterexample: {v.name}", CMD_COUNTEREXAMPLE, arguments=[uri, v.name])))
    verdict_of = {v.name: v for v in outcome.verdicts} if outcome else {}
    for p in syn.properties:
        r = _prop_name_range(p, an.text) or _range(p.span)
        r = lsp.Range(r.start, r.start)
        out.append(lsp.CodeLens(r, lsp.Command("Explore", CMD_EXPLORE, arguments=[uri])))
        v = verdict_of.get(p.name) if p.name else None
        if v is not None and v.trace is not None:
            out.append(lsp.CodeLens(r, lsp.Command("Show counterexample", CMD_COUNTEREXAMPLE, arguments=[uri, v.name])))
    return out


def counterexample_uri(spec_path: str, prop: str) -> str:
    h = hashlib.sha256(os.path.abspath(spec_path).encode()).hexdigest()[:8]
    return f"{L.SCHEME}:/counterexample/{Path(spec_path).stem}/{prop}.txt?{h}"


def simulation_uri(spec_path: str) -> str:
    h = hashlib.sha256(os.path.abspath(spec_path).encode()).hexdigest()[:8]
    return f"{L.SCHEME}:/simulation/{Path(spec_path).stem}.txt?{h}"


_SEVERITY = {"violated": lsp.DiagnosticSeverity.Error, "holds": lsp.DiagnosticSeverity.Information}


def _verdict_diags(ls: AsmServer, spec_uri: str, spec_path: str, outcome: runs.ExploreOutcome):
    """Diagnostics per file: each property's verdict at its span (spec or property file)."""
    by_uri: dict[str, list[lsp.Diagnostic]] = {}
    main_span = None
    d = ls.docs.get(spec_uri)
    an = d.analysis if d and d.analysis.syntax is not None else (d.good if d else None)
    if an is not None and an.syntax is not None and an.syntax.main is not None:
        main_span = an.syntax.main.span
    for v in outcome.verdicts:
        sp = v.span if v.span is not None and v.span.line else main_span
        if sp is None:
            continue
        p = sp.path if os.path.isabs(sp.path) else os.path.abspath(sp.path)
        uri = _uri_of(p)
        if not sp.end_line:                   # a property file's position: underline the name written there
            tok = AN.token_at(ls.texts.get(p) or "", sp.line, sp.col)
            if tok is not None and tok.col == sp.col:
                sp = Span(sp.path, sp.line, sp.col, sp.line, tok.end_col)
        msg = f"{v.name}: {v.verdict} ({outcome.states:,} states, {outcome.spec})"
        if v.verdict == "incomplete" and outcome.reason:
            msg += f": {outcome.reason}"
        data = {"property": v.name, "spec": spec_uri}
        if v.trace is not None:
            data["counterexample"] = counterexample_uri(spec_path, v.name)
        diag = lsp.Diagnostic(_range(sp), msg, severity=_SEVERITY.get(v.verdict, lsp.DiagnosticSeverity.Warning),
                              source=RUN_SOURCE, code=v.verdict, data=data)
        by_uri.setdefault(uri, []).append(diag)
    return by_uri


def _progress_supported(ls: AsmServer) -> bool:
    caps = ls.client_capabilities
    return bool(caps and caps.window and caps.window.work_done_progress)


async def _with_progress(ls: AsmServer, title: str, work):
    """Run ``work(report, cancelled)`` in a thread under a cancellable $/progress."""
    token = str(uuid.uuid4())
    event = threading.Event()
    request = ls.protocol.msg_id              # the workspace/executeCommand request this run answers
    if request is not None:
        ls.request_events[request] = event
    use = _progress_supported(ls)
    if use:
        try:
            await ls.work_done_progress.create_async(token)
        except Exception:
            use = False
    if use:
        ls.cancel_events[token] = event
        ls.work_done_progress.begin(token, lsp.WorkDoneProgressBegin(title=title, cancellable=True))
    loop = asyncio.get_running_loop()

    def report(message: str):
        if use:
            loop.call_soon_threadsafe(ls.work_done_progress.report, token,
                                      lsp.WorkDoneProgressReport(message=message))

    try:
        return await loop.run_in_executor(None, work, report, event.is_set)
    except asyncio.CancelledError:
        event.set()
        raise
    finally:
        if request is not None:
            ls.request_events.pop(request, None)
        if use:
            ls.cancel_events.pop(token, None)
            ls.work_done_progress.end(token, lsp.WorkDoneProgressEnd(
                message="cancelled" if event.is_set() else "done"))


@server.feature(lsp.WINDOW_WORK_DONE_PROGRESS_CANCEL)
def progress_cancel(ls: AsmServer, params: lsp.WorkDoneProgressCancelParams):
    ev = ls.cancel_events.get(str(params.token))
    if ev is not None:
        ev.set()


async def _explore(ls: AsmServer, uri: str):
    path = _path_of(uri)
    if path is None:
        raise ValueError(f"not a file: {uri}")
    settings = ls.settings

    def work(report, cancelled):
        with ls.run_lock:
            return runs.explore(path, settings, progress=lambda s, dep, tr, secs: report(
                f"{s:,} states, depth {dep}, {secs:.1f} s"), cancelled=cancelled)

    try:
        outcome = await _with_progress(ls, f"Exploring {Path(path).name}", work)
    except runs.Cancelled:
        ls.window_show_message(lsp.ShowMessageParams(lsp.MessageType.Info, f"Exploration of {Path(path).name} "
                                                                          f"cancelled"))
        return {"cancelled": True}
    except (AsmError, UsageError) as err:
        ls.window_show_message(lsp.ShowMessageParams(lsp.MessageType.Error, str(err)))
        return {"error": str(err)}
    ls.outcomes[uri] = outcome
    for v in outcome.verdicts:
        if v.trace is not None:
            ls.virtual[counterexample_uri(path, v.name)] = v.trace + "\n"
    new = _verdict_diags(ls, uri, path, outcome)
    touched = set(new)
    for target, per_spec in ls.run_diags.items():
        if uri in per_spec:
            per_spec.pop(uri)
            touched.add(target)
    for target, diags in new.items():
        ls.run_diags.setdefault(target, {})[uri] = diags
    for target in sorted(touched):
        ls.publish(target)
    caps = ls.client_capabilities
    if caps and caps.workspace and caps.workspace.code_lens and caps.workspace.code_lens.refresh_support:
        try:
            await ls.workspace_code_lens_refresh_async(None)
        except Exception:
            pass
    return {"summary": outcome.summary, "verdict": outcome.verdict,
            "properties": [{"name": v.name, "verdict": v.verdict,
                            "counterexample": counterexample_uri(path, v.name) if v.trace is not None else None}
                           for v in outcome.verdicts]}


@server.command(CMD_EXPLORE)
async def cmd_explore(ls: AsmServer, *args):
    return await _explore(ls, str(args[0]))


async def _show(ls: AsmServer, uri: str):
    caps = ls.client_capabilities
    if caps and caps.window and caps.window.show_document and caps.window.show_document.support:
        try:
            await ls.window_show_document_async(lsp.ShowDocumentParams(uri=uri, take_focus=True))
        except Exception:
            pass


@server.command(CMD_COUNTEREXAMPLE)
async def cmd_counterexample(ls: AsmServer, *args):
    uri, name = str(args[0]), str(args[1])
    path = _path_of(uri)
    if uri not in ls.outcomes:
        await _explore(ls, uri)
    target = counterexample_uri(path, name)
    if target not in ls.virtual:
        return None
    await _show(ls, target)
    return target


@server.command(CMD_SIMULATE)
async def cmd_simulate(ls: AsmServer, *args):
    uri = str(args[0])
    path = _path_of(uri)
    settings = ls.settings

    def work(report, cancelled):
        with ls.run_lock:
            return runs.simulate(path, settings)

    try:
        text = await _with_progress(ls, f"Simulating {Path(path).name}", work)
    except (AsmError, UsageError) as err:
        ls.window_show_message(lsp.ShowMessageParams(lsp.MessageType.Error, str(err)))
        return {"error": str(err)}
    target = simulation_uri(path)
    ls.virtual[target] = text
    await _show(ls, target)
    return target


@server.feature(CONTENT_REQUEST)
def text_document_content(ls: AsmServer, params):
    uri = params.get("uri") if isinstance(params, dict) else getattr(params, "uri", None)
    text = ls.text_of(str(uri)) if uri else None
    return {"text": text}


def main(import_path: list[str] | None = None) -> int:
    """Serve over the process's stdin and stdout; anything printed meanwhile goes to stderr, so the
    protocol's channel carries only the protocol.  ``import_path`` (``asmcheck lsp -I DIR``) comes
    before the folders of the editor's ``importPath`` setting."""
    import sys
    server.base_import_path = [os.path.abspath(d) for d in import_path or []]
    server.apply_settings({})
    stdin, stdout = sys.__stdin__.buffer, sys.__stdout__.buffer
    saved = sys.stdout
    sys.stdout = sys.stderr
    try:
        server.start_io(stdin, stdout)
    finally:
        sys.stdout = saved
    return 0
