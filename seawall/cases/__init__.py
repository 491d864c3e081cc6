"""The named cases, one definition each, shared by the CLI, tests, benchmarks and validation."""

from __future__ import annotations

from typing import Any

from ..errors import ParameterError
from .base import Case, Parameter, outline_wall, tank_wall, wall_layers
from .channels import CHANNEL, PIPE_3D
from .dem_box import DEM_BOX
from .flows import COUETTE, ELLIPTICAL_DROP, POISEUILLE, TAYLOR_GREEN
from .idbc_tests import DROP_IMPACT, PARTICLE_IN_BOX
from .lid_cavity import CAVITY
from .liu2015 import DAM_BREAK_ETSIN, PLATES
from .moving import MOVING_WALL
from .s_cavity import S_CAVITY
from .tanks import COLLAPSE, DAM_BREAK, DAM_BREAK_3D, HYDROSTATIC
from .waves import MOVABLE_SEAWALL, SOLITARY_RUNUP, SOLITARY_SEAWALL, SOLITARY_WAVE
from ..runner import Runner

CASES = {c.name: c for c in (HYDROSTATIC, DAM_BREAK, COLLAPSE, DAM_BREAK_3D, PARTICLE_IN_BOX, DROP_IMPACT, MOVING_WALL,
                                DEM_BOX, SOLITARY_WAVE, SOLITARY_SEAWALL, SOLITARY_RUNUP, MOVABLE_SEAWALL,
                                CHANNEL, S_CAVITY, PIPE_3D,
                                POISEUILLE, COUETTE, TAYLOR_GREEN, ELLIPTICAL_DROP, CAVITY,
                                PLATES, DAM_BREAK_ETSIN)}


def case_by_name(name: str) -> Case:
    """Return the :class:`Case` called ``name``, or the case of the file ``name`` (``.py`` or ``.toml``)."""
    from .files import is_case_file, load_case_file

    if name not in CASES and is_case_file(name):
        return load_case_file(name)
    try:
        return CASES[name]
    except KeyError:
        raise ParameterError(f"unknown case {name!r}; available: {', '.join(CASES)} "
                             f"(or a case file ending in .py or .toml)") from None


def build(name: str, **params: Any) -> Runner:
    """Build case ``name`` (see ``seawall cases``; or a case file's path) and return its Simulation."""
    return case_by_name(name).build(**params)


__all__ = ["CASES", "Case", "Parameter", "case_by_name", "build", "outline_wall", "tank_wall", "wall_layers"]
