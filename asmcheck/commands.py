"""Subcommands beyond ``parse`` (registered on the CLI's argument parser)."""
from __future__ import annotations


def register(sub) -> None:
    """Add the subcommands to ``sub`` (an argparse subparsers object)."""
