"""Textbook checks: every example model against its published or closed-form solution.

Each test names its source (the reference exercise "Practice 12 - 2 DoF forced system"
of BME's Department of Applied Mechanics, docs/reference-exercise.md, or a textbook
section) and states the
tolerance of every comparison.  Expected values are computed here, independently of
resonant's internals: from closed forms, or with numpy from matrices written down by
hand from the physics.  The program is driven only through its command line
(``resonant solve/modes/sweep ... --json``), following the contract in
``docs/model-format.md``:

* the stationary solution of ``M q'' + C q' + K q = F_S sin(wt) + F_C cos(wt)`` is
  ``q = L cos(wt) + N sin(wt)`` with
  ``[[K - w^2 M, w C], [-w C, K - w^2 M]] [L; N] = [F_C; F_S]``;
* a response ``L cos(wt) + N sin(wt) = X sin(wt + delta)``, ``X = hypot(L, N)``,
  ``delta = atan2(L, N)`` (phases compared modulo 2 pi).
"""

from __future__ import annotations

import functools
import math
import re
import tomllib
from typing import Any

import numpy as np
import pytest
import sympy as sp

from conftest import EXAMPLES, run_json, solve_json

from resonant.model.units import parse_unit, split_value

# --------------------------------------------------------------------------- helpers


@functools.lru_cache(maxsize=None)
def solved(name: str, *extra: str) -> dict[str, Any]:
    """``resonant solve examples/NAME --json *extra``, run once per argument list."""
    return solve_json(EXAMPLES / name, *extra)


def arr(value: Any) -> np.ndarray:
    return np.asarray(value, dtype=float)


def wrap(angle: float) -> float:
    """Angle reduced to [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def assert_phase(actual: float, expected: float, tol: float) -> None:
    """Phases agree modulo 2 pi within the absolute tolerance ``tol`` (rad)."""
    assert abs(wrap(actual - expected)) <= tol, (actual, expected)


def stationary(M, C, K, omega, F_S, F_C) -> tuple[np.ndarray, np.ndarray]:
    """L, N from the real 2n x 2n system (reference exercise Eq. (38))."""
    M, C, K = arr(M), arr(C), arr(K)
    n = len(M)
    D = K - omega**2 * M
    A = np.block([[D, omega * C], [-omega * C, D]])
    sol = np.linalg.solve(A, np.concatenate([arr(F_C), arr(F_S)]))
    return sol[:n], sol[n:]


def natural_frequencies(M, K) -> np.ndarray:
    """Undamped natural angular frequencies, ascending: sqrt(eig(M^-1 K))."""
    lam = np.linalg.eigvals(np.linalg.solve(arr(M), arr(K)))
    return np.sqrt(np.sort(lam.real))


def single_harmonic(res: dict[str, Any]) -> dict[str, Any]:
    assert len(res["harmonics"]) == 1, res["harmonics"]
    return res["harmonics"][0]


T_SYM = sp.Symbol("t")
TIMES = (0.0, 0.013, 0.1, 0.37, 1.7)  # s, sample instants for comparing Q(t)


class ModelSymbols:
    """Test-side (trusted) sympy view of an example file, for the ``symbolic`` key.

    The program may write its symbolic matrices with derived parameters (e.g.
    ``thetaS``) or with their definitions, and Q(t) with the signal names or their
    expressions in t; this helper accepts all of these.
    """

    def __init__(self, name: str) -> None:
        data = tomllib.loads((EXAMPLES / name).read_text())
        self.data = data
        names: list[str] = []
        for section in ("parameters", "coordinates", "signals", "definitions", "outputs"):
            names += list(data.get(section, {}))
        self.sym: dict[str, Any] = {n: sp.Symbol(n) for n in names}
        self.sym["t"] = T_SYM
        self.base: dict[str, float] = {}
        self.derived: dict[str, sp.Expr] = {}
        for n, v in data["parameters"].items():
            # "2 kg", "pi/3 rad" (docs/units.md): the value times its unit's SI factor
            text, unit = split_value(v) if isinstance(v, str) else (v, None)
            factor = parse_unit(unit).to_si() if unit is not None else 1.0
            try:
                self.base[n] = float(text) * factor
            except ValueError:
                self.derived[n] = self._sympify(text) * factor
        self.signals = {n: self._sympify(e) for n, e in data.get("signals", {}).items()}

    def _sympify(self, text: str) -> sp.Expr:
        return sp.sympify(text, locals=self.sym, convert_xor=True)

    def parse(self, text: str) -> sp.Expr:
        """Parse a string of the ``symbolic`` key; ``s'`` of a signal s is d s/dt."""

        def deriv(symbol: sp.Symbol, order: int) -> sp.Expr:
            return sp.diff(self.signals[str(symbol)], T_SYM, int(order))

        text = re.sub(
            r"([A-Za-z_]\w*)('+)", lambda m: f"__d({m.group(1)}, {len(m.group(2))})", text
        )
        expr = sp.sympify(text, locals={**self.sym, "__d": deriv}, convert_xor=True)
        return expr.subs({self.sym[n]: e for n, e in self.signals.items()})

    def expand_derived(self, expr: sp.Expr) -> sp.Expr:
        """Replace derived parameters by their defining expressions (recursively)."""
        subs = {self.sym[n]: e for n, e in self.derived.items()}
        for _ in range(len(subs) + 1):
            expr = sp.sympify(expr).subs(subs)
        return expr

    def values(self, perturbed: bool = False) -> dict[sp.Symbol, float]:
        """Numeric parameter values: the file's, or the base ones moved by +-7..13 %."""
        vals: dict[sp.Symbol, float] = {}
        for i, (n, v) in enumerate(self.base.items()):
            factor = (1.13, 0.93, 1.07, 0.89)[i % 4] if perturbed else 1.0
            vals[self.sym[n]] = v * factor
        for n, e in self.derived.items():  # in file order: earlier parameters only
            vals[self.sym[n]] = float(sp.sympify(e).subs(vals).evalf())
        return vals

    def assert_matrix(self, strings: list[list[str]], expected: sp.Matrix) -> None:
        """Symbolic equality: simplify(got - expected) == 0 entrywise (exact)."""
        got = sp.Matrix([[self.expand_derived(self.parse(s)) for s in row] for row in strings])
        assert got.shape == expected.shape
        diff = (got - self.expand_derived(expected)).applyfunc(sp.simplify)
        assert diff == sp.zeros(*expected.shape), diff

    def assert_vector_of_t(self, strings: list[str], expected: list[sp.Expr]) -> None:
        """Q(t) agrees at the instants TIMES for the file's parameter values and for
        perturbed ones (so the agreement is of formulas, not of one set of numbers);
        tolerance rel 1e-9, abs 1e-12 (relative to the largest entry)."""
        got = [self.parse(s) for s in strings]
        assert len(got) == len(expected)
        for perturbed in (False, True):
            vals = self.values(perturbed)
            for tv in TIMES:
                g = [float(e.subs(vals).subs(T_SYM, tv).evalf()) for e in got]
                x = [float(sp.sympify(e).subs(vals).subs(T_SYM, tv).evalf()) for e in expected]
                scale = max(1.0, *(abs(v) for v in x))
                assert g == pytest.approx(x, rel=1e-9, abs=1e-12 * scale), (perturbed, tv)


