"""The analyses' results as the user gets them: the same data, with their views.

Each class here is a subclass of an analysis result (same fields, same
``to_dict()``) that adds the methods which draw or describe it:
``summary()``, ``plot()`` and the Jupyter reprs.  They are defined here, above
both the analyses and the views, so that each method is a visible one-line call
of its view; the analyses themselves return the plain results
(:func:`promote` turns one into the other without copying its arrays).

Examples
--------
>>> import resonant
>>> sol = resonant.load("examples/cart_pendulum.toml").linearize().stationary()
>>> type(sol).__name__, type(sol).__mro__[1].__module__
('StationarySolution', 'resonant.analyses.stationary')
>>> print(sol.summary().splitlines()[0].split("  (")[0])
Cart with pendulum under force and support excitation
"""

from __future__ import annotations

import inspect
from pathlib import Path
from typing import Any, TypeVar

from ..analyses import backbone, harmonic_balance, modes, simulate, stationary, sweep
from ..studies import result as study_result
from ..views import display, nonlinear_plots, plotting, study_plots

__all__ = ["Backbones", "FrequencyResponse", "ModalAnalysis", "NonlinearResponse",
           "Simulation", "StationarySolution", "Study", "promote"]

T = TypeVar("T")


def fields_of_base(cls: type[T]) -> type[T]:
    """Append the base result's Attributes section to ``cls``'s docstring: the fields are
    the base's, documented once, where they are defined."""
    base_doc = inspect.getdoc(cls.__mro__[1]) or ""
    start = base_doc.find("Attributes\n----------")
    end = base_doc.find("Examples\n--------")
    own = inspect.getdoc(cls) or ""
    head, examples = own.split("Examples\n--------", 1) if "Examples\n--------" in own \
        else (own, "")
    fields = base_doc[start:end if end > start else None].rstrip() if start >= 0 else ""
    cls.__doc__ = head.rstrip() + "\n\n" + fields + \
        ("\n\nExamples\n--------" + examples if examples else "")
    return cls


def promote(subclass: type[T], result: object) -> T:
    """The same result as an instance of ``subclass``, a subclass of its type that adds views.

    The fields are shared, not copied (results are frozen, their arrays read-only).

    Parameters
    ----------
    subclass : type
        The subclass to promote to.
    result : object
        An instance of a base class of ``subclass``.

    Returns
    -------
    object
        ``result`` itself if it already is a ``subclass``, else a new ``subclass``
        holding its fields.

    Examples
    --------
    >>> class Base:
    ...     def __init__(self):
    ...         self.x = 1
    >>> class WithView(Base):
    ...     def show(self):
    ...         return f"x = {self.x}"
    >>> promote(WithView, Base()).show()
    'x = 1'
    """
    if isinstance(result, subclass):
        return result
    if not issubclass(subclass, type(result)):
        raise TypeError(f"cannot promote a {type(result).__name__} to {subclass.__name__}")
    promoted = object.__new__(subclass)
    promoted.__dict__.update(result.__dict__)
    return promoted


@fields_of_base
class StationarySolution(stationary.StationarySolution):
    """A :class:`resonant.analyses.stationary.StationarySolution` with its text and reprs.

    Examples
    --------
    >>> import resonant
    >>> sol = resonant.load("examples/cart_pendulum.toml").linearize().stationary()
    >>> sol.natural_frequencies.round(4).tolist()
    [4.5607, 7.93]
    """

    def summary(self) -> str:
        """The text ``resonant solve`` prints.

        Returns
        -------
        str
        """
        return display.solution_text(self)

    def _repr_html_(self) -> str:
        return display.stationary_html(self)

    def _repr_latex_(self) -> str:
        return display.stationary_latex(self)


@fields_of_base
class ModalAnalysis(modes.ModalAnalysis):
    """A :class:`resonant.analyses.modes.ModalAnalysis` with its plot and text.

    Examples
    --------
    >>> import resonant
    >>> m = resonant.load("examples/two_dof_free.toml").linearize().modes()
    >>> "mode" in m.summary().lower()
    True
    """

    def plot(self, path: str | Path | None = None, count: int | None = None,
             **options: Any) -> Any:
        """The mode shapes (:func:`resonant.views.plotting.plot_modes`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        count : int, optional
            How many modes to draw.
        **options
            ``ax=`` and more, passed on.

        Returns
        -------
        matplotlib.figure.Figure
        """
        return plotting.plot_modes(self, path=path, count=count, **options)

    def summary(self, units: Any = None) -> str:
        """The text ``resonant modes`` prints.

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (:mod:`resonant.views.units_display`); Hz by default.

        Returns
        -------
        str
        """
        return display.modes_text(self, units)


