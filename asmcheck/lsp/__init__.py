"""The AsmetaL language server (``asmcheck lsp``): diagnostics, navigation, completion, code lenses.

It needs the optional dependencies of the ``lsp`` extra (``pip install 'asmcheck[lsp]'``).
"""
from __future__ import annotations


def available() -> str | None:
    """None when the server can run; otherwise why not."""
    try:
        import lsprotocol  # noqa: F401
        import pygls  # noqa: F401
    except ImportError as exc:
        return (f"the language server needs pygls and lsprotocol ({exc}); install them with "
                f"pip install 'asmcheck[lsp]'")
    return None


def main(import_path: list[str] | None = None) -> int:
    """Serve the Language Server Protocol over stdin and stdout (``asmcheck lsp [-I DIR]``)."""
    import sys
    why = available()
    if why is not None:
        print(f"asmcheck: error: {why}", file=sys.stderr)
        return 2
    from .server import main as serve
    return serve(import_path or [])