def S(*names: str):
    """sympy Symbols for building expected symbolic results."""
    out = sp.symbols(" ".join(names))
    return out if len(names) > 1 else (out,)


# ----------------------------------------------------------- every example: contract


ALL_EXAMPLES = sorted(p.name for p in EXAMPLES.glob("*.toml"))


@pytest.mark.parametrize("name", ALL_EXAMPLES)
def test_example_solves_with_contract_keys(name):
    """docs/model-format.md, section 2 (``resonant solve --json`` keys): every example is a
    valid model and the output carries every required key, with an amplitude for every
    coordinate and output declared in the file."""
    data = tomllib.loads((EXAMPLES / name).read_text())
    res = solved(name)
    for key in ("coordinates", "M", "C", "K", "symbolic", "natural_frequencies",
                "harmonics", "amplitudes", "phases", "stability", "warnings"):
        assert key in res, key
    assert res["coordinates"] == list(data["coordinates"])
    n = len(res["coordinates"])
    for key in ("M", "C", "K"):
        assert arr(res[key]).shape == (n, n), key
    for key in ("M", "C", "K"):
        assert np.asarray(res["symbolic"][key]).shape == (n, n), key
    assert len(res["symbolic"]["Q"]) == n
    names = list(data["coordinates"]) + list(data.get("outputs", {}))
    assert set(names) <= set(res["amplitudes"])
    assert res["stability"] in ("asymptotically stable", "marginally stable", "unstable")
    assert isinstance(res["warnings"], list)
    wn = res["natural_frequencies"]
    assert wn == sorted(wn)


# ----------------------- reference exercise (cart + pendulum, docs/reference-exercise.md)

REF = "cart_pendulum.toml"
REF_EXACT = "cart_pendulum_exact.toml"
# Data of the exercise: m1 = 2 kg, m2 = 1 kg, l = 0.5 m, k = 100 N/m, g = 9.81 m/s^2,
# F0 = 5 N, eps = pi/3, r0 = 0.01 m, omega = 20 rad/s.
m1, m2, l, k, g, F0, eps, r0 = 2.0, 1.0, 0.5, 100.0, 9.81, 5.0, math.pi / 3, 0.01
REF_M = np.array([[m1 + m2, m2 / 2], [m2 / 2, m2 / 3]])  # Eq. (20) = [[3, .5], [.5, 1/3]]
REF_K = np.array([[k, 0.0], [0.0, m2 * g / (2 * l)]])  # Eq. (26) = diag(100, 9.81)
REF_FS = np.array([F0 * math.cos(eps), F0 * math.cos(eps)])  # Eq. (34) = [2.5, 2.5]
REF_FC = np.array([k * r0 + F0 * math.sin(eps), F0 * math.sin(eps)])  # Eq. (34)


def test_reference_matrices():
    """Reference exercise, Eqs. (20) and (26), and C = 0 (text after Eq. (35)):
    M = [[3, 0.5], [0.5, 1/3]] kg, K = diag(100, 9.81) N/m.  Tolerance rel 1e-12
    (abs 1e-12 for the zero entries)."""
    res = solved(REF)
    assert res["coordinates"] == ["x1", "x2"]
    assert arr(res["M"]) == pytest.approx(np.array([[3, 0.5], [0.5, 1 / 3]]), rel=1e-12, abs=1e-12)
    assert arr(res["K"]) == pytest.approx(np.array([[100, 0], [0, 9.81]]), rel=1e-12, abs=1e-12)
    assert arr(res["C"]) == pytest.approx(np.zeros((2, 2)), rel=1e-12, abs=1e-12)


