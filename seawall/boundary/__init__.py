"""Wall treatments: one module per family, all behind the WallModel interface.

``registry`` maps the command-line names to factories, so cases and the CLI
can build any model by name.
"""

from .base import EvaluationContext, WallModel, WallSystem
from .dbc import DynamicBoundary, ImprovedDynamicBoundary
from .dummy import DummyParticles
from .ghost import GhostParticles
from .interpolation import MLS, SFDI, ImprovedShepard, Interpolation, Normalised
from .liu2012 import Liu2012Force
from .liu2015 import Liu2015Wall
from .lust import LocalUniformStencil
from .movement import PrescribedMotion
from .repulsive import MonaghanKajtar
from .registry import BOUNDARIES, boundary_by_name

__all__ = ["WallModel", "WallSystem", "EvaluationContext", "DummyParticles", "DynamicBoundary",
           "ImprovedDynamicBoundary", "GhostParticles", "MonaghanKajtar", "Liu2012Force", "Liu2015Wall",
           "LocalUniformStencil",
           "Interpolation", "MLS", "SFDI", "Normalised", "ImprovedShepard", "PrescribedMotion", "BOUNDARIES",
           "boundary_by_name"]