@fields_of_base
class FrequencyResponse(sweep.FrequencyResponse):
    """A :class:`resonant.analyses.sweep.FrequencyResponse` with its plot and text.

    Examples
    --------
    >>> import resonant
    >>> r = resonant.load("examples/cart_pendulum.toml").linearize().sweep("omega", [5, 10])
    >>> fig = r.plot()
    >>> len(fig.axes) >= 2
    True
    """

    def plot(self, path: str | Path | None = None, names: Any = None, **options: Any) -> Any:
        """Amplitude and phase against the swept parameter
        (:func:`resonant.views.plotting.plot_frequency_response`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        names : sequence of str, optional
            The quantities to draw.
        **options
            ``ax=`` and more, passed on.

        Returns
        -------
        matplotlib.figure.Figure
        """
        return plotting.plot_frequency_response(self, path=path, names=names, **options)

    def summary(self) -> str:
        """The text ``resonant sweep`` prints.

        Returns
        -------
        str
        """
        return display.sweep_text(self)


@fields_of_base
class Simulation(simulate.Simulation):
    """A :class:`resonant.analyses.simulate.Simulation` with its plot and text.

    Examples
    --------
    >>> import resonant
    >>> sim = resonant.load("examples/two_dof_free.toml").simulate(0.05, initial={"x1": 0.01})
    >>> sim.start
    'given'
    """

    def plot(self, path: str | Path | None = None, **options: Any) -> Any:
        """The time histories (:func:`resonant.views.plotting.plot_simulation`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        **options
            ``axes=`` and more, passed on.

        Returns
        -------
        matplotlib.figure.Figure
        """
        return plotting.plot_simulation(self, path=path, **options)

    def summary(self) -> str:
        """The text ``resonant simulate`` prints.

        Returns
        -------
        str
        """
        return display.simulation_text(self)


@fields_of_base
class NonlinearResponse(harmonic_balance.NonlinearResponse):
    """A :class:`resonant.analyses.harmonic_balance.NonlinearResponse` with plot and text.

    Examples
    --------
    >>> import resonant
    >>> r = resonant.load("examples/duffing.toml").nonlinear_sweep(
    ...     "omega", 0.8, 1.2, harmonics=1, points=20)
    >>> r.parameter, r.harmonics
    ('omega', 1)
    """

    def plot(self, path: str | Path | None = None, **options: Any) -> Any:
        """Amplitude against the parameter: stable solid, unstable dashed, special points
        (:func:`resonant.views.nonlinear_plots.plot_nonlinear_response`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        **options
            ``ax=`` and more, passed on.

        Returns
        -------
        matplotlib.figure.Figure
        """
        return nonlinear_plots.plot_nonlinear_response(self, path, **options)

    def summary(self) -> str:
        """The text ``resonant sweep --nonlinear`` prints.

        Returns
        -------
        str
        """
        return nonlinear_plots.nonlinear_text(self)


@fields_of_base
class Backbones(backbone.Backbones):
    """:class:`resonant.analyses.backbone.Backbones` with their plot.

    Examples
    --------
    >>> import resonant
    >>> b = resonant.load("examples/duffing.toml").backbone(harmonics=1, points=10)
    >>> len(b.curves) >= 1
    True
    """

    def plot(self, path: str | Path | None = None, **options: Any) -> Any:
        """Frequency against amplitude, one curve per mode
        (:func:`resonant.views.nonlinear_plots.plot_backbones`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        **options
            ``ax=``, passed on.

        Returns
        -------
        matplotlib.figure.Figure
        """
        return nonlinear_plots.plot_backbones(self, path, **options)


@fields_of_base
class Study(study_result.StudyResult):
    """A :class:`resonant.studies.StudyResult` with its pictures.

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> study = model.study({"k": "uniform(90, 110)"}, ["natural_frequency:1"],
    ...                     samples=200, seed=1, workers=0)
    >>> round(float(study.summary().loc["natural_frequency:1", "mean"]), 2)
    4.56
    """

    def plot(self, directory: str | Path) -> list[Path]:
        """Write the study's pictures into ``directory``
        (:func:`resonant.views.study_plots.plot_study`).

        Parameters
        ----------
        directory : str or Path

        Returns
        -------
        list of Path
            The files written.
        """
        return study_plots.plot_study(self.table, list(self.spec.vary),
                                      list(self.spec.columns), directory, self.sensitivity,
                                      grid=self.spec.design == "grid")