def test_reference_symbolic():
    """Reference exercise, Eqs. (20), (26) and (32): the symbolic M, K are exactly
    [[m1+m2, m2/2], [m2/2, m2/3]] and diag(k, m2 g/(2 l)) (sympy simplify of the
    difference is 0), C = 0, and Q(t) = [k r0 cos(wt) + F0 sin(wt+eps), F0 sin(wt+eps)]
    (compared at five instants, rel 1e-9)."""
    ms = ModelSymbols(REF)
    sm1, sm2, sl, sk, sg, sF0, seps, sr0, sw = S("m1", "m2", "l", "k", "g", "F0", "eps", "r0", "omega")
    sym = solved(REF)["symbolic"]
    ms.assert_matrix(sym["M"], sp.Matrix([[sm1 + sm2, sm2 / 2], [sm2 / 2, sm2 / 3]]))
    ms.assert_matrix(sym["K"], sp.diag(sk, sm2 * sg / (2 * sl)))
    ms.assert_matrix(sym["C"], sp.zeros(2, 2))
    force = sF0 * sp.sin(sw * T_SYM + seps)
    ms.assert_vector_of_t(sym["Q"], [sk * sr0 * sp.cos(sw * T_SYM) + force, force])


def test_reference_excitation_harmonics():
    """Reference exercise, Eq. (34): one harmonic at omega = 20 rad/s with
    F_S = [F0 cos eps, F0 cos eps] = [2.5, 2.5] N and
    F_C = [k r0 + F0 sin eps, F0 sin eps] = [5.330127, 4.330127] N.
    Tolerance rel 1e-9 against the exact values, abs 5e-7 against the rounded ones."""
    h = single_harmonic(solved(REF))
    assert h["omega"] == pytest.approx(20.0, rel=1e-12)
    assert arr(h["F_S"]) == pytest.approx(REF_FS, rel=1e-9)
    assert arr(h["F_C"]) == pytest.approx(REF_FC, rel=1e-9)
    assert arr(h["F_S"]) == pytest.approx([2.5, 2.5], abs=5e-7)
    assert arr(h["F_C"]) == pytest.approx([1 + 4.330127, 4.330127], abs=5e-7)


def test_reference_stationary_solution():
    """Reference exercise, Eqs. (40)-(44): L = [0.00217, -0.03856] m,
    N = [0.00199, -0.02347] m.  The exercise rounds to 5 decimals: tolerance abs 5e-6;
    against an exact numpy solve of the 4x4 system (39): rel 1e-9."""
    h = single_harmonic(solved(REF))
    assert arr(h["L"]) == pytest.approx([0.00217, -0.03856], abs=5e-6)
    assert arr(h["N"]) == pytest.approx([0.00199, -0.02347], abs=5e-6)
    L, N = stationary(REF_M, np.zeros((2, 2)), REF_K, 20.0, REF_FS, REF_FC)
    assert arr(h["L"]) == pytest.approx(L, rel=1e-9)
    assert arr(h["N"]) == pytest.approx(N, rel=1e-9)


def test_reference_amplitudes_and_phases():
    """Reference exercise, Eqs. (45)-(48): X2 = sqrt(L2^2 + N2^2) = 0.0451 m (rel 1e-3
    against the rounded value), phi_max = X2/l = 0.090 rad (abs 5e-4, the exercise's
    rounding); against the exact numpy solution rel 1e-9.  Phases delta = atan2(L, N)
    from Eq. (46), abs 1e-9 rad (mod 2 pi)."""
    res = solved(REF)
    L, N = stationary(REF_M, np.zeros((2, 2)), REF_K, 20.0, REF_FS, REF_FC)
    amp = res["amplitudes"]
    assert amp["x2"] == pytest.approx(0.0451, rel=1e-3)
    assert amp["phi"] == pytest.approx(0.090, abs=5e-4)
    assert amp["phi"] == pytest.approx(0.0451 / l, rel=1e-3)
    assert amp["x1"] == pytest.approx(math.hypot(L[0], N[0]), rel=1e-9)
    assert amp["x2"] == pytest.approx(math.hypot(L[1], N[1]), rel=1e-9)
    assert amp["phi"] == pytest.approx(math.hypot(L[1], N[1]) / l, rel=1e-9)
    assert_phase(res["phases"]["x1"], math.atan2(L[0], N[0]), 1e-9)
    assert_phase(res["phases"]["x2"], math.atan2(L[1], N[1]), 1e-9)
    assert_phase(res["phases"]["phi"], math.atan2(L[1], N[1]), 1e-9)


def test_reference_natural_frequencies_and_stability():
    """Reference exercise, Eqs. (20), (26): undamped natural frequencies
    sqrt(eig(M^-1 K)) (numpy, rel 1e-9; about 4.561 and 7.930 rad/s); no damping and a
    positive definite K: "marginally stable"."""
    res = solved(REF)
    assert arr(res["natural_frequencies"]) == pytest.approx(natural_frequencies(REF_M, REF_K), rel=1e-9)
    assert res["natural_frequencies"] == pytest.approx([4.56071096, 7.92996595], rel=1e-8)
    assert res["stability"] == "marginally stable"


def test_reference_set_omega():
    """Reference exercise, Eqs. (39)-(41) with omega = 10 rad/s instead of 20
    (``--set omega=10``): M, K and the force vectors of Eq. (34) are unchanged (rel 1e-12
    / 1e-9), L, N follow from a numpy solve of Eq. (39) (rel 1e-9)."""
    res = solved(REF, "--set", "omega=10")
    assert arr(res["M"]) == pytest.approx(REF_M, rel=1e-12)
    assert arr(res["K"]) == pytest.approx(REF_K, rel=1e-12, abs=1e-12)
    h = single_harmonic(res)
    assert h["omega"] == pytest.approx(10.0, rel=1e-12)
    assert arr(h["F_S"]) == pytest.approx(REF_FS, rel=1e-9)
    assert arr(h["F_C"]) == pytest.approx(REF_FC, rel=1e-9)
    L, N = stationary(REF_M, np.zeros((2, 2)), REF_K, 10.0, REF_FS, REF_FC)
    assert arr(h["L"]) == pytest.approx(L, rel=1e-9)
    assert arr(h["N"]) == pytest.approx(N, rel=1e-9)
    assert res["amplitudes"]["x2"] == pytest.approx(math.hypot(L[1], N[1]), rel=1e-9)
    assert res["amplitudes"]["phi"] == pytest.approx(math.hypot(L[1], N[1]) / l, rel=1e-9)
    # and the result really changed (omega = 20 gives X2 = 0.0451 m, omega = 10 gives 0.321 m)
    assert res["amplitudes"]["x2"] == pytest.approx(0.32074726, rel=1e-7)


