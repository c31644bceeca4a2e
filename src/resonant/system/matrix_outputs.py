"""The outputs of a ``[matrices]`` model in full, evaluated on time samples.

The linear system (:class:`resonant.system.MatrixEOM`) carries the outputs
linearized at rest; a periodic motion of the nonlinear equations needs them in
full: :class:`OutputSeries` compiles every ``[outputs]`` expression once (sympy,
numpy) as a function of the coordinates it reads, their first two rates and the
parameters, and evaluates it at many samples at once.

Examples
--------
>>> import numpy as np
>>> from resonant.model import loads
>>> model = loads('''
... [parameters]
... k = 3
... [matrices]
... M = [[1, 0], [0, 1]]
... K = [[2, -1], [-1, 1]]
... [outputs]
... force = "k*(q2 - q1)^3"
... ''')
>>> out = OutputSeries(model.outputs, ("q1", "q2"))
>>> out.coordinates
('q1', 'q2')
>>> samples = np.zeros((3, 2, 2)); samples[0, 1] = [1.0, 2.0]   # q2 = 1, 2
>>> out(samples, {"k": 3.0}).tolist()
[[3.0, 24.0]]
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import sympy

from ..errors import ModelError, Problem
from ..expressions import Expression, compilable

#: the highest rate of a coordinate an output may read (an acceleration)
MAX_RATE = 2


class OutputSeries:
    """The outputs of a ``[matrices]`` model as one compiled function of samples.

    Parameters
    ----------
    outputs : mapping
        name -> :class:`~resonant.expressions.Expression` (``model.outputs``).
    coordinates : sequence of str
        The model's coordinates.
    source : str, optional
        The model file, for messages.

    Attributes
    ----------
    names : tuple of str
        The outputs, in order.
    coordinates : tuple of str
        The coordinates the outputs read, in the model's order.
    parameters : tuple of str
        The parameters the outputs read.

    Raises
    ------
    ModelError
        For an output that reads a coordinate's third or higher rate.

    Examples
    --------
    See the module docstring.
    """

    def __init__(self, outputs: Mapping[str, Expression], coordinates: Sequence[str],
                 source: str = "") -> None:
        self.names = tuple(outputs)
        used = {name for e in outputs.values() for name, _ in e.names()}
        self.coordinates = tuple(q for q in coordinates if q in used)
        self.parameters = tuple(sorted(used - set(coordinates)))
        samples = {(q, k): sympy.Symbol(f"{q}__{k}", real=True)
                   for k in range(MAX_RATE + 1) for q in self.coordinates}
        exprs = []
        for name, expression in outputs.items():
            def resolve(label: str, primes: int, name: str = name) -> sympy.Expr:
                if (label, primes) in samples:
                    return samples[(label, primes)]
                if label in self.coordinates:
                    raise ModelError(Problem(f"an output may read up to the second rate of "
                                             f"a coordinate, not {label}{chr(39) * primes}",
                                             source, "outputs", name))
                return sympy.Symbol(label, real=True)
            exprs.append(compilable(expression.to_sympy(resolve)))
        arguments = [*samples.values(), *(sympy.Symbol(p, real=True) for p in self.parameters)]
        self._fn = sympy.lambdify(arguments, exprs, modules="numpy", cse=True)

    def __call__(self, samples: np.ndarray, values: Mapping[str, float]) -> np.ndarray:
        """The outputs at k samples.

        Parameters
        ----------
        samples : ndarray
            (3, c, k): the c coordinates of :attr:`coordinates`, their rates and their
            second rates at k instants.
        values : mapping
            Parameter values (at least :attr:`parameters`).

        Returns
        -------
        ndarray
            (outputs, k); NaN where an output is not finite or not real.
        """
        count = samples.shape[-1]
        flat = samples.reshape(-1, count)
        with np.errstate(all="ignore"):
            raw = self._fn(*flat, *(values[p] for p in self.parameters))
        out = np.array([np.broadcast_to(np.asarray(v), (count,)) for v in raw])
        if np.iscomplexobj(out):
            out = np.where(out.imag == 0, out.real, np.nan)
        return out.astype(float).reshape(len(self.names), count)


__all__ = ["OutputSeries", "MAX_RATE"]
