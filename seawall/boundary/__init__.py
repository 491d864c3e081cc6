"""Wall treatments: one module per family, all behind the WallModel interface.

``registry`` maps the command-line names to factories, so cases and the CLI
can build any model by name.
"""

from .base import EvaluationContext, WallModel, WallSystem
from .dbc import DynamicBoundary, ImprovedDynamicBoundary
from .dummy import DummyParticles
from .registry import BOUNDARIES, boundary_by_name

__all__ = ["WallModel", "WallSystem", "EvaluationContext", "DummyParticles", "DynamicBoundary",
           "ImprovedDynamicBoundary", "BOUNDARIES",
           "boundary_by_name"]
