"""``asmcheck lsp``: the AsmetaL language server, over stdin and stdout, for editors."""
from __future__ import annotations

from .common import EXIT_ERROR, error


def run(args) -> int:
    from .. import lsp
    why = lsp.available()
    if why is not None:
        error(f"asmcheck: error: {why}")
        return EXIT_ERROR
    return lsp.main(import_path=list(getattr(args, "import_path", None) or []))


def register(sub) -> None:
    p = sub.add_parser(
        "lsp", help="serve the Language Server Protocol over stdio (for editors)",
        description="Run the AsmetaL language server over stdin and stdout: diagnostics, outline, go to "
                    "definition, references, hover, completion, and Explore / Simulate code lenses. Editors start "
                    "it (editors/vscode is a VS Code extension that does). Needs the 'lsp' extra: "
                    "pip install 'asmcheck[lsp]'. -I DIR: folders searched for imports, as for the other "
                    "commands (the editor's settings add to them).")
    p.set_defaults(func=run)
