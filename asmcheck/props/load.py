"""A spec, its step function and the properties that apply to it, loaded in one call.

The engines below the public API (:mod:`asmcheck.smt`, the differential tests) and the API
itself load specs through :func:`load_machine` and :func:`load_properties`."""
from __future__ import annotations

from ..errors import AsmError
from ..semantics.machine import Machine
from ..semantics.resolve import check_file
from . import spec_properties
from .files import properties_for


def load_machine(path: str, options: dict | None = None):
    """(spec, Machine) of the spec at ``path``; an :class:`AsmError` when it cannot run."""
    spec = check_file(path)
    if spec is None:
        raise AsmError(None, f"{path}: the file is empty: nothing to run")
    if spec.main is None:
        raise AsmError(spec.root_module.syntax.span if spec.root_module.syntax else None,
                       f"{spec.name} has no main rule: nothing to run (is it a module?)")
    return spec, Machine(spec, options or {})


def load_properties(spec, machine, path: str, files=None, use_default: bool = True):
    """(state properties, step properties, temporal properties and fairness): the spec's own
    invariants and those of the property files that apply (see :func:`properties_for`)."""
    state_props, step_props = spec_properties(machine)
    extra_state, extra_step, temporal = properties_for(spec, machine, path, files, use_default=use_default)
    return state_props + extra_state, step_props + extra_step, temporal
