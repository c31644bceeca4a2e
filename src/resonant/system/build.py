"""A model's systems: its :class:`~resonant.system.base.LinearSystem` and its
:class:`~resonant.system.nonlinear.NonlinearSystem` (derived and compiled once)."""

from __future__ import annotations

from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError
from ..model import Model
from .base import LinearSystem
from .element_system import ElementSystem
from .matrix import MatrixEOM
from .nonlinear import EnergySystem, NonlinearSystem
from .symbolic import LinearEOM


def linear_system(model: Model, deadline: Deadline = NO_DEADLINE) -> LinearSystem:
    """The linear system of a model: derived from its energies, or its given matrices.

    Parameters
    ----------
    model : Model
    deadline : Deadline, optional
        Checked throughout the derivation.

    Returns
    -------
    LinearSystem

    Raises
    ------
    ModelError
        If the derivation fails (see :func:`resonant.derivation.linearize`).

    Examples
    --------
    >>> import resonant
    >>> type(linear_system(resonant.load("examples/two_dof_free.toml"))).__name__
    'LinearEOM'
    """
    if model.matrices is not None:
        return MatrixEOM(model, model.coordinates)
    return LinearEOM.of_model(model, deadline)


def nonlinear_system(source: Model | LinearSystem | NonlinearSystem,
                     deadline: Deadline = NO_DEADLINE) -> NonlinearSystem:
    """The nonlinear system of a model (or of its linear system): derived and compiled once.

    Parameters
    ----------
    source : Model, LinearSystem or NonlinearSystem
        A model given by its energies or a ``[matrices]`` model with ``[[nonlinear]]``
        elements, or its linear system (``model.linearize()``); a NonlinearSystem is
        returned as it is.
    deadline : Deadline, optional
        Checked by the linear derivation and before the compilation.

    Returns
    -------
    NonlinearSystem
        An :class:`EnergySystem` (energies) or an
        :class:`~resonant.system.element_system.ElementSystem` (matrices and elements).

    Raises
    ------
    AnalysisError
        For a ``[matrices]`` model without ``[[nonlinear]]`` elements (it has no nonlinear
        equations) or a linear system without a model.

    Examples
    --------
    >>> from resonant.model import loads
    >>> model = loads('[parameters]\\nk = 4\\n[coordinates]\\nx = ""\\n'
    ...               '[energy]\\nT = "x\\'^2/2"\\nU = "k*x^2/2"')
    >>> system = nonlinear_system(model)
    >>> system.coordinates, system.linear.numeric().K.tolist()
    (('x',), [[4.0]])
    """
    if isinstance(source, NonlinearSystem):
        return source
    if isinstance(source, Model):
        model = source
        linear: LinearSystem | None = None
    else:
        if source.model is None:
            raise AnalysisError("this system has no model: the full equations of motion "
                                "need a model given by its energies")
        model, linear = source._model(), source
    if model.matrices is not None and model.matrices.nonlinear:
        return ElementSystem(linear or MatrixEOM(model, model.coordinates), deadline)
    if model.matrices is not None or isinstance(linear, MatrixEOM):
        raise AnalysisError("a [matrices] model without [[nonlinear]] elements has no "
                            "nonlinear equations: the full equations of motion need a model "
                            "given by its energies or nonlinear elements")
    if linear is None:
        linear = LinearEOM.of_model(model, deadline)
    deadline.check("before compiling the full equations of motion", analysis=True)
    return EnergySystem(model, linear)
