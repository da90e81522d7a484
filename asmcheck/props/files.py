"""Property files (properties/*.prop): which apply to a spec, and their properties."""
from __future__ import annotations


def properties_for(spec, machine, spec_path, files=None, use_default=True):
    """(state properties, step properties, temporal properties) from property files."""
    return [], [], []
