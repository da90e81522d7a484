"""``asmcheck parse``: parse and type-check files."""
from __future__ import annotations

import json

from .. import api
from .common import EXIT_ERROR, EXIT_OK, out


def run(args) -> int:
    results = []
    dirs = list(getattr(args, "import_path", None) or [])
    for path in args.files:
        try:
            api.parse(path, import_path=dirs)
            results.append((path, None))
        except api.AsmError as err:
            results.append((path, err))
    if args.format == "json":
        doc = {"files": [{"path": p, "ok": e is None, "error": None if e is None else _error(e)}
                         for p, e in results]}
        out(json.dumps(doc, indent=2))
    else:
        for p, e in results:
            out(f"{p}: OK" if e is None else e.render())
    return EXIT_OK if all(e is None for _, e in results) else EXIT_ERROR


def _error(err) -> dict:
    sp = err.span
    return {"path": sp.path if sp else None, "line": sp.line if sp and sp.line else None,
            "column": sp.col if sp and sp.line else None, "message": err.message}


def register(sub) -> None:
    sp = sub.add_parser("parse", help="parse and type-check AsmetaL files",
                        description="Parse and type-check each FILE (with its imports); print OK or the error.")
    sp.add_argument("files", nargs="+", metavar="FILE")
    sp.add_argument("--format", choices=["text", "json"], default="text")
    sp.set_defaults(func=run)