def test_reference_exact_kinematics_same_linearization():
    """Reference exercise, Eqs. (10)-(13), (21) without the small-angle replacement of
    Eq. (11) (phi = asin(x2/l)): the linearization, hence every number of ``solve``,
    equals that of the worked example (rel 1e-12, abs 1e-14 for zeros; phases abs
    1e-12 rad)."""
    a, b = solved(REF), solved(REF_EXACT)
    assert b["coordinates"] == a["coordinates"]
    for key in ("M", "C", "K"):
        assert arr(b[key]) == pytest.approx(arr(a[key]), rel=1e-12, abs=1e-14), key
    assert arr(b["natural_frequencies"]) == pytest.approx(arr(a["natural_frequencies"]), rel=1e-12)
    ha, hb = single_harmonic(a), single_harmonic(b)
    for key in ("omega", "F_S", "F_C", "L", "N"):
        assert arr(hb[key]) == pytest.approx(arr(ha[key]), rel=1e-12, abs=1e-14), key
    for name in ("x1", "x2", "phi"):
        assert b["amplitudes"][name] == pytest.approx(a["amplitudes"][name], rel=1e-12)
        assert_phase(b["phases"][name], a["phases"][name], 1e-12)
    assert b["stability"] == a["stability"] == "marginally stable"


def test_reference_exact_kinematics_symbolic():
    """Reference exercise, Eqs. (20), (26), (32) from the exact kinematics: symbolic M
    and K simplify to the same expressions (theta_S = m2 l^2/12 expanded), Q(t) as in
    Eq. (32) (five instants, rel 1e-9)."""
    ms = ModelSymbols(REF_EXACT)
    sm1, sm2, sl, sk, sg, sF0, seps, sr0, sw = S("m1", "m2", "l", "k", "g", "F0", "eps", "r0", "omega")
    sym = solved(REF_EXACT)["symbolic"]
    ms.assert_matrix(sym["M"], sp.Matrix([[sm1 + sm2, sm2 / 2], [sm2 / 2, sm2 / 3]]))
    ms.assert_matrix(sym["K"], sp.diag(sk, sm2 * sg / (2 * sl)))
    force = sF0 * sp.sin(sw * T_SYM + seps)
    ms.assert_vector_of_t(sym["Q"], [sk * sr0 * sp.cos(sw * T_SYM) + force, force])


# ------------------------------------------------------------------ rotating unbalance


def test_rotating_unbalance():
    """Inman, Engineering Vibration, 4th ed., Sect. 2.3; Rao, Mechanical Vibrations,
    Sect. 3.7: M x'' + c x' + k x = m0 e Omega^2 cos(Omega t),
    X = (m0 e Omega^2/k) / sqrt((1 - r^2)^2 + (2 zeta r)^2) and
    x = X cos(Omega t - theta), theta = atan2(2 zeta r, 1 - r^2); transmitted force
    |k x + c x'| = X sqrt(k^2 + (c Omega)^2).  Closed forms: rel 1e-9 (phase abs 1e-9
    rad; the vanishing F_S abs 1e-9 N)."""
    M, m0, e, k_, c = 100.0, 0.2, 0.05, 1e6, 2000.0
    Om = 2 * math.pi * 1200 / 60
    wn, zeta, r = math.sqrt(k_ / M), c / (2 * math.sqrt(k_ * M)), Om / math.sqrt(k_ / M)
    X = (m0 * e * Om**2 / k_) / math.sqrt((1 - r**2) ** 2 + (2 * zeta * r) ** 2)
    theta = math.atan2(2 * zeta * r, 1 - r**2)

    res = solved("rotating_unbalance.toml")
    assert arr(res["M"]) == pytest.approx(np.array([[M]]), rel=1e-12)
    assert arr(res["C"]) == pytest.approx(np.array([[c]]), rel=1e-12)
    assert arr(res["K"]) == pytest.approx(np.array([[k_]]), rel=1e-12)
    assert res["natural_frequencies"] == pytest.approx([wn], rel=1e-9)
    h = single_harmonic(res)
    assert h["omega"] == pytest.approx(Om, rel=1e-12)
    assert arr(h["F_C"]) == pytest.approx([m0 * e * Om**2], rel=1e-9)
    assert arr(h["F_S"]) == pytest.approx([0.0], abs=1e-9)
    assert res["amplitudes"]["x"] == pytest.approx(X, rel=1e-9)
    assert res["amplitudes"]["x"] == pytest.approx(2.5013258e-4, rel=1e-7)
    assert_phase(res["phases"]["x"], math.pi / 2 - theta, 1e-9)
    assert res["amplitudes"]["F_T"] == pytest.approx(X * math.hypot(k_, c * Om), rel=1e-9)
    assert res["stability"] == "asymptotically stable"


def test_rotating_unbalance_symbolic_excitation():
    """Inman Sect. 2.3 / Rao Sect. 3.7: the unbalance enters through the explicitly
    time-dependent T; Q(t) = m0 e Omega^2 cos(Omega t) (five instants and two
    parameter sets, rel 1e-9)."""
    ms = ModelSymbols("rotating_unbalance.toml")
    sm0, se, sOm = S("m0", "e", "Omega")
    ms.assert_vector_of_t(solved("rotating_unbalance.toml")["symbolic"]["Q"],
                          [sm0 * se * sOm**2 * sp.cos(sOm * T_SYM)])


