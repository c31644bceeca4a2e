"""The limits of the model layer: what a (hostile) model file may ask for.

Each limit is checked before the work it bounds; docs/security.md lists them
and how to change them.
"""

from __future__ import annotations

TOP_LEVEL = ("title", "description", "parameters", "coordinates", "equilibrium", "signals",
             "definitions", "energy", "force", "outputs", "matrices", "harmonic", "exercise",
             "variants", "gravity", "point", "body", "spring", "damper", "torque", "display",
             "study", "explore", "nonlinear", "random", "shock", "fatigue",
             "periodic", "measurement", "campbell", "rotor", "unbalance")
#: the part sections (docs/parts.md; resonant.model.parts)
PART_SECTIONS = ("point", "body", "spring", "damper", "torque")
#: most entries of each part section ([[body]], [[spring]], ...)
MAX_PARTS = 1000
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

# -- matrix files ([matrices] M/K/C = "file.npy" | "file.npz" | "file.mtx") ----------------
# Checked from the file's header (.npy header, zip directory, Matrix Market size line)
# before anything is allocated or decompressed.  The loader reads these module
# attributes at call time, so ``resonant.model.limits.MAX_MATRIX_DIMENSION = 10**6``
# raises a limit for the rest of the process.

#: largest matrix size n (an n x n matrix; dense or sparse)
MAX_MATRIX_DIMENSION = 200_000
#: most stored entries of a sparse matrix (.npz in scipy's layout, coordinate .mtx);
#: a symmetric .mtx counts twice
MAX_MATRIX_NONZEROS = 20_000_000
#: most entries (n*n) of a dense matrix (.npy, dense .npz member, array .mtx): 200 MB of float64
MAX_DENSE_ENTRIES = 25_000_000
#: most bytes of all members of one .npz archive together, decompressed
MAX_DECOMPRESSED_BYTES = 512 * 2**20
#: largest decompressed/compressed ratio of one .npz member; deflate (what numpy
#: writes) cannot exceed about 1032, so this refuses forged headers, not real files
MAX_COMPRESSION_RATIO = 1100
#: most members of one .npz archive (numpy/scipy write at most 6)
MAX_ARCHIVE_MEMBERS = 64
#: largest matrix file on disk (a 20-million-entry .mtx is text of about 600 MB)
MAX_MATRIX_FILE_BYTES = 2**30

__all__ = ["TOP_LEVEL", "PART_SECTIONS", "MAX_PARTS", "ENERGY_KEYS", "MAX_FILE_BYTES",
           "MAX_COORDINATES", "MAX_INLINED_NODES",
           "MAX_INLINED_DEGREE", "MAX_MATRIX_DIMENSION", "MAX_MATRIX_NONZEROS",
           "MAX_DENSE_ENTRIES", "MAX_DECOMPRESSED_BYTES", "MAX_COMPRESSION_RATIO",
           "MAX_ARCHIVE_MEMBERS", "MAX_MATRIX_FILE_BYTES"]

# -- counts of a model's entries, checked right after the TOML is parsed, before any
# expression is parsed or evaluated (100000 parameters once took 75 s).  Read at
# call time, like the limits above.

#: most [parameters] (each is parsed and evaluated exactly, in order)
MAX_PARAMETERS = 10_000
#: most [signals] (each is split into harmonics and compiled)
MAX_SIGNALS = 1000
#: most [definitions]
MAX_DEFINITIONS = 10_000
#: most [outputs] (each is a row of every result: a sweep stores points x outputs)
MAX_OUTPUTS = 2000
#: most [[force]] entries
MAX_FORCES = 10_000
#: most [[harmonic]] entries of a [matrices] model
MAX_HARMONICS = 1000

__all__ += ["MAX_PARAMETERS", "MAX_SIGNALS", "MAX_DEFINITIONS", "MAX_OUTPUTS", "MAX_FORCES",
            "MAX_HARMONICS"]

#: the highest frequency (Hz) an analysis in the frequency domain takes: above it the
#: dynamic stiffness w^2 M and the spectral moments (f^4 times a density) leave the
#: floating-point range, or no digit of the response is left beside w^2 M
MAX_FREQUENCY_HZ = 1e15

__all__ += ["MAX_FREQUENCY_HZ"]
