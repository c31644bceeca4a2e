"""The model as the user gets it from :func:`load`: the data, and every analysis.

:class:`Model` is the model layer's :class:`resonant.model.Model` (the
validated names, expressions and values) with the conveniences a user calls:
``linearize()``, ``simulate()``, ``nonlinear_sweep()``, ``backbone()``,
``draw()``, ``report()`` and the Jupyter reprs.  Each is a one-line call of
the function that does the work, written here, above the analyses, views and
report it calls, so that an editor, mypy and import-linter follow every call.

Examples
--------
>>> import resonant
>>> model = resonant.load("examples/cart_pendulum.toml")
>>> type(model).__module__, model.coordinates
('resonant.api.model', ('x1', 'x2'))
>>> round(model.linearize().stationary().amplitudes["x2"], 5)
0.04514
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import fields
from pathlib import Path
from typing import Any

from .. import model as model_layer
from ..analyses import backbone as backbone_analysis
from ..analyses import condensed, harmonic_balance
from ..analyses import simulate as simulate_analysis
from ..deadline import Deadline
from ..report import write_report
from ..studies import StudyJob, collect, engine_for, request
from ..views import display, drawing
from ..views import explore as explore_view
from .results import Backbones, NonlinearResponse, Simulation, Study, fields_of_base, promote
from .systems import SystemMethods, linear_system

__all__ = ["Model", "load", "loads", "simulate", "with_methods"]


@fields_of_base
class Model(model_layer.Model):
    """A validated model with its analyses as methods.

    Build it with :func:`load` or :func:`loads`.  Every field is that of
    :class:`resonant.model.Model`; :meth:`with_parameters` keeps the class.

    Examples
    --------
    >>> import resonant
    >>> model = resonant.load("examples/cart_pendulum.toml")
    >>> model.coordinates, round(model.linearize().stationary().amplitudes["x1"], 6)
    (('x1', 'x2'), 0.002944)
    """

    def linearize(self, timeout: float | None = None, deadline: Deadline | None = None
                  ) -> SystemMethods:
        """The linearized equation of motion M q'' + C q' + K q = Q(t).

        Parameters
        ----------
        timeout : float, optional
            Time limit of the derivation in seconds (used when no ``deadline`` is given).
        deadline : Deadline, optional
            The cooperative deadline of the whole run.

        Returns
        -------
        SystemMethods
            A :class:`~resonant.system.LinearEOM` for a model given by its energies, a
            :class:`~resonant.system.MatrixEOM` for ``[matrices]``, with
            ``stationary()``, ``modes()`` and ``sweep()``.

        Raises
        ------
        ModelError
            If the derivation fails, exceeds the time limit, overflows or nests
            too deeply; the message names the expression being worked on.

        Examples
        --------
        >>> import resonant
        >>> resonant.load("examples/two_dof_free.toml").linearize().n
        2
        """
        return linear_system(self, deadline or Deadline(timeout, self.source))

    def simulate(self, duration: float | None = None, nonlinear: bool = False,
                 **options: Any) -> Simulation:
        """Time integration, linear or of the full nonlinear equations
        (:func:`resonant.analyses.simulate.simulate`).

        Parameters
        ----------
        duration : float, optional
            End time in s (default: chosen from the system's time scales).
        nonlinear : bool
            Integrate the full Lagrange equations instead of the linearized ones.
        **options
            ``initial``, ``start``, ``periods``, ``method``, ``rtol``, ``deadline``, ...

        Returns
        -------
        Simulation
        """
        system = self.linearize(deadline=options.get("deadline"))
        return promote(Simulation,
                       simulate_analysis.simulate(system, duration, nonlinear, **options))

    def nonlinear_sweep(self, param: str, start: float, stop: float, **options: Any
                        ) -> NonlinearResponse:
        """The periodic steady state of the full equations against a parameter: harmonic
        balance, continuation, stability
        (:func:`resonant.analyses.harmonic_balance.nonlinear_sweep`).

        Parameters
        ----------
        param : str
            The parameter to vary (usually the excitation frequency).
        start, stop : float
            The range.
        **options
            ``harmonics``, ``points``, ``linear``, ``deadline``; for a ``[matrices]``
            model with ``[[nonlinear]]`` elements, whose balance is condensed onto their
            coordinates (:func:`resonant.analyses.condensed.condensed_sweep`), also
            ``observe``, ``tol``, ``exact``, ``samples``.

        Returns
        -------
        NonlinearResponse
        """
        system = self.linearize(deadline=options.get("deadline"))
        if condensed.has_nonlinear_elements(system._model()):
            return promote(NonlinearResponse,
                           condensed.condensed_sweep(system, param, start, stop, **options))
        return promote(NonlinearResponse,
                       harmonic_balance.nonlinear_sweep(system, param, start, stop, **options))

    def backbone(self, amplitude: float | None = None, **options: Any) -> Backbones:
        """The backbone curves: free-vibration frequency against amplitude
        (:func:`resonant.analyses.backbone.backbone`).

        Parameters
        ----------
        amplitude : float, optional
            The largest amplitude to follow.
        **options
            ``harmonics``, ``points``, ``modes``, ``deadline``.

        Returns
        -------
        Backbones
        """
        return promote(Backbones, backbone_analysis.backbone(self, amplitude, **options))

    def study(self, vary: Mapping[str, Any] | None = None,
              quantities: Sequence[str] | None = None, *, output: str | Path | None = None,
              workers: int | None = None, scheduler: str | None = None, client: Any = None,
              resume: bool = False, progress: bool | None = None, **options: Any) -> Study:
        """A parameter study (docs/studies.md): the arguments given, the rest from the
        model's ``[study]`` section.

        Parameters
        ----------
        vary : mapping, optional
            parameter -> ``"uniform(a, b)"``, ``"normal(mean, sd)"``,
            ``"lognormal(mean, sd)"``, a list or ``{"from":, "to":, "step":}``.
        quantities : sequence of str, optional
            ``natural_frequency:I``, ``damping_ratio:I``, ``amplitude:NAME``,
            ``phase:NAME``, ``peak:NAME``, ``stable``, ``nonlinear_amplitude:NAME``.
        output : str or Path, optional
            Also write the rows there (.parquet or .csv).
        workers : int, optional
            Local worker processes (0: this process; default: chosen by the work).
        scheduler : str, optional
            A Dask scheduler's address.
        client : distributed.Client, optional
            A Dask client of yours.
        resume : bool
            Continue an interrupted study of ``output``.
        progress : bool, optional
            A progress bar on standard error.
        **options
            ``design``, ``samples``, ``seed``, ``band``, ``harmonics``.

        Returns
        -------
        Study
        """
        spec = request(self, vary, quantities, **options)
        return promote(Study, collect(StudyJob.of(self, spec), engine_for(workers, scheduler,
                                                                          client),
                                      output, resume=resume, progress=progress))

    def draw(self, path: str | Path | None = None, ax: Any = None) -> Any:
        """The mechanism drawn from its parts (:func:`resonant.views.drawing.draw_mechanism`).

        Parameters
        ----------
        path : str or Path, optional
            Also write the figure there (``.svg``, ``.png`` or ``.pdf``).
        ax : matplotlib.axes.Axes, optional
            Draw into the caller's axes.

        Returns
        -------
        matplotlib.figure.Figure
        """
        return drawing.draw_mechanism(self, path, ax)

    def explore(self, path: str | Path | None = None, timeout: float | None = None
                ) -> explore_view.ExplorePage:
        """The interactive page of the model (:func:`resonant.views.explore.explore_page`);
        shown inline in Jupyter.

        Parameters
        ----------
        path : str or Path, optional
            Also write the page there (``.html``).
        timeout : float, optional
            Seconds for the derivation (default: no limit).

        Returns
        -------
        ExplorePage
            With ``html``, ``save(path)`` and ``_repr_html_`` (an iframe).
        """
        page = explore_view.explore_page(self, deadline=Deadline(timeout, self.source))
        if path is not None:
            page.save(path)
        return page

    def report(self, path: str | Path, plots: bool = True) -> Path:
        """Write the worked solution (:func:`resonant.report.write_report`).

        Parameters
        ----------
        path : str or Path
            ``.html``, ``.md`` or ``.tex``.
        plots : bool
            Include the figures.

        Returns
        -------
        Path
        """
        return write_report(self, path, plots)

    def _repr_latex_(self) -> str:
        return display.model_latex(self)

    def _repr_html_(self) -> str:
        return display.model_html(self)


def with_methods(model: model_layer.Model) -> Model:
    """The same model with its analyses as methods (fields shared, not copied).

    Parameters
    ----------
    model : resonant.model.Model

    Returns
    -------
    Model

    Examples
    --------
    >>> from resonant.model import loads as plain_loads
    >>> type(with_methods(plain_loads('[coordinates]\\nx = ""\\n[energy]\\nT = "x\\'^2/2"'
    ...                                 '\\nU = "x^2/2"'))).__name__
    'Model'
    """
    if isinstance(model, Model):
        return model
    return Model(**{f.name: getattr(model, f.name) for f in fields(model)})


def load(path: str | Path, overrides: Mapping[str, float | str] | None = None,
         allow_paths: Sequence[str | os.PathLike[str]] = ()) -> Model:
    """Read and validate a model file (:func:`resonant.model.load`).

    Parameters
    ----------
    path : str or Path
        The TOML model file.
    overrides : mapping, optional
        Parameter values replacing the file's (numbers or expression text, units allowed).
    allow_paths : sequence of path-like, optional
        Folders outside the model's own from which matrix files may be read.

    Returns
    -------
    Model

    Raises
    ------
    ModelError
        Every problem of the file at once, each naming file, section and key.

    Examples
    --------
    >>> import resonant
    >>> resonant.load("examples/cart_pendulum.toml", {"k": 120}).parameter_values["k"]
    120.0
    """
    return with_methods(model_layer.load(path, overrides, allow_paths))


def loads(text: str, source: str = "<string>", base_dir: str | Path | None = None,
          overrides: Mapping[str, float | str] | None = None,
          allow_paths: Sequence[str | os.PathLike[str]] = ()) -> Model:
    """Validate a model given as TOML text (:func:`resonant.model.loads`).

    Parameters
    ----------
    text : str
        The TOML model.
    source : str
        The name used in messages (a file name).
    base_dir : str or Path, optional
        The folder that matrix files are read from (default: the current one).
    overrides : mapping, optional
        Parameter values replacing the text's.
    allow_paths : sequence of path-like, optional
        Further folders from which matrix files may be read.

    Returns
    -------
    Model

    Raises
    ------
    ModelError
        Every problem at once, each naming source, section and key.

    Examples
    --------
    >>> import resonant
    >>> m = resonant.loads('[parameters]\\nk = 4\\n[coordinates]\\nx = ""\\n'
    ...                    '[energy]\\nT = "x\\'^2/2"\\nU = "k*x^2/2"')
    >>> float(m.linearize().modes().natural_frequencies[0])
    2.0
    """
    return with_methods(model_layer.loads(text, source, base_dir, overrides, allow_paths))


def simulate(system: SystemMethods | Any, duration: float | None = None,
                    nonlinear: bool = False, **options: Any) -> Simulation:
    """Time integration of a system (:func:`resonant.analyses.simulate.simulate`).

    Parameters
    ----------
    system : LinearSystem
        The linear system of a model (its model gives the full equations).
    duration : float, optional
        End time in s.
    nonlinear : bool
        Integrate the full equations of motion.
    **options
        Passed on.

    Returns
    -------
    Simulation
        The time histories and the steady-state amplitudes.

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/two_dof_free.toml").linearize()
    >>> simulate(eom, 0.05, initial={"x2": 0.01}).initial["x2"]
    0.01
    """
    return promote(Simulation, simulate_analysis.simulate(system, duration, nonlinear, **options))