# --------------------------------------------------------------------- base excitation


def test_base_excitation_transmissibility():
    """Rao, Mechanical Vibrations, Sect. 3.6 (displacement transmissibility and
    relative motion); Inman, 4th ed., Sect. 2.4:
    m x'' + c x' + k x = k Y sin(wt) + c w Y cos(wt),
    X/Y = sqrt((1 + (2 zeta r)^2) / ((1 - r^2)^2 + (2 zeta r)^2)),
    x = X sin(wt - phi), phi = atan2(2 zeta r^3, 1 + (4 zeta^2 - 1) r^2);
    z = x - y: Z/Y = r^2 / sqrt((1 - r^2)^2 + (2 zeta r)^2), z = Z sin(wt - phi1),
    phi1 = atan2(2 zeta r, 1 - r^2).  Closed forms rel 1e-9, phases abs 1e-9 rad."""
    m, k_, c, Y, w = 10.0, 4000.0, 40.0, 0.005, 30.0
    wn, zeta = math.sqrt(k_ / m), c / (2 * math.sqrt(k_ * m))
    r = w / wn
    den = (1 - r**2) ** 2 + (2 * zeta * r) ** 2
    X = Y * math.sqrt((1 + (2 * zeta * r) ** 2) / den)
    Z = Y * r**2 / math.sqrt(den)

    res = solved("base_excitation.toml")
    assert arr(res["M"]) == pytest.approx(np.array([[m]]), rel=1e-12)
    assert arr(res["C"]) == pytest.approx(np.array([[c]]), rel=1e-12)
    assert arr(res["K"]) == pytest.approx(np.array([[k_]]), rel=1e-12)
    assert res["natural_frequencies"] == pytest.approx([wn], rel=1e-9)
    h = single_harmonic(res)
    assert h["omega"] == pytest.approx(w, rel=1e-12)
    assert arr(h["F_S"]) == pytest.approx([k_ * Y], rel=1e-9)
    assert arr(h["F_C"]) == pytest.approx([c * w * Y], rel=1e-9)
    assert res["amplitudes"]["x"] == pytest.approx(X, rel=1e-9)
    assert res["amplitudes"]["z"] == pytest.approx(Z, rel=1e-9)
    assert res["amplitudes"]["x"] == pytest.approx(4.0608086e-3, rel=1e-7)
    assert res["amplitudes"]["z"] == pytest.approx(8.7514857e-3, rel=1e-7)
    assert_phase(res["phases"]["x"], -math.atan2(2 * zeta * r**3, 1 + (4 * zeta**2 - 1) * r**2), 1e-9)
    assert_phase(res["phases"]["z"], -math.atan2(2 * zeta * r, 1 - r**2), 1e-9)
    assert res["stability"] == "asymptotically stable"


# ------------------------------------------------------------------- damper excitation


def test_damper_excitation():
    """Kinematic excitation through the damper alone (derived as in Rao Sect. 3.6 /
    Inman Sect. 2.4 with the spring anchored): m x'' + c x' + k x = c w Y cos(wt),
    X = c w Y / sqrt((k - m w^2)^2 + (c w)^2), x = X cos(wt - theta),
    theta = atan2(c w, k - m w^2).  Closed forms rel 1e-9, phase abs 1e-9 rad,
    vanishing F_S abs 1e-12 N."""
    m, k_, c, Y, w = 2.0, 800.0, 16.0, 0.01, 25.0
    X = c * w * Y / math.hypot(k_ - m * w**2, c * w)
    res = solved("damper_excitation.toml")
    assert arr(res["M"]) == pytest.approx(np.array([[m]]), rel=1e-12)
    assert arr(res["C"]) == pytest.approx(np.array([[c]]), rel=1e-12)
    assert arr(res["K"]) == pytest.approx(np.array([[k_]]), rel=1e-12)
    assert res["natural_frequencies"] == pytest.approx([math.sqrt(k_ / m)], rel=1e-9)
    h = single_harmonic(res)
    assert h["omega"] == pytest.approx(w, rel=1e-12)
    assert arr(h["F_C"]) == pytest.approx([c * w * Y], rel=1e-9)
    assert arr(h["F_S"]) == pytest.approx([0.0], abs=1e-12)
    assert res["amplitudes"]["x"] == pytest.approx(X, rel=1e-9)
    assert res["amplitudes"]["x"] == pytest.approx(6.6436384e-3, rel=1e-7)
    assert_phase(res["phases"]["x"], math.pi / 2 - math.atan2(c * w, k_ - m * w**2), 1e-9)
    assert res["stability"] == "asymptotically stable"


def test_damper_excitation_symbolic():
    """Same source: symbolic C = [[c]], K = [[k]] (exact) and Q(t) = c Y w cos(wt)
    (the damper's moving end enters through D; five instants, rel 1e-9)."""
    ms = ModelSymbols("damper_excitation.toml")
    sc, sk, sY, sw = S("c", "k", "Y", "omega")
    sym = solved("damper_excitation.toml")["symbolic"]
    ms.assert_matrix(sym["C"], sp.Matrix([[sc]]))
    ms.assert_matrix(sym["K"], sp.Matrix([[sk]]))
    ms.assert_vector_of_t(sym["Q"], [sc * sY * sw * sp.cos(sw * T_SYM)])


# --------------------------------------------------------------------- free 2-DoF system


