"""The model with its analyses as methods: what :func:`resonant.load` returns.

:class:`resonant.model.Model` is the data (names, parsed expressions, values) and computes
with nothing above the model layer.  :class:`Model` here is that class with every analysis
a user starts from a model as a one-line method: the method calls the function that does
the work, imported at the top of this module (the api is the top of the library), so no
layer below reaches up for it.

Examples
--------
>>> import resonant
>>> model = resonant.load("examples/two_dof_free.toml")
>>> type(model).__module__, isinstance(model, resonant.model.Model)
('resonant.api.model', True)
>>> model.with_parameters().linearize().n      # a copy keeps the methods
2
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..analyses.backbone import Backbones, backbone
from ..analyses.campbell import Campbell, campbell
from ..analyses.harmonic_balance import nonlinear_sweep
from ..analyses.nonlinear_response import NonlinearResponse
from ..analyses.random_response import RandomResponse, random_response
from ..analyses.rotor_map import CriticalSpeedMap, critical_speed_map
from ..analyses.simulate import Simulation, simulate
from ..analyses.unbalance import UnbalanceResponse, unbalance_response
from ..deadline import NO_DEADLINE, Deadline
from ..model import loader
from ..model import types as model_types
from ..model.options import BalanceOptions, SimulationOptions
from ..report import write_report
from ..studies.result import StudyResult
from ..studies.run import study_of
from ..system import LinearSystem, linear_system, nonlinear_system
from ..views.display import model_html, model_latex
from ..views.drawing import draw_mechanism
from ..views.explore import ExplorePage, explore_page

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


@dataclass(frozen=True)
class Model(model_types.Model):
    """A validated model (:class:`resonant.model.Model`) with its analyses as methods.

    Build it with :func:`load` or :func:`loads`; :meth:`of` gives the methods to a model
    read by :mod:`resonant.model`.  Every method is one call of the function named in its
    docstring, with the same options.

    Attributes
    ----------
    title, source, parameters, parameter_values, exact_values, coordinates : see Model
        As :class:`resonant.model.Model`.
    descriptions, equilibrium, signals, definitions, energy, forces, outputs : see Model
        As :class:`resonant.model.Model`.
    matrices, exercise, parts, units, study_section, explore_section : see Model
        As :class:`resonant.model.Model`.
    random_section, shock_section, fatigue_section, periodic_section : see Model
        As :class:`resonant.model.Model`.
    measurement_section : see Model
    campbell_section, unbalances : see Model
        The data of the model, exactly those of :class:`resonant.model.Model` (this class
        adds no field).

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/two_dof_free.toml").linearize()
    >>> eom.modes().natural_frequencies.round(3).tolist()
    [20.0, 34.641]
    """

    @classmethod
    def of(cls, model: model_types.Model) -> Model:
        """The same model with the analyses as methods (itself if it has them).

        Examples
        --------
        >>> from resonant.model import loads as read
        >>> Model.of(read('[matrices]\\nM = [[1]]\\nK = [[4]]\\n')).linearize().n
        1
        """
        if isinstance(model, cls):
            return model
        return cls(**{f.name: getattr(model, f.name) for f in fields(model)})

    def linearize(self, timeout: float | None = None, deadline: Deadline | None = None
                  ) -> LinearSystem:
        """The linearized equation of motion M q'' + C q' + K q = Q(t)
        (:func:`resonant.system.linear_system`).

        Parameters
        ----------
        timeout : float, optional
            Time limit of the derivation in seconds (used when no ``deadline`` is given).
        deadline : Deadline, optional
            The cooperative deadline of the whole run.

        Returns
        -------
        LinearSystem
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

    def simulate(self, duration: float | None = None, nonlinear: bool | None = None,
                 initial: Mapping[str, float | str] | None = None, *, start: str = "auto",
                 periods: float | None = None, method: str | None = None,
                 rtol: float = 1e-9, progress: bool | None = None,
                 deadline: Deadline | None = None, options: SimulationOptions | None = None
                 ) -> Simulation:
        """Time integration, linear or of the full nonlinear equations
        (:func:`resonant.analyses.simulate.simulate`, where the options are described).

        Parameters
        ----------
        duration : float, optional
            End time in s (default: chosen from the system's time scales).
        nonlinear : bool, optional
            Integrate the full Lagrange equations instead of the linearized ones.
        initial : mapping, optional
            coordinate -> initial value.
        start : {"auto", "rest", "stationary", "periodic"}
            Where the motion starts.
        periods : float, optional
            Forcing periods to integrate when no ``duration`` is given.
        method : str, optional
            The integrator.
        rtol : float
            Relative tolerance of the integrator.
        progress : bool, optional
            A progress bar on standard error.
        deadline : Deadline, optional
            The run's time limit.
        options : SimulationOptions, optional
            The options above (but ``deadline``) as one record, instead of keywords.

        Returns
        -------
        Simulation

        Examples
        --------
        >>> import resonant
        >>> sim = resonant.load("examples/two_dof_free.toml").simulate(0.05, initial={"x1": 0.01})
        >>> sim.start
        'given'
        """
        return simulate(self.linearize(deadline=deadline), duration, nonlinear, initial,
                                 start=start, periods=periods, method=method, rtol=rtol,
                                 progress=progress, deadline=deadline or NO_DEADLINE,
                                 options=options)

    def nonlinear_sweep(self, param: str, start: float, stop: float, *,
                        harmonics: int | None = None, points: int = 101, linear: bool = True,
                        observe: Sequence[str] | None = None, samples: int | None = None,
                        exact: bool | None = None, tol: float | None = None,
                        deadline: Deadline | None = None, options: BalanceOptions | None = None
                        ) -> NonlinearResponse:
        """The periodic steady state against a parameter: harmonic balance, continuation,
        stability (:func:`resonant.analyses.harmonic_balance.nonlinear_sweep`, which chooses
        the balance the model calls for).

        Parameters
        ----------
        param : str
            The parameter to vary (usually the excitation frequency).
        start, stop : float
            The range.
        harmonics : int, optional
            H (default: chosen from the truncation).
        points : int
            About this many steps across the range.
        linear : bool
            Also compute the linear sweep.
        observe, samples, exact, tol : optional
            Options of the balance condensed onto ``[[nonlinear]]`` elements.
        deadline : Deadline, optional
            The run's time limit.
        options : BalanceOptions, optional
            The options above (but ``deadline``) as one record, instead of keywords.

        Returns
        -------
        NonlinearResponse

        Examples
        --------
        >>> import resonant
        >>> r = resonant.load("examples/duffing.toml").nonlinear_sweep(
        ...     "omega", 0.8, 1.2, harmonics=1, points=20)
        >>> r.parameter, r.harmonics
        ('omega', 1)
        """
        deadline = deadline or NO_DEADLINE
        return nonlinear_sweep(
            nonlinear_system(self.linearize(deadline=deadline), deadline), param, start, stop,
            harmonics=harmonics, points=points, linear=linear, observe=observe,
            samples=samples, exact=exact, tol=tol, deadline=deadline, options=options)

    def backbone(self, amplitude: float | None = None, *, harmonics: int | None = None,
                 points: int | None = None, modes: list[int] | None = None,
                 deadline: Deadline | None = None) -> Backbones:
        """The backbone curves: free-vibration frequency against amplitude
        (:func:`resonant.analyses.backbone.backbone`).

        Parameters
        ----------
        amplitude : float, optional
            The largest amplitude to follow.
        harmonics : int, optional
            H (default: chosen).
        points : int, optional
            Points per curve.
        modes : list of int, optional
            The modes to follow (1-based; default all).
        deadline : Deadline, optional
            The run's time limit.

        Returns
        -------
        Backbones

        Examples
        --------
        >>> import resonant
        >>> b = resonant.load("examples/duffing.toml").backbone(harmonics=1, points=10)
        >>> len(b.curves) >= 1
        True
        """
        deadline = deadline or NO_DEADLINE
        return backbone(nonlinear_system(self, deadline), amplitude, harmonics=harmonics,
                        points=points, modes=modes, deadline=deadline)

    def study(self, vary: Mapping[str, Any] | None = None,
              quantities: Sequence[str] | None = None, *,
              output: str | os.PathLike[str] | None = None, workers: int | None = None,
              scheduler: str | None = None, client: Any = None, resume: bool = False,
              progress: bool | None = None, design: str | None = None,
              samples: int | None = None, seed: int | None = None,
              band: Mapping[str, Any] | None = None, harmonics: int | None = None
              ) -> StudyResult:
        """A parameter study (docs/studies.md; :func:`resonant.studies.run.study_of`, where
        the arguments are described): the arguments given, the rest from the model's
        ``[study]`` section.

        Returns
        -------
        StudyResult

        Examples
        --------
        >>> import resonant
        >>> model = resonant.load("examples/cart_pendulum.toml")
        >>> study = model.study({"k": "uniform(90, 110)"}, ["natural_frequency:1"],
        ...                     samples=200, seed=1, workers=0)
        >>> round(float(study.summary().loc["natural_frequency:1", "mean"]), 2)
        4.56
        """
        return study_of(self, vary, quantities, output=output, workers=workers,
                            scheduler=scheduler, client=client, resume=resume,
                            progress=progress, design=design, samples=samples, seed=seed,
                            band=band, harmonics=harmonics)

    def draw(self, path: str | Path | None = None, ax: Axes | None = None
             ) -> Figure:
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
        return draw_mechanism(self, path, ax)

    def explore(self, path: str | Path | None = None,
                timeout: float | None = None) -> ExplorePage:
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
        return explore_page(self, deadline=Deadline(timeout, self.source)).saved(path)

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

    def campbell(self, speeds: Sequence[float] | None = None, *, modes: int | None = None,
                 orders: Sequence[float] | None = None, speed: str | None = None,
                 deadline: Deadline | None = None) -> Campbell:
        """The Campbell diagram of a rotor: its modes tracked over the speed, the critical
        speeds and the stability threshold (:func:`resonant.analyses.campbell.campbell`).

        Parameters
        ----------
        speeds : sequence of float, optional
            The speeds (rad/s); default the ``[campbell]`` section's range.
        modes : int, optional
            The branches followed.
        orders : sequence of float, optional
            The excitation orders of the critical speeds.
        speed : str, optional
            The speed parameter (default ``[matrices]`` ``speed``).
        deadline : Deadline, optional
            The run's time limit.

        Returns
        -------
        Campbell

        Examples
        --------
        >>> import resonant
        >>> result = resonant.load("examples/rotors/jeffcott_rotor.toml").campbell()
        >>> sorted(c.whirl for c in result.critical_speeds)
        ['backward', 'forward']
        """
        return campbell(self.linearize(deadline=deadline), speeds, modes=modes, orders=orders,
                        speed=speed, deadline=deadline or NO_DEADLINE)

    def unbalance_response(self, speeds: Sequence[float] | None = None, *,
                           speed: str | None = None, deadline: Deadline | None = None
                           ) -> UnbalanceResponse:
        """The orbits of the rotor's stations under its ``[[unbalance]]`` over the speed
        (:func:`resonant.analyses.unbalance.unbalance_response`; amplitudes 0-pk).

        Parameters
        ----------
        speeds : sequence of float, optional
            The speeds (rad/s); default the ``[campbell]`` section's range.
        speed : str, optional
            The speed parameter (default ``[matrices]`` ``speed``).
        deadline : Deadline, optional
            The run's time limit.

        Returns
        -------
        UnbalanceResponse

        Examples
        --------
        >>> import resonant
        >>> r = resonant.load("examples/rotors/jeffcott_rotor.toml").unbalance_response([316.2])
        >>> r.precession[0]
        ('forward',)
        """
        return unbalance_response(self.linearize(deadline=deadline), speeds, speed=speed,
                                  deadline=deadline or NO_DEADLINE)

    def critical_speed_map(self, stiffness: Sequence[float], *, modes: int = 4,
                           orders: Sequence[float] = (1.0,), damped: bool = False,
                           speeds: Sequence[float] | None = None,
                           deadline: Deadline | None = None) -> CriticalSpeedMap:
        """The critical speeds of the ``[rotor]`` against its bearings' direct stiffness,
        undamped or (``damped``) with the bearings' damping and cross coupling kept
        (:func:`resonant.analyses.rotor_map.critical_speed_map`).

        Parameters
        ----------
        stiffness : sequence of float
            Increasing stiffness values (N/m) given to every bearing (kxx = kyy).
        modes : int
            Critical speeds per order.
        orders : sequence of float
            The excitation orders.
        damped : bool
            The damped critical speeds (the bearings' damping and cross coupling kept).
        speeds : sequence of float, optional
            A damped map's speed grid (rad/s; default the ``[campbell]`` range).
        deadline : Deadline, optional

        Returns
        -------
        CriticalSpeedMap

        Examples
        --------
        >>> import resonant
        >>> m = resonant.load("examples/rotors/friswell_5_9_1.toml")
        >>> m.critical_speed_map([1e6, 1e7], modes=1).speeds.shape
        (2, 1, 1)
        """
        return critical_speed_map(self.linearize(deadline=deadline), stiffness, modes=modes,
                                  orders=orders, damped=damped, speeds=speeds,
                                  deadline=deadline or NO_DEADLINE)

    def random_response(self, *, names: Sequence[str] | None = None, method: str = "auto",
                        tolerance: float | None = None, deadline: Deadline | None = None
                        ) -> RandomResponse:
        """The response to the ``[random]`` section's inputs: spectral densities, RMS values,
        Rice's rates (:func:`resonant.analyses.random_response.random_response`).

        Parameters
        ----------
        names : sequence of str, optional
            The coordinates and outputs to report (default all).
        method : str
            The harmonic solve's method.
        tolerance : float, optional
            Relative accuracy of the RMS values.
        deadline : Deadline, optional
            The run's time limit.

        Returns
        -------
        RandomResponse

        Examples
        --------
        >>> import resonant
        >>> result = resonant.load("examples/shaker_gevs.toml").random_response()
        >>> all(v > 0 for v in result.rms.values())
        True
        """
        return random_response(
            self.linearize(deadline=deadline), self.random_section, deadline or NO_DEADLINE,
            names=names, method=method, tolerance=tolerance)

    def _repr_latex_(self) -> str:
        return model_latex(self)

    def _repr_html_(self) -> str:
        return model_html(self)


