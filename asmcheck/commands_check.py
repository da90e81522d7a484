"""The `asmcheck check` subcommand."""
from __future__ import annotations


def register(sub) -> None:
    """Add the subcommand to `sub` (an argparse subparsers object)."""
    return None
