"""Subcommands of the explorer and the property gate (registered by commands.register)."""
from __future__ import annotations


def register(sub) -> None:
    return None