def load(path: str | Path, overrides: Mapping[str, float | str] | None = None,
         allow_paths: Sequence[str | os.PathLike[str]] = ()) -> Model:
    """Read and validate a model file (:func:`resonant.model.load`), with its analyses
    as methods.

    Parameters
    ----------
    path : str or Path
        The TOML model file.
    overrides : mapping, optional
        Parameter values that replace those of the file.
    allow_paths : sequence of paths, optional
        Directories, besides the model file's folder, that ``[matrices]`` files may be in.

    Returns
    -------
    Model

    Examples
    --------
    >>> load("examples/two_dof_free.toml").linearize().n
    2
    """
    return Model.of(loader.load(path, overrides, allow_paths))


def loads(text: str, source: str = "<string>", base_dir: str | Path | None = None,
          overrides: Mapping[str, float | str] | None = None,
          allow_paths: Sequence[str | os.PathLike[str]] = ()) -> Model:
    """Read and validate a model from TOML text (:func:`resonant.model.loads`), with its
    analyses as methods.

    Parameters
    ----------
    text : str
        The TOML model.
    source : str
        The name used in messages.
    base_dir : str or Path, optional
        The folder ``[matrices]`` file paths are relative to.
    overrides : mapping, optional
        Parameter values that replace those of the text.
    allow_paths : sequence of paths, optional
        Directories ``[matrices]`` files may be in.

    Returns
    -------
    Model

    Examples
    --------
    >>> loads('[matrices]\\nM = [[1]]\\nK = [[4]]\\n').linearize().n
    1
    """
    return Model.of(loader.loads(text, source, base_dir, overrides, allow_paths))
