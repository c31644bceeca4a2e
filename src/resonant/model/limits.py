"""The limits of the model layer: what a (hostile) model file may ask for.

Each limit is checked before the work it bounds; docs/security.md lists them
and how to change them.
"""

from __future__ import annotations

TOP_LEVEL = ("title", "description", "parameters", "coordinates", "equilibrium", "signals",
             "definitions", "energy", "force", "outputs", "matrices", "harmonic")
ENERGY_KEYS = ("T", "U", "D")
#: largest model accepted, so that a hostile file cannot exhaust memory
MAX_FILE_BYTES = 5_000_000
MAX_COORDINATES = 2000
#: largest size (syntax-tree nodes) of a definition with the definitions it uses
#: substituted, counted with multiplicity: ``d2 = d1*d1`` doubles, a chain
#: ``y2 = y1 + x2`` only adds.  Beyond it the derivation grows exponentially.
MAX_INLINED_NODES = 250_000
#: largest polynomial degree of a definition after substitution (``d2 = d1^2`` ...)
MAX_INLINED_DEGREE = 10_000

__all__ = ["TOP_LEVEL", "ENERGY_KEYS", "MAX_FILE_BYTES", "MAX_COORDINATES", "MAX_INLINED_NODES",
           "MAX_INLINED_DEGREE"]