def test_two_dof_free_vibration():
    """Rao, Mechanical Vibrations, Sect. 5.3 (cf. Example 5.1); Inman, 4th ed.,
    Sect. 4.1: m1 = m2 = m = 5 kg, k1 = k2 = k3 = k = 2000 N/m; M = m I,
    K = [[2k, -k], [-k, 2k]], w1 = sqrt(k/m) = 20 rad/s, w2 = sqrt(3k/m) = 34.641 rad/s
    (rel 1e-9).  No signals: empty harmonics, zero amplitudes (abs 1e-15), no phases,
    "marginally stable" (docs/model-format.md, section 2)."""
    m, k_ = 5.0, 2000.0
    res = solved("two_dof_free.toml")
    assert arr(res["M"]) == pytest.approx(np.diag([m, m]), rel=1e-12, abs=1e-12)
    assert arr(res["K"]) == pytest.approx(np.array([[2 * k_, -k_], [-k_, 2 * k_]]), rel=1e-12)
    assert arr(res["C"]) == pytest.approx(np.zeros((2, 2)), abs=1e-12)
    assert res["natural_frequencies"] == pytest.approx(
        [math.sqrt(k_ / m), math.sqrt(3 * k_ / m)], rel=1e-9)
    assert res["harmonics"] == []
    for name in ("x1", "x2"):
        assert res["amplitudes"][name] == pytest.approx(0.0, abs=1e-15)
    assert not res["phases"]
    assert res["stability"] == "marginally stable"


def test_two_dof_free_mode_shapes():
    """Rao Sect. 5.3 / Inman Sect. 4.1: mode shapes [1, 1] (in phase, w1) and [1, -1]
    (out of phase, w2), normalized so the largest component is +1 (spec, ``modes``);
    for the second mode either [1, -1] or [-1, 1] satisfies that.  Tolerance abs 1e-9;
    damping ratios 0 (abs 1e-12)."""
    res = run_json("modes", EXAMPLES / "two_dof_free.toml")
    assert res["natural_frequencies"] == pytest.approx([20.0, math.sqrt(1200.0)], rel=1e-9)
    first, second = (arr(s) for s in res["mode_shapes"])
    assert first == pytest.approx([1.0, 1.0], abs=1e-9)
    assert (second == pytest.approx([1.0, -1.0], abs=1e-9)
            or second == pytest.approx([-1.0, 1.0], abs=1e-9)), second
    assert arr(res["damping_ratios"]) == pytest.approx(np.zeros(len(res["damping_ratios"])), abs=1e-12)
    assert res["stability"] == "marginally stable"


# ------------------------------------------------------------ pendulum with moving pivot


def test_pendulum_moving_pivot():
    """Landau & Lifshitz, Mechanics, Sect. 5, Problem 3(a), linearized (Sect. 22):
    m l^2 theta'' + m g l theta = -m l s'' = m l w^2 s0 cos(wt), so
    theta = Theta cos(wt), Theta = w^2 s0 / (g - l w^2) (> 0 below resonance, phase
    pi/2), and the bob's horizontal position s + l theta has amplitude
    s0 g / (g - l w^2).  Closed forms rel 1e-9, phases abs 1e-9 rad."""
    m, l_, g_, s0, w = 0.5, 0.8, 9.81, 0.01, 2.5
    Theta = w**2 * s0 / (g_ - l_ * w**2)
    res = solved("pendulum.toml")
    assert arr(res["M"]) == pytest.approx(np.array([[m * l_**2]]), rel=1e-12)
    assert arr(res["K"]) == pytest.approx(np.array([[m * g_ * l_]]), rel=1e-12)
    assert arr(res["C"]) == pytest.approx(np.array([[0.0]]), abs=1e-12)
    assert res["natural_frequencies"] == pytest.approx([math.sqrt(g_ / l_)], rel=1e-9)
    h = single_harmonic(res)
    assert h["omega"] == pytest.approx(w, rel=1e-12)
    assert arr(h["F_C"]) == pytest.approx([m * l_ * w**2 * s0], rel=1e-9)
    assert arr(h["F_S"]) == pytest.approx([0.0], abs=1e-12)
    assert res["amplitudes"]["theta"] == pytest.approx(Theta, rel=1e-9)
    assert res["amplitudes"]["theta"] == pytest.approx(0.012993763, rel=1e-7)
    assert res["amplitudes"]["x_bob"] == pytest.approx(s0 * g_ / (g_ - l_ * w**2), rel=1e-9)
    assert_phase(res["phases"]["theta"], math.pi / 2, 1e-9)
    assert_phase(res["phases"]["x_bob"], math.pi / 2, 1e-9)
    assert res["stability"] == "marginally stable"


def test_pendulum_symbolic():
    """Landau & Lifshitz, Sect. 5, Problem 3(a): symbolic M = [[m l^2]],
    K = [[m g l]] (exact), Q(t) = m l w^2 s0 cos(wt) (five instants, rel 1e-9)."""
    ms = ModelSymbols("pendulum.toml")
    sm, sl, sg, ss0, sw = S("m", "l", "g", "s0", "omega")
    sym = solved("pendulum.toml")["symbolic"]
    ms.assert_matrix(sym["M"], sp.Matrix([[sm * sl**2]]))
    ms.assert_matrix(sym["K"], sp.Matrix([[sm * sg * sl]]))
    ms.assert_vector_of_t(sym["Q"], [sm * sl * sw**2 * ss0 * sp.cos(sw * T_SYM)])


# ----------------------------------------------------------------- damped 3-mass chain


