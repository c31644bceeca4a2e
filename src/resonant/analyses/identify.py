"""Modes identified from measured frequency response functions (docs/testing.md).

**Poles: the least-squares complex-frequency method** (LSCF; Guillaume, Verboven,
Vanlanduit, Van der Auweraer & Peeters, IMAC 2003), common denominator: every FRF
H_o(w) = B_o(z) / A(z) with z = exp(-i w dt), dt = 1 / (2 f_max), polynomials of order n.
The linearized error B_o - H_o A, minimized over all FRFs with real coefficients, reduces to
one (n+1) x (n+1) system in the denominator (the numerators eliminated; the normal
matrices are Toeplitz, built from sums of H_o z^m over the lines, so 64 FRFs x 4,000 lines
cost one matrix product); the poles are the roots of A (its companion matrix,
:func:`resonant.modal.matrix_polynomial_roots`), s = -ln(z) / dt.

**The stabilization chart**: the fit at orders 2, 4, ..., ``max_order``; a pole of order n
is *stable* when a pole of order n - 2 lies within ``frequency_tolerance`` (relative, 1 %)
in frequency, ``damping_tolerance`` (relative, 5 %) in damping, and its mode shape (the
residues of a least-squares fit at that order) has a MAC above ``mac_tolerance`` (0.98) with
that pole's.  The modes reported are the poles of the highest order that stay stable over
the last ``stable_orders`` orders (default 4), or the poles closest to frequencies given.

**Residues and shapes: least squares in the frequency domain** (LSFD): with the poles
fixed, H_o(w) = sum_r [A_or / (i w - s_r) + conj(A_or) / (i w - conj s_r)] + U_o - L_o / w^2
(upper and lower residuals) is linear in A_or, U_o, L_o, solved for every FRF at once
(real unknowns; one least-squares matrix shared by all).  For an FRF of a derivative d of
the response (``derivative``: 1 mobility, 2 accelerance) every term is multiplied by
(i w)^d.  The mode shape of mode r is the column A_r (one reference), its fitted FRFs and
their error beside the measured ones.

Examples
--------
>>> import numpy as np
>>> f = np.linspace(1, 10, 400)
>>> s = -0.05 * 2 * np.pi * 4 + 2j * np.pi * 4 * np.sqrt(1 - 0.05 ** 2)
>>> iw = 2j * np.pi * f
>>> h = 1 / (iw - s) + 1 / (iw - np.conj(s))
>>> r = identify_modes(f, {"a": h, "b": 2 * h}, max_order=16)
>>> round(float(r.frequency[0]), 6), round(float(r.damping[0]), 6), r.errors["a"] < 1e-6
(4.0, 0.05, True)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..arrays import ComplexArray, freeze_fields
from ..charts import (
    COLORS,
    Chart,
    Charted,
    Charts,
    Curve,
    Rule,
    charts_svg,
)
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem, printable
from ..memory import require
from ..modal import matrix_polynomial_roots, modal_assurance
from ..model.units_display import ResultUnits, cyclic_shown
from .frf_mimo import pair_name
from .result_fields import (
    COMPLEX_NUMBER,
    COUNT,
    PLAIN_NUMBER,
    PLAIN_NUMBERS,
    Codec,
    FieldsJSON,
    saved,
)
from .results_json import Saved

#: the stability criteria's defaults (relative frequency, relative damping, MAC)
FREQUENCY_TOLERANCE, DAMPING_TOLERANCE, MAC_TOLERANCE = 0.01, 0.05, 0.98
#: the highest model order accepted
MAX_ORDER = 200

__all__ = ["ModalIdentification", "Stabilization", "identify_modes", "lscf_poles",
           "lsfd_residues", "identify_modes_matrix"]


#: the stability flags of one order's poles, as a list of strings
_FLAGS = Codec(lambda flags: list(map(str, flags)),
               lambda reader, key, shape: np.array(reader.strings(key)))


@dataclass(frozen=True)
class Stabilization(FieldsJSON):
    """The poles of every model order and their stability (the stabilization chart).

    Attributes
    ----------
    orders : tuple of int
    poles : tuple of ndarray
        The poles of each order (upper half plane, damped, in the band), rad/s.
    stable : tuple of ndarray of str
        For each pole: ``"s"`` stable in frequency, damping and MAC; ``"d"`` in frequency
        and damping; ``"f"`` in frequency; ``"o"`` new.
    criteria : mapping
        The tolerances: ``frequency``, ``damping`` (relative) and ``mac``.
    """

    #: the saved keys' order (resonant.analyses.result_fields.FieldsJSON)
    _json_order = ("criteria", "orders")

    orders: tuple[int, ...] = saved(records="orders", key="order", codec=COUNT)
    poles: tuple[ComplexArray, ...] = saved(records="orders", axes=(None,))
    stable: tuple[np.ndarray, ...] = saved(records="orders", codec=_FLAGS)
    criteria: dict[str, float] = saved(codec=PLAIN_NUMBERS)

    def __post_init__(self) -> None:
        freeze_fields(self)


@dataclass(frozen=True)
class ModalIdentification(Charted, FieldsJSON):
    """Modes identified from FRFs: poles, shapes, the fit and the stabilization chart.

    Attributes
    ----------
    poles : ndarray
        s_r (rad/s), one per mode, by frequency.
    frequency : ndarray
        Natural frequencies |s_r| / (2 pi) (Hz).
    damping : ndarray
        Damping ratios -Re s_r / |s_r|.
    shapes : ndarray
        (channels, modes) the residues A_or (complex mode shapes times the reference's).
    channels : tuple of str
    measured_frequency : ndarray
        The lines fitted (Hz).
    measured : mapping
        Channel -> the measured FRF.
    fitted : mapping
        Channel -> the fitted FRF (modes and residuals).
    errors : mapping
        Channel -> ||fitted - measured|| / ||measured|| over the lines.
    stabilization : Stabilization
    derivative : int
        0 receptance, 1 mobility, 2 accelerance.
    warnings : tuple of str
    inputs : tuple of str
        With an FRF matrix (:func:`identify_modes_matrix`): the inputs; ``measured``,
        ``fitted`` and ``errors`` are then keyed by response/input pairs
        (:func:`resonant.analyses.frf_mimo.pair_name`).  Empty for one reference.
    participation : ndarray
        (inputs, modes) the modal participation factors L_ir with an FRF matrix (the
        residues A_r = shapes_r L_r^T), each mode's largest equal to 1; (0, modes) for one
        reference.

    Examples
    --------
    >>> import numpy as np
    >>> from resonant.analyses.identify import identify_modes
    >>> f = np.linspace(0.5, 6.0, 400)
    >>> w, wn = 2 * np.pi * f, 2 * np.pi * 3.0                   # one mode: 3 Hz, 2 %
    >>> frf = 1 / (wn ** 2 - w ** 2 + 2j * 0.02 * wn * w)
    >>> r = identify_modes(f, {"x": frf}, max_order=20, near=[3.0])
    >>> [round(float(v), 6) for v in (r.frequency[0], r.damping[0])]
    [3.0, 0.02]
    """

    #: the saved keys' order (resonant.analyses.result_fields.FieldsJSON)
    _json_order = ("modes", "channels", "shapes", "fit_error", "derivative", "stabilization",
                   "frequency_hz", "measured", "fitted", "warnings", "inputs", "participation")
    _group_order = {"modes": ("frequency_hz", "damping_ratio", "pole")}

    poles: np.ndarray = saved(records="modes", key="pole", codec=COMPLEX_NUMBER)
    frequency: np.ndarray = saved(records="modes", key="frequency_hz", codec=PLAIN_NUMBER)
    damping: np.ndarray = saved(records="modes", key="damping_ratio", codec=PLAIN_NUMBER)
    shapes: ComplexArray = saved(axes=("channels", "poles"))
    channels: tuple[str, ...] = saved()
    measured_frequency: np.ndarray = saved(key="frequency_hz", axes=(None,))
    measured: dict[str, ComplexArray] = saved(axes=("measured_frequency",))
    fitted: dict[str, ComplexArray] = saved(axes=("measured_frequency",))
    errors: dict[str, float] = saved(key="fit_error", codec=PLAIN_NUMBERS)
    stabilization: Stabilization = saved()
    derivative: int = saved(0, codec=COUNT, required=True)
    warnings: tuple[str, ...] = ()
    inputs: tuple[str, ...] = saved((), only_with="inputs")
    participation: ComplexArray = saved(
        default_factory=lambda: np.zeros((0, 0), complex), axes=("inputs", "poles"),
        only_with="inputs")

    def __post_init__(self) -> None:
        freeze_fields(self)

    @classmethod
    def _check_saved(cls, values: dict[str, Any], saved_data: Saved) -> None:
        """The FRFs of every channel (and input) in their order, and a single reference's
        participation of no input (read as for :func:`identify_modes`)."""
        inputs = values.get("inputs", ())
        keys = [pair_name(c, i) for c in values["channels"] for i in inputs] if inputs \
            else list(values["channels"])
        for name in ("measured", "fitted"):
            frfs = saved_data.mapping(name)
            for key in keys:
                frfs.value(key)   # the error naming a missing one
            values[name] = {key: values[name][key] for key in keys}
        if not inputs:
            values["participation"] = np.zeros((0, len(values["poles"])), complex)

    def chart(self) -> Charts:
        """The stabilization chart over the FRFs' sum, and the measured and fitted FRFs.

        Returns
        -------
        Charts
        """
        f = np.asarray(self.measured_frequency)
        xlim = (float(f[0]), float(f[-1]))
        st = self.stabilization
        kinds = (("o", "new", "#bbbbbb"), ("f", "frequency", "#ff7f0e"),
                 ("d", "frequency, damping", "#1f77b4"), ("s", "stable (f, damping, MAC)",
                                                          "#d62728"))
        curves = []
        for flag, label, color in kinds:
            xs, ys = [], []
            for n, p, s in zip(st.orders, st.poles, st.stable):
                keep = np.asarray(s) == flag
                xs.extend(np.abs(p[keep]) / (2 * np.pi))
                ys.extend([n] * int(keep.sum()))
            if xs:
                curves.append(Curve(np.array(xs), np.array(ys, dtype=float), label, color,
                                    marker="point" if flag != "s" else "cross", line=False))
        rules = tuple(Rule(float(x), label="" if k else "identified", color="#2ca02c",
                           dash="1 1.65")
                      for k, x in enumerate(self.frequency))
        top = Chart(tuple(curves), "frequency [Hz]", "model order", xlim, rules=rules,
                    title="stabilization")
        fits = []
        for k, name in enumerate(self.measured):
            color = COLORS[k % len(COLORS)]
            fits.append(Curve(f, np.abs(self.measured[name]), f"{name} measured", color))
            fits.append(Curve(f, np.abs(self.fitted[name]), f"{name} fitted", color,
                              dash="3.7 1.6"))
        bottom = Chart(tuple(fits), "frequency [Hz]", "|H|", xlim, ylog=True, rules=rules)
        return Charts((top, bottom), title="identified modes", heights=(1.4, 1.0),
                      size=(7.0, 6.0))

    def summary(self, units: ResultUnits | None = None) -> str:
        """The modes as a text table and the fit's error per channel.

        Parameters
        ----------
        units : ResultUnits, optional
            The display units (``--units``: frequencies in the unit chosen; default Hz).

        Returns
        -------
        str
        """
        hz = cyclic_shown(units)
        lines = [f"{'mode':>4} {f'f [{hz.text}]':>10} {'zeta [%]':>9}"]
        lines += [f"{k + 1:>4} {hz(f):>10.5g} {100 * z:>9.4g}"
                  for k, (f, z) in enumerate(zip(self.frequency, self.damping))]
        lines += [f"fit error {printable(k, limit=20)}: {v:.3g}" for k, v in self.errors.items()]
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines) + "\n"

    def _repr_html_(self) -> str:
        return charts_svg(self.chart(), "identified-modes")


def _check(frequency: np.ndarray, frfs: Mapping[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    f = np.asarray(frequency, dtype=float).ravel()
    if len(f) < 4 or not np.isfinite(f).all() or (np.diff(f) <= 0).any() or f[0] < 0:
        raise ModelError(Problem("the frequencies must be at least 4 increasing, "
                                 "non-negative numbers", "", "", "frequency"))
    if not frfs:
        raise ModelError(Problem("no FRF to identify modes from", "", "", "frfs"))
    H = np.array([np.asarray(h, dtype=complex).ravel() for h in frfs.values()])
    if H.shape[1] != len(f):
        raise ModelError(Problem(f"every FRF needs {len(f)} values, one per frequency", "",
                                 "", "frfs"))
    bad = ~np.isfinite(H).all(axis=1)
    if bad.any():
        raise ModelError(Problem(f"the FRF '{list(frfs)[int(np.argmax(bad))]}' holds NaN",
                                 "", "", "frfs"))
    return f, H


def lscf_poles(frequency: np.ndarray, H: np.ndarray, order: int) -> np.ndarray:
    """The poles of a common-denominator LSCF fit of order ``order`` to the FRFs ``H``.

    Parameters
    ----------
    frequency : ndarray
        The lines (Hz).
    H : ndarray
        (channels, lines) FRFs.
    order : int
        The denominator's order (twice the modes it can hold).

    Returns
    -------
    ndarray
        Every root s = -ln(z) / dt (rad/s), unsorted.

    Examples
    --------
    >>> f = np.linspace(1, 10, 200)
    >>> s = -1 + 20j
    >>> h = 1 / (2j * np.pi * f - s) + 1 / (2j * np.pi * f - np.conj(s))
    >>> p = lscf_poles(f, h[None, :], 8)
    >>> complex(np.round(p[(p.imag > 0) & (p.real < 0)][0], 4))
    (-1+20j)
    """
    return _lscf_roots(_lscf_sums(frequency, H, order), order)


@dataclass(frozen=True)
class _Sums:
    """The LSCF's Toeplitz sums for m = -N ... N: sum_k z_k^m, sum_k H_ok z_k^m (each FRF)
    and sum_o sum_k |H_ok|^2 z_k^m; every order up to N takes its normal matrices from them."""

    top: int
    dt: float
    ones: np.ndarray
    frfs: np.ndarray
    squares: np.ndarray


def _lscf_sums(frequency: np.ndarray, H: np.ndarray, top: int) -> _Sums:
    dt = 1.0 / (2.0 * frequency[-1])
    Z = np.exp(-1j * np.outer(2 * np.pi * frequency, np.arange(-top, top + 1)) * dt)
    return _Sums(top, dt, np.real(Z.sum(axis=0)), np.real(H @ Z),
                 np.real((np.abs(H) ** 2).sum(axis=0) @ Z))


def _lscf_roots(sums: _Sums, order: int) -> np.ndarray:
    """The poles of order ``order``: the reduced normal equations
    M = sum_o (T_o - S_o^T R^-1 S_o) in the denominator, a_n = 1 (R = Re G^H G,
    S_o = -Re G^H diag(H_o) G, T_o = Re G^H diag|H_o|^2 G, G_kr = z_k^r)."""
    r = np.arange(order + 1)
    diff = r[None, :] - r[:, None] + sums.top
    R = sums.ones[diff]
    S = -sums.frfs[:, diff]                               # (channels, n+1, n+1)
    T = sums.squares[diff]
    count = len(S)
    Rinv_S = np.linalg.solve(R, S.transpose(1, 0, 2).reshape(order + 1, -1)).reshape(
        order + 1, count, order + 1).transpose(1, 0, 2)
    # sum_o S_o^T R^-1 S_o as one matrix product over (o, r)
    M = T - S.reshape(-1, order + 1).T @ Rinv_S.reshape(-1, order + 1)
    alpha = np.append(np.linalg.solve(M[:order, :order], -M[:order, order]), 1.0)
    z = matrix_polynomial_roots(alpha)
    return np.asarray(-np.log(z.astype(complex)) / sums.dt)


def lsfd_residues(frequency: np.ndarray, H: np.ndarray, poles: np.ndarray,
                  derivative: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Residues of the poles (upper half plane) and residuals by least squares (LSFD).

    Parameters
    ----------
    frequency : ndarray
        The lines (Hz).
    H : ndarray
        (channels, lines).
    poles : ndarray
        s_r, Im s_r > 0.
    derivative : int
        The FRFs' derivative of the response (0, 1, 2).

    Returns
    -------
    residues : ndarray
        (channels, poles) A_or.
    fitted : ndarray
        (channels, lines) the fitted FRFs.

    Examples
    --------
    >>> f = np.linspace(1, 10, 50)
    >>> s = np.array([-1 + 20j])
    >>> iw = 2j * np.pi * f
    >>> h = (2 - 1j) / (iw - s[0]) + (2 + 1j) / (iw - np.conj(s[0]))
    >>> A, fit = lsfd_residues(f, h[None, :], s)
    >>> complex(np.round(A[0, 0], 9)), bool(np.allclose(fit, h))
    ((2-1j), True)
    """
    iw = 2j * np.pi * frequency
    factor = iw ** derivative
    p = np.asarray(poles)[None, :]
    plus = factor[:, None] / (iw[:, None] - p)
    minus = factor[:, None] / (iw[:, None] - np.conj(p))
    w2 = (2 * np.pi * np.maximum(frequency, frequency[frequency > 0].min())) ** 2
    basis = np.column_stack([plus + minus, 1j * (plus - minus), factor,
                             -factor / w2])            # a_r, b_r, upper, lower residual
    design = np.vstack([basis.real, basis.imag])
    rhs = np.vstack([H.real.T, H.imag.T])
    scale = np.linalg.norm(design, axis=0)
    scale[scale == 0] = 1.0
    x = np.linalg.lstsq(design / scale, rhs, rcond=None)[0] / scale[:, None]
    count = p.shape[1]
    residues = (x[:count] + 1j * x[count:2 * count]).T
    return residues, (basis @ x).T


def _stable_flags(poles: np.ndarray, shapes: np.ndarray, previous: np.ndarray,
                  previous_shapes: np.ndarray, criteria: Mapping[str, float]) -> np.ndarray:
    flags = np.full(len(poles), "o", dtype="<U1")
    if not len(previous):
        return flags
    f, z = np.abs(poles), -poles.real / np.abs(poles)
    fp, zp = np.abs(previous), -previous.real / np.abs(previous)
    mac = modal_assurance(shapes, previous_shapes)
    for k in range(len(poles)):
        j = int(np.argmin(np.abs(fp - f[k])))
        if abs(fp[j] - f[k]) > criteria["frequency"] * f[k]:
            continue
        flags[k] = "f"
        if abs(zp[j] - z[k]) > criteria["damping"] * z[k]:
            continue
        flags[k] = "s" if mac[k, j] >= criteria["mac"] else "d"
    return flags


def _physical(s: np.ndarray, frequency: np.ndarray) -> np.ndarray:
    """The poles of a vibrating mode: Im s > 0, damped (0 < zeta < 1), inside the band."""
    f = np.abs(s) / (2 * np.pi)
    keep = (s.imag > 0) & (s.real < 0) & (f >= frequency[0]) & (f <= frequency[-1])
    return np.sort_complex(s[keep][np.argsort(np.abs(s[keep]))])


def identify_modes(frequency: np.ndarray, frfs: Mapping[str, Any], *, max_order: int = 40,
                   derivative: int = 0, near: Sequence[float] | None = None,
                   stable_orders: int = 4, frequency_tolerance: float = FREQUENCY_TOLERANCE,
                   damping_tolerance: float = DAMPING_TOLERANCE,
                   mac_tolerance: float = MAC_TOLERANCE, added_decay: float = 0.0,
                   deadline: Deadline = NO_DEADLINE) -> ModalIdentification:
    """Poles by LSCF with a stabilization chart, then residues and shapes by LSFD.

    Parameters
    ----------
    frequency : ndarray
        The lines (Hz), increasing.
    frfs : mapping
        Channel -> complex FRF at ``frequency`` (one reference).
    max_order : int
        The highest LSCF order (even; 2 to :data:`MAX_ORDER`).
    derivative : int
        0 receptance, 1 mobility, 2 accelerance.
    near : sequence of float, optional
        Take the stable (else any) pole of the highest order closest to each of these
        frequencies (Hz) instead of the automatic choice.
    stable_orders : int
        How many of the last orders a pole must stay stable in (automatic choice).
    frequency_tolerance, damping_tolerance, mac_tolerance : float
        The stability criteria (module docstring).
    added_decay : float
        The decay rate (s^-1) an exponential window added to the FRFs
        (:attr:`resonant.analyses.frf_estimate.MeasuredFRF.added_decay`): the poles reported
        are s + added_decay (the fit, of the windowed FRFs, keeps s).
    deadline : Deadline, optional
        Checked between orders.

    Returns
    -------
    ModalIdentification

    Raises
    ------
    ModelError
        For frequencies or FRFs that are not numbers, an order out of range, or when no
        pole is stable.
    """
    f, H = _check(frequency, frfs)
    if not (2 <= max_order <= MAX_ORDER) or derivative not in (0, 1, 2):
        raise ModelError(Problem(f"the order must lie in 2 to {MAX_ORDER} and the derivative "
                                 "be 0, 1 or 2", "", "", "max_order"))
    require(16.0 * len(f) * (2 * max_order + 1) * 2, "the LSCF sums", "fit fewer lines")
    criteria = {"frequency": frequency_tolerance, "damping": damping_tolerance,
                "mac": mac_tolerance}
    orders, all_poles, all_flags, history = [], [], [], []
    previous, previous_shapes = np.zeros(0, complex), np.zeros((len(H), 0), complex)
    sums = _lscf_sums(f, H, max_order)
    for order in range(2, max_order + 1, 2):
        deadline.check("while fitting the stabilization chart", analysis=True)
        poles = _physical(_lscf_roots(sums, order), f)
        shapes = lsfd_residues(f, H, poles, derivative)[0] if len(poles) else \
            np.zeros((len(H), 0), complex)
        flags = _stable_flags(poles, shapes, previous, previous_shapes, criteria)
        orders.append(order)
        all_poles.append(poles)
        all_flags.append(flags)
        history.append((poles, flags))
        previous, previous_shapes = poles, shapes
    chosen = _choose(history, near, stable_orders, criteria)
    warnings = [] if len(chosen) else ["no pole is stable over the last orders: raise the "
                                       "order, narrow the band or give the frequencies"]
    residues, fitted = lsfd_residues(f, H, chosen, derivative)
    names = tuple(frfs)
    errors = {n: float(np.linalg.norm(fitted[k] - H[k]) / np.linalg.norm(H[k]))
              for k, n in enumerate(names)}
    stabilization = Stabilization(tuple(orders), tuple(all_poles), tuple(all_flags), criteria)
    chosen = chosen + added_decay
    if (chosen.real >= 0).any():
        warnings.append("the window's added decay is larger than a pole's: that mode's "
                        "damping is not known (use a slower exponential window)")
    return ModalIdentification(chosen, np.abs(chosen) / (2 * np.pi),
                               -chosen.real / np.abs(chosen), residues, names, f,
                               {n: H[k] for k, n in enumerate(names)},
                               {n: fitted[k] for k, n in enumerate(names)}, errors,
                               stabilization, derivative, tuple(warnings))


def _choose(history: list[tuple[np.ndarray, np.ndarray]], near: Sequence[float] | None,
            stable_orders: int, criteria: Mapping[str, float]) -> np.ndarray:
    """The poles of the highest order stable over its last orders, or nearest ``near``."""
    poles, flags = history[-1]
    if near is not None:
        stable = poles[flags == "s"] if (flags == "s").any() else poles
        if not len(stable):
            return np.zeros(0, complex)
        picked = [stable[int(np.argmin(np.abs(np.abs(stable) / (2 * np.pi) - x)))]
                  for x in near]
        return np.array(sorted(set(picked), key=abs))
    chosen = []
    for k, s in enumerate(poles):
        if flags[k] != "s":
            continue
        run, target = 1, s
        for earlier, earlier_flags in reversed(history[:-1]):
            if not len(earlier):
                break
            j = int(np.argmin(np.abs(np.abs(earlier) - abs(target))))
            if abs(abs(earlier[j]) - abs(target)) > criteria["frequency"] * abs(target) or \
                    earlier_flags[j] not in "sd":
                break
            run, target = run + 1, earlier[j]
        if run >= stable_orders:
            chosen.append(s)
    kept: list[complex] = []
    for s in sorted(chosen, key=abs):       # one pole per mode (a close double is one)
        if not kept or abs(abs(s) - abs(kept[-1])) > 1e-3 * abs(s):
            kept.append(s)
    return np.array(kept, dtype=complex)


#: the ratio of a mode's second to first residue singular value above which it is warned of
RANK_ONE_WARNING = 0.1


def identify_modes_matrix(frequency: np.ndarray, H: np.ndarray, outputs: Sequence[str],
                          inputs: Sequence[str], *, max_order: int = 40, derivative: int = 0,
                          near: Sequence[float] | None = None, stable_orders: int = 4,
                          frequency_tolerance: float = FREQUENCY_TOLERANCE,
                          damping_tolerance: float = DAMPING_TOLERANCE,
                          mac_tolerance: float = MAC_TOLERANCE, added_decay: float = 0.0,
                          deadline: Deadline = NO_DEADLINE) -> ModalIdentification:
    """Modes from an FRF matrix (several inputs): poles shared by every response and input,
    mode shapes and participation factors from the residue matrices.

    The LSCF's common denominator is fitted to all outputs x inputs FRFs at once (the
    poles of the structure do not depend on where it is driven), the LSFD residues A_or,i
    to each FRF with those poles.  Each mode's residue matrix is of rank one,
    A_r = psi_r L_r^T (mode shape times participation factor: Ewins, Modal Testing, 2nd
    ed., sec. 4.4); its first singular pair gives psi_r and L_r, L_r scaled so that its
    largest entry is 1 (with one input, psi_r is the residue column of
    :func:`identify_modes`).  A mode that one input does not drive (a node at that point)
    is still found when another input drives it.  Where a mode's second singular value
    exceeds :data:`RANK_ONE_WARNING` times its first (close modes fitted as one, or
    inconsistent FRFs) a warning says so.

    Parameters
    ----------
    frequency : ndarray
        The lines (Hz), increasing.
    H : ndarray
        (lines, outputs, inputs) complex, as :attr:`resonant.analyses.frf_mimo.MIMOFRF.H`.
    outputs, inputs : sequence of str
        The response and input channels.
    max_order : int
        The highest LSCF order (as :func:`identify_modes`).
    derivative : int
        0 receptance, 1 mobility, 2 accelerance.
    near : sequence of float, optional
        The frequencies (Hz) the poles are taken nearest to.
    stable_orders : int
    frequency_tolerance, damping_tolerance, mac_tolerance : float
        The stability criteria (module docstring).
    added_decay : float
        The decay rate (s^-1) an exponential window added.
    deadline : Deadline, optional

    Returns
    -------
    ModalIdentification
        ``shapes`` (outputs, modes), ``participation`` (inputs, modes); ``measured``,
        ``fitted`` and ``errors`` keyed by :func:`resonant.analyses.frf_mimo.pair_name`.

    Raises
    ------
    ModelError
        For an H of another shape than (lines, outputs, inputs), or as
        :func:`identify_modes`.

    Examples
    --------
    >>> f = np.linspace(1, 10, 400)
    >>> iw = 2j * np.pi * f
    >>> s = -0.05 * 2 * np.pi * 4 + 2j * np.pi * 4 * np.sqrt(1 - 0.05 ** 2)
    >>> mode = 1 / (iw - s) + 1 / (iw - np.conj(s))            # psi = (1, 2), L = (1, 0.5)
    >>> H = np.array([[1.0, 0.5], [2.0, 1.0]])[None, :, :] * mode[:, None, None]
    >>> r = identify_modes_matrix(f, H, ["a", "b"], ["u", "v"], max_order=16)
    >>> round(float(r.frequency[0]), 6), np.round(r.participation[:, 0].real, 6).tolist()
    (4.0, [1.0, 0.5])
    >>> np.round(r.shapes[:, 0].real, 6).tolist(), sorted(r.errors)
    ([1.0, 2.0], ['a/u', 'a/v', 'b/u', 'b/v'])
    """
    H = np.asarray(H)
    if H.ndim != 3 or H.shape[1:] != (len(outputs), len(inputs)) or not len(inputs):
        raise ModelError(Problem(f"the FRF matrix must be (lines, {len(outputs)} outputs, "
                                 f"{len(inputs)} inputs), not {H.shape}", "", "", "H"))
    frfs = {pair_name(o, i): H[:, r, k] for r, o in enumerate(outputs)
            for k, i in enumerate(inputs)}
    base = identify_modes(frequency, frfs, max_order=max_order, derivative=derivative,
                          near=near, stable_orders=stable_orders,
                          frequency_tolerance=frequency_tolerance,
                          damping_tolerance=damping_tolerance, mac_tolerance=mac_tolerance,
                          added_decay=added_decay, deadline=deadline)
    count = len(base.poles)
    residues = np.asarray(base.shapes).reshape(len(outputs), len(inputs), count)
    shapes = np.zeros((len(outputs), count), complex)
    participation = np.zeros((len(inputs), count), complex)
    warnings = list(base.warnings)
    for m in range(count):
        U, S, Vh = np.linalg.svd(residues[:, :, m])
        factor = Vh[0]                                      # A_r ~ S0 U0 Vh0 (= psi L^T)
        largest = factor[int(np.argmax(np.abs(factor)))]
        participation[:, m] = factor / largest
        shapes[:, m] = S[0] * U[:, 0] * largest
        if len(S) > 1 and S[0] > 0 and S[1] > RANK_ONE_WARNING * S[0]:
            warnings.append(f"mode {m + 1} ({base.frequency[m]:.6g} Hz): its residue matrix is "
                            f"not of rank one (second singular value {S[1] / S[0]:.2g} of "
                            "the first): close modes fitted as one, or inconsistent FRFs")
    return replace(base, shapes=shapes, channels=tuple(outputs), warnings=tuple(warnings),
                   inputs=tuple(inputs), participation=participation)