def test_chain3_damped():
    """Rao, Mechanical Vibrations, Sect. 6 (forced vibration of viscously damped
    multi-DoF systems); Inman, 4th ed., Sect. 4: fixed-free chain, m = 1 kg,
    k = 1000 N/m, c = 2 N s/m in parallel with every spring, F0 sin(wt) on mass 3,
    w = 30 rad/s.  Natural frequencies 2 sqrt(k/m) sin((2j-1) pi/14) (rel 1e-9);
    stationary response from the complex solve (K - w^2 M + i w C) X = [0, 0, F0],
    x = Im(X e^{iwt}): N = Re X, L = Im X, amplitude |X|, phase arg X (rel 1e-9,
    phases abs 1e-9 rad)."""
    m, k_, c, F0_, w = 1.0, 1000.0, 2.0, 10.0, 30.0
    B = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    M, K, C = m * np.eye(3), k_ * B, c * B
    Xc = np.linalg.solve(K - w**2 * M + 1j * w * C, np.array([0.0, 0.0, F0_]))

    res = solved("chain3_damped.toml")
    assert res["coordinates"] == ["x1", "x2", "x3"]
    assert arr(res["M"]) == pytest.approx(M, rel=1e-12, abs=1e-12)
    assert arr(res["K"]) == pytest.approx(K, rel=1e-12, abs=1e-12)
    assert arr(res["C"]) == pytest.approx(C, rel=1e-12, abs=1e-12)
    expected_wn = [2 * math.sqrt(k_ / m) * math.sin((2 * j - 1) * math.pi / 14) for j in (1, 2, 3)]
    assert res["natural_frequencies"] == pytest.approx(expected_wn, rel=1e-9)
    h = single_harmonic(res)
    assert h["omega"] == pytest.approx(w, rel=1e-12)
    assert arr(h["F_S"]) == pytest.approx([0.0, 0.0, F0_], rel=1e-9, abs=1e-12)
    assert arr(h["F_C"]) == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)
    assert arr(h["L"]) == pytest.approx(Xc.imag, rel=1e-9)
    assert arr(h["N"]) == pytest.approx(Xc.real, rel=1e-9)
    for i, name in enumerate(("x1", "x2", "x3")):
        assert res["amplitudes"][name] == pytest.approx(abs(Xc[i]), rel=1e-9)
        assert_phase(res["phases"][name], float(np.angle(Xc[i])), 1e-9)
    assert res["stability"] == "asymptotically stable"


# ------------------------------------------------------------- undamped tuned absorber

ABS_M1, ABS_K1, ABS_M2, ABS_WA, ABS_F0 = 10.0, 4000.0, 1.0, 20.0, 10.0
ABS_K2 = ABS_M2 * ABS_WA**2  # 400 N/m
ABS_M = np.diag([ABS_M1, ABS_M2])
ABS_K = np.array([[ABS_K1 + ABS_K2, -ABS_K2], [-ABS_K2, ABS_K2]])


def test_absorber_tuned():
    """Den Hartog, Mechanical Vibrations, Sect. 3.2; Rao, Mechanical Vibrations,
    Sect. 9.11: with omega = sqrt(k2/m2) the main mass stands still (amplitude and
    L, N abs 1e-12 m) and the absorber moves as x2 = -(F0/k2) sin(wt) (amplitude F0/k2
    = 0.025 m rel 1e-9, phase pi abs 1e-9 rad).  Natural frequencies (mu = m2/m1 = 0.1,
    omega_a = sqrt(k1/m1)): omega_a sqrt(1 + mu/2 -+ sqrt(mu + mu^2/4)) (rel 1e-9);
    undamped: "marginally stable"."""
    mu = ABS_M2 / ABS_M1
    res = solved("absorber.toml")
    assert arr(res["M"]) == pytest.approx(ABS_M, rel=1e-12, abs=1e-12)
    assert arr(res["K"]) == pytest.approx(ABS_K, rel=1e-12)
    assert arr(res["C"]) == pytest.approx(np.zeros((2, 2)), abs=1e-12)
    expected_wn = [ABS_WA * math.sqrt(1 + mu / 2 + s * math.sqrt(mu + mu**2 / 4)) for s in (-1, 1)]
    assert res["natural_frequencies"] == pytest.approx(expected_wn, rel=1e-9)
    h = single_harmonic(res)
    assert h["omega"] == pytest.approx(ABS_WA, rel=1e-12)
    assert arr(h["F_S"]) == pytest.approx([ABS_F0, 0.0], rel=1e-9, abs=1e-12)
    assert arr(h["F_C"]) == pytest.approx([0.0, 0.0], abs=1e-12)
    assert h["L"][0] == pytest.approx(0.0, abs=1e-12)
    assert h["N"][0] == pytest.approx(0.0, abs=1e-12)
    assert h["N"][1] == pytest.approx(-ABS_F0 / ABS_K2, rel=1e-9)
    assert res["amplitudes"]["x1"] == pytest.approx(0.0, abs=1e-12)
    assert res["amplitudes"]["x2"] == pytest.approx(ABS_F0 / ABS_K2, rel=1e-9)
    assert res["amplitudes"]["x2"] == pytest.approx(0.025, rel=1e-9)
    assert_phase(res["phases"]["x2"], math.pi, 1e-9)
    assert res["stability"] == "marginally stable"


def test_absorber_detuned():
    """Den Hartog Sect. 3.2 / Rao Sect. 9.11, off tuning (``--set omega=25``; the
    absorber keeps k2 = m2 omega_a^2 = 400 N/m): the main mass moves again;
    L, N from a numpy solve of (K - w^2 M) [L; N] = [0; F_S] (rel 1e-9)."""
    w = 25.0
    res = solved("absorber.toml", "--set", "omega=25")
    assert arr(res["K"]) == pytest.approx(ABS_K, rel=1e-12)
    L, N = stationary(ABS_M, np.zeros((2, 2)), ABS_K, w, [ABS_F0, 0.0], [0.0, 0.0])
    h = single_harmonic(res)
    assert h["omega"] == pytest.approx(w, rel=1e-12)
    assert arr(h["N"]) == pytest.approx(N, rel=1e-9)
    assert arr(h["L"]) == pytest.approx([0.0, 0.0], abs=1e-12)
    assert res["amplitudes"]["x1"] == pytest.approx(abs(N[0]), rel=1e-9)
    assert res["amplitudes"]["x2"] == pytest.approx(abs(N[1]), rel=1e-9)
    assert res["amplitudes"]["x1"] > 1e-3  # clearly nonzero once detuned (about 3.2 mm)


# ------------------------------------------------------------------ tuned mass damper

TMD_M1, TMD_K1, TMD_MU, TMD_F0 = 100.0, 1e5, 0.05, 100.0
TMD_M2 = TMD_MU * TMD_M1
TMD_W1 = math.sqrt(TMD_K1 / TMD_M1)
TMD_F = 1 / (1 + TMD_MU)  # Den Hartog's optimal tuning
TMD_ZETA = math.sqrt(3 * TMD_MU / (8 * (1 + TMD_MU) ** 3))  # ... and damping
TMD_K2 = TMD_M2 * (TMD_F * TMD_W1) ** 2
TMD_C2 = 2 * TMD_ZETA * TMD_M2 * TMD_W1
TMD_M = np.diag([TMD_M1, TMD_M2])
TMD_K = np.array([[TMD_K1 + TMD_K2, -TMD_K2], [-TMD_K2, TMD_K2]])
TMD_C = np.array([[TMD_C2, -TMD_C2], [-TMD_C2, TMD_C2]])


def tmd_response(w: float) -> np.ndarray:
    """Complex amplitudes X for F0 sin(wt) on m1: x = Im(X e^{iwt})."""
    return np.linalg.solve(TMD_K - w**2 * TMD_M + 1j * w * TMD_C, np.array([TMD_F0, 0.0]))


def test_tuned_mass_damper_at_main_resonance():
    """Den Hartog, Mechanical Vibrations, Sect. 3.3; Rao Sect. 9.11: mu = 0.05,
    f = 1/(1+mu), zeta = c2/(2 m2 w1) = sqrt(3 mu/(8 (1+mu)^3)).  Matrices written by
    hand (rel 1e-12); natural frequencies from numpy (rel 1e-9).  At w = w1 =
    sqrt(k1/m1) the main-mass equation reduces to (k2 + i w c2)(X1 - X2) = F0, so
    m2 w1^2 X2 = -F0: absorber amplitude F0/(mu k1) = 0.02 m, phase pi (rel 1e-9, abs
    1e-9 rad); X1 and the stroke x2 - x1 from the complex solve (rel 1e-9)."""
    res = solved("tuned_mass_damper.toml")
    assert arr(res["M"]) == pytest.approx(TMD_M, rel=1e-12, abs=1e-12)
    assert arr(res["K"]) == pytest.approx(TMD_K, rel=1e-12)
    assert arr(res["C"]) == pytest.approx(TMD_C, rel=1e-12)
    assert res["natural_frequencies"] == pytest.approx(natural_frequencies(TMD_M, TMD_K), rel=1e-9)
    h = single_harmonic(res)
    assert h["omega"] == pytest.approx(TMD_W1, rel=1e-12)
    X = tmd_response(TMD_W1)
    assert res["amplitudes"]["x2"] == pytest.approx(TMD_F0 / (TMD_MU * TMD_K1), rel=1e-9)
    assert_phase(res["phases"]["x2"], math.pi, 1e-9)
    assert res["amplitudes"]["x1"] == pytest.approx(abs(X[0]), rel=1e-9)
    assert_phase(res["phases"]["x1"], float(np.angle(X[0])), 1e-9)
    assert res["amplitudes"]["stroke"] == pytest.approx(abs(X[1] - X[0]), rel=1e-9)
    assert arr(h["L"]) == pytest.approx(X.imag, rel=1e-9, abs=1e-12)
    assert arr(h["N"]) == pytest.approx(X.real, rel=1e-9, abs=1e-12)
    assert res["stability"] == "asymptotically stable"


def test_tuned_mass_damper_sweep_equal_peaks():
    """Den Hartog, Mechanical Vibrations, Sect. 3.3 (fixed points P and Q): with the
    optimal tuning the main-mass response k1 X1/F0 has two (nearly) equal peaks at the
    height sqrt(1 + 2/mu) = 6.403 (mu = 0.05).  ``resonant sweep`` over omega from 20
    to 45 rad/s in 251 points: each amplitude agrees with the complex solve (rel 1e-9);
    the maximum below and above w1 both equal sqrt(1 + 2/mu) within rel 2e-3 (the
    true peaks lie 0.07 % and 0.08 % above the fixed points; grid step 0.1 rad/s)."""
    res = run_json("sweep", EXAMPLES / "tuned_mass_damper.toml",
                   "--param", "omega", "--from", "20", "--to", "45", "--points", "251")
    assert res["parameter"] == "omega"
    values = arr(res["values"])
    assert values == pytest.approx(np.linspace(20.0, 45.0, 251), rel=1e-12)
    a1 = arr(res["amplitudes"]["x1"])
    expected = np.array([abs(tmd_response(w)[0]) for w in values])
    assert a1 == pytest.approx(expected, rel=1e-9)
    fixed_point = math.sqrt(1 + 2 / TMD_MU) * TMD_F0 / TMD_K1
    assert a1[values < TMD_W1].max() == pytest.approx(fixed_point, rel=2e-3)
    assert a1[values > TMD_W1].max() == pytest.approx(fixed_point, rel=2e-3)
    assert any(p["name"] == "x1" and p["amplitude"] == pytest.approx(fixed_point, rel=2e-3)
               for p in res["peaks"]), res["peaks"]
