"""Rotors: the gyroscopic modal kernel, [matrices] with G and speed, the Campbell diagram
(tracking, whirl, critical speeds, stability threshold), against closed forms.

References (each test names its own):
- the Jeffcott rotor with stationary damping c_e and rotating damping c_i, in the complex
  coordinate z = x + i y: m z'' + (c_e + c_i) z' + (k - i Omega c_i) z = 0 (Genta,
  Dynamics of Rotating Systems, Springer 2005, sec. 4.7; Vance, Zeidan & Murphy,
  Machinery Vibration and Rotordynamics, Wiley 2010, sec. 2.7): the whirl roots solve
  that quadratic, and the threshold of instability is Omega_th = omega_n (1 + c_e / c_i);
- a rigid disc on the end of a massless cantilever (an overhung rotor; Friswell, Penny,
  Garvey & Lees, Dynamics of Rotating Machines, CUP 2010, sec. 3.6): with the cantilever's
  tip stiffness a [[12, -6L], [-6L, 4L^2]], a = EI/L^3, on (deflection, slope), a forward
  whirl at omega solves (12a - m w^2)(4L^2 a - I_t w^2 + I_p Omega w) - 36 L^2 a^2 = 0 and
  a backward one the same with -I_p Omega w.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import EXAMPLES, run_cli
from resonant.analyses.campbell import Campbell, campbell
from resonant.analyses.rotor_tracking import track_modes
from resonant.analyses.unbalance import unbalance_response
from resonant.errors import ModelError
from resonant.modal import gyroscopic_modes, lowest_gyroscopic_modes, modal_assurance
from resonant.model import loads
from resonant.system import linear_system

JEFFCOTT = EXAMPLES / "rotors" / "jeffcott_rotor.toml"


def jeffcott_roots(m: float, k: float, ce: float, ci: float, speed: float) -> np.ndarray:
    """The roots s of m s^2 + (c_e + c_i) s + (k - i Omega c_i) = 0 (forward: Im s > 0) and
    of its conjugate-whirl twin (backward)."""
    forward = np.roots([m, ce + ci, k - 1j * speed * ci])
    backward = np.roots([m, ce + ci, k + 1j * speed * ci])
    return np.concatenate([forward[forward.imag > 0], np.conj(backward[backward.imag < 0])])


# -- the kernel ----------------------------------------------------------------------------

def test_gyroscopic_modes_jeffcott_closed_form() -> None:
    """Genta 2005 sec. 4.7: the roots of the complex-coordinate equation, to 1e-12."""
    m, k, ce, ci, speed = 10.0, 1e6, 20.0, 10.0, 500.0
    K = np.array([[k, ci * speed], [-ci * speed, k]])
    s, q = gyroscopic_modes(m * np.eye(2), (ce + ci) * np.eye(2), K)
    expected = jeffcott_roots(m, k, ce, ci, speed)
    assert len(s) == 2
    for root in expected:
        assert np.min(np.abs(s - root)) < 1e-12 * abs(root)
    assert np.allclose(np.linalg.norm(q, axis=0), 1.0)


def test_sparse_gyroscopic_modes_agree_with_dense() -> None:
    """The shift-invert route gives the dense kernel's lowest modes (same order) to 1e-9."""
    rng = np.random.default_rng(1)
    n = 60
    A = rng.standard_normal((n, n))
    K = A @ A.T + n * np.eye(n)
    G = rng.standard_normal((n, n))
    G = G - G.T
    M = np.diag(rng.uniform(1, 2, n))
    dense_s, dense_q = gyroscopic_modes(M, 0.3 * G, K)
    s, q = lowest_gyroscopic_modes(M, 0.3 * G, K, 5)
    assert np.allclose(s, dense_s[:5], rtol=1e-9, atol=0)
    assert np.all(np.diag(modal_assurance(q, dense_q[:, :5])) > 1 - 1e-9)


# -- [matrices] with G ---------------------------------------------------------------------

def test_matrices_gyroscopic_term_is_speed_times_g() -> None:
    model = loads('[parameters]\nOmega = "60 rpm"\n[matrices]\nM = [[1, 0], [0, 1]]\n'
                  'K = [[4, 0], [0, 4]]\nC = [[0.1, 0], [0, 0.1]]\nG = [[0, 2], [-2, 0]]\n'
                  'speed = "Omega"\n')
    C = linear_system(model).numeric().C
    assert np.allclose(C, [[0.1, 4 * np.pi], [-4 * np.pi, 0.1]], rtol=1e-14)


def test_energies_give_the_gyroscopic_matrix() -> None:
    """T with I_p Omega ax' ay (a spinning disc's tilts) gives C = Omega G, G skew, by
    Lagrange's equations, the same modes as [matrices] with G."""
    energies = loads('[parameters]\nIt = 1\nIp = 2\nOmega = 3\nk = 4\n[coordinates]\n'
                     'd_ax = ""\nd_ay = ""\n[energy]\n'
                     'T = "It*(d_ax\'^2 + d_ay\'^2)/2 + Ip*Omega*d_ax\'*d_ay"\n'
                     'U = "k*(d_ax^2 + d_ay^2)/2"\n')
    matrices = loads('[parameters]\nOmega = 3\n[matrices]\nM = [[1, 0], [0, 1]]\n'
                     'K = [[4, 0], [0, 4]]\nG = [[0, 2], [-2, 0]]\nspeed = "Omega"\n'
                     '[coordinates]\nd_ax = ""\nd_ay = ""\n')
    a, b = (linear_system(m).numeric() for m in (energies, matrices))
    assert np.allclose(a.C, [[0, 6], [-6, 0]]) and np.allclose(a.C, b.C)
    speeds = np.linspace(0, 3, 7)
    r1 = campbell(linear_system(energies), speeds, modes=2, speed="Omega")
    r2 = campbell(linear_system(matrices), speeds, modes=2)
    assert np.allclose(r1.frequencies, r2.frequencies, rtol=1e-12)


# -- the Jeffcott rotor --------------------------------------------------------------------

def test_jeffcott_campbell_against_closed_form() -> None:
    """Genta 2005 sec. 4.7: frequencies and log decrements of both whirls at every speed
    (1e-10), the 1x critical speed where Im s = Omega of the forward root (1e-9) and the
    threshold omega_n (1 + c_e/c_i) = 948.683 rad/s (1e-9)."""
    result = JEFFCOTT_RESULT()
    m, k, ce, ci = 10.0, 1e6, 20.0, 10.0
    for i, speed in enumerate(result.speeds):
        roots = jeffcott_roots(m, k, ce, ci, speed)   # forward, backward
        whirl = result.whirl[i]
        forward = result.eigenvalues[i, whirl.index("forward")] if speed > 0 else None
        if forward is not None:
            assert abs(forward - roots[0]) < 1e-10 * abs(roots[0])
    wn = np.sqrt(k / m)
    assert result.threshold.verdict == "threshold"
    assert result.threshold.whirl == "forward"
    assert result.threshold.speed == pytest.approx(wn * (1 + ce / ci), rel=1e-9)
    forward = [c for c in result.critical_speeds if c.whirl == "forward"]
    assert len(forward) == 1
    speed = forward[0].speed
    assert jeffcott_roots(m, k, ce, ci, speed)[0].imag == pytest.approx(speed, rel=1e-9)
    assert speed == pytest.approx(wn, rel=1e-4)


_CACHE: dict[str, Campbell] = {}


def JEFFCOTT_RESULT() -> Campbell:  # noqa: N802 - one computation for several tests
    if "j" not in _CACHE:
        _CACHE["j"] = campbell(linear_system(loads(JEFFCOTT.read_text(), source=str(JEFFCOTT))))
    return _CACHE["j"]


def test_threshold_not_in_range_is_said() -> None:
    result = campbell(linear_system(loads(JEFFCOTT.read_text())), np.linspace(0, 500, 6),
                      modes=2)
    assert result.threshold.speed is None and result.threshold.verdict == "stable in range"
    assert "not extrapolated" in result.summary()


def test_campbell_round_trips_through_json() -> None:
    result = JEFFCOTT_RESULT()
    back = Campbell.from_dict(json.loads(json.dumps(result.to_dict())))
    assert back.to_dict() == result.to_dict()


# -- the overhung disc: gyroscopic stiffening -----------------------------------------------

OVERHUNG = """
title = "disc on an overhung massless shaft"
[parameters]
a = 2e5        # EI / L^3
L = 0.3
m = 5
It = 0.05
Ip = 0.09
Omega = 0
[coordinates]
d_x = ""
d_y = ""
d_ax = ""
d_ay = ""
[matrices]
M = [["m", 0, 0, 0], [0, "m", 0, 0], [0, 0, "It", 0], [0, 0, 0, "It"]]
K = [["12*a", 0, 0, "-6*L*a"], [0, "12*a", "6*L*a", 0], [0, "6*L*a", "4*L^2*a", 0],
     ["-6*L*a", 0, 0, "4*L^2*a"]]
G = [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, "Ip"], [0, 0, "-Ip", 0]]
speed = "Omega"
"""


def overhung_frequencies(speed: float, forward: bool) -> np.ndarray:
    """Friswell et al. 2010 sec. 3.6: the positive roots of the whirl's frequency equation."""
    a, L, m, It, Ip = 2e5, 0.3, 5.0, 0.05, 0.09
    g = Ip * speed * (1 if forward else -1)
    poly = np.polysub(np.polymul([-m, 0, 12 * a], [-It, g, 4 * L * L * a]), [36 * L * L * a * a])
    roots = np.roots(poly)
    return np.sort(roots[(np.abs(roots.imag) < 1e-9 * np.abs(roots)) & (roots.real > 0)].real)


def test_overhung_disc_forward_and_backward_whirl() -> None:
    """Each tracked branch matches its closed-form whirl frequency at every speed to 1e-10;
    forward branches rise with speed (gyroscopic stiffening), backward ones fall."""
    speeds = np.linspace(0, 3000, 31)
    result = campbell(linear_system(loads(OVERHUNG)), speeds, modes=4)
    assert result.refined == 0 or result.refined < 40
    for i, speed in enumerate(result.speeds):
        if speed == 0:
            continue
        fw, bw = overhung_frequencies(speed, True), overhung_frequencies(speed, False)
        for j in range(4):
            label = result.whirl[i][j]
            exact = fw if label == "forward" else bw
            assert label in ("forward", "backward")
            assert np.min(np.abs(exact - result.frequencies[i, j])) < 1e-10 * exact.max()
    labels = [result.whirl[-1][j] for j in range(4)]
    assert sorted(labels) == ["backward", "backward", "forward", "forward"]
    for j in range(4):
        rising = result.frequencies[-1, j] > result.frequencies[1, j]
        assert rising == (labels[j] == "forward")


def test_tracking_never_jumps_at_a_veering() -> None:
    """Two anisotropic modes that veer (a weak coupling eps): sampled coarsely, the
    tracked branches stay on the continuous eigenvalue curves (the lower below the upper
    at every speed) and refinement adds speeds there."""
    model = loads("""
[parameters]
Omega = 0
eps = 0.05
[matrices]
M = [[1, 0], [0, 1]]
K = [["1 + Omega", "eps"], ["eps", "2 - Omega"]]
speed = "Omega"
""")
    system = linear_system(model)
    coarse = track_modes(system, "Omega", np.linspace(0, 1, 5), 2)
    assert coarse.refined > 0
    assert np.all(coarse.frequencies[:, 0] < coarse.frequencies[:, 1])
    exact = np.sqrt(np.array([np.linalg.eigvalsh([[1 + w, 0.05], [0.05, 2 - w]])
                              for w in coarse.speeds]))
    assert np.allclose(coarse.frequencies, exact, rtol=1e-12)


def test_crossing_forward_and_backward_are_not_exchanged() -> None:
    """The overhung disc's forward and backward branches cross the other family: whirl
    labels stay constant along each branch."""
    result = campbell(linear_system(loads(OVERHUNG)), np.linspace(0, 6000, 13), modes=4)
    for j in range(4):
        labels = {result.whirl[i][j] for i in range(1, len(result.speeds))}
        assert len(labels) == 1


# -- bad input -----------------------------------------------------------------------------

@pytest.mark.parametrize("text, key", [
    ('[parameters]\nW = 1\n[matrices]\nM = [[1]]\nK = [[1]]\nG = [[0]]\n', "speed"),
    ('[parameters]\nW = 1\n[matrices]\nM = [[1]]\nK = [[1]]\nG = [[0]]\nspeed = "V"\n',
     "speed"),
    ('[parameters]\nW = 1\n[matrices]\nM = [[1]]\nK = [[1]]\nspeed = "W"\n'
     '[campbell]\nto = "3 m/s"\n', "to"),
    ('[parameters]\nW = 1\n[matrices]\nM = [[1]]\nK = [[1]]\nspeed = "W"\n'
     '[campbell]\nfrom = "100 rpm"\nto = "50 rpm"\n', "to"),
    ('[parameters]\nW = 1\n[matrices]\nM = [[1]]\nK = [[1]]\nspeed = "W"\n'
     '[campbell]\nto = "50 Hz"\n', "to"),
    ('[parameters]\nW = 1\n[matrices]\nM = [[1]]\nK = [[1]]\nspeed = "W"\n'
     '[campbell]\nto = 5\norders = [0]\n', "orders"),
])
def test_bad_rotor_input_names_the_key(text: str, key: str, tmp_path) -> None:
    path = tmp_path / "rotor.toml"
    path.write_text(text)
    with pytest.raises(ModelError) as info:
        loads(text, source=str(path))
    assert any(p.key == key for p in info.value.problems)
    status, _, err = run_cli(["campbell", path])
    assert status == 2 and "rotor.toml" in err and key in err


def test_speeds_not_increasing_is_an_error() -> None:
    with pytest.raises(ModelError, match="increasing"):
        campbell(linear_system(loads(JEFFCOTT.read_text())), [0.0, 10.0, 5.0])


# -- the command ----------------------------------------------------------------------------

def test_campbell_command_json_and_plot(tmp_path) -> None:
    plot = tmp_path / "campbell.svg"
    status, out, _ = run_cli(["campbell", JEFFCOTT, "--to", "6000 rpm", "--points", "13",
                              "--orders", "1,2", "--json", "--plot", plot])
    assert status == 0 and plot.stat().st_size > 1000
    data = json.loads(out)
    assert data["orders"] == [1.0, 2.0]
    assert {c["whirl"] for c in data["critical_speeds"]} == {"forward", "backward"}
    assert data["stability_threshold"]["verdict"] == "stable in range"
    assert "rad/s" in data["conventions"]["speed"]


# -- the [rotor] section: Friswell et al. (2010) Example 5.9.1 ---------------------------------

FRISWELL = EXAMPLES / "rotors" / "friswell_5_9_1.toml"


def test_friswell_5_9_1_published_frequencies() -> None:
    """Friswell, Penny, Garvey & Lees (2010), Example 5.9.1, p. 206, as ROSS's tests pin
    them (ross/tests/test_examples.py, 1e-3): the lateral natural frequencies at 0 and
    4000 rpm (the book's 650.41 rad/s, the same at both speeds, is the mode outside the
    lateral plane ROSS's six coordinates a node add), here to 1e-3; and ROSS 2.3.0's
    run_modal on the same model (recorded, 6 elements) to 1e-8."""
    model = loads(FRISWELL.read_text(), source=str(FRISWELL))
    result = campbell(linear_system(model), [0.0, 4000 * np.pi / 30], modes=6)
    book_0 = [86.66, 86.66, 274.31, 274.31, 716.78]
    book_4000 = [85.39, 87.80, 251.78, 294.71, 600.18]
    assert np.allclose(np.delete(result.frequencies[0], 4), book_0, rtol=1e-3)
    assert np.allclose(result.frequencies[-1, :5], book_4000, rtol=1e-3)
    ross_4000 = [85.389467, 87.795864, 251.784604, 294.713331, 600.179362, 827.075362]
    assert np.allclose(result.frequencies[-1], ross_4000, rtol=1e-8, atol=1e-6)
    assert [result.whirl[-1][j] for j in range(4)] == ["backward", "forward"] * 2
    assert result.threshold.verdict == "stable in range"


def test_rotor_coordinates_are_named_by_station() -> None:
    model = loads(FRISWELL.read_text())
    assert model.coordinates[:4] == ("bearing1_x", "bearing1_y", "bearing1_ax", "bearing1_ay")
    assert "disc2_ay" in model.coordinates and len(model.coordinates) == 28


def test_speed_dependent_bearings_threshold() -> None:
    """The fluid-film-like example: tables interpolated in speed and kxy = q Omega; the
    threshold is found by Brent's method: Re s of the unstable branch there is 0 to the
    kernel's tolerance, and the speed is the same on a finer grid (1e-8)."""
    path = EXAMPLES / "rotors" / "rotor_fluid_film.toml"
    system = linear_system(loads(path.read_text(), source=str(path)))
    coarse = campbell(system, np.linspace(0, 6000 * np.pi / 30, 13), modes=4)
    fine = campbell(system, np.linspace(0, 6000 * np.pi / 30, 25), modes=4)
    assert coarse.threshold.verdict == "threshold" and coarse.threshold.whirl == "forward"
    assert coarse.threshold.speed == pytest.approx(fine.threshold.speed, rel=1e-8)
    point = system.numeric(Omega=coarse.threshold.speed)
    s, _ = gyroscopic_modes(np.asarray(point.M), np.asarray(point.C), np.asarray(point.K))
    nearest = s[np.argmin(np.abs(np.abs(s.imag) - coarse.threshold.frequency))]
    assert abs(nearest.real) < 1e-7 * abs(nearest)


def test_table_is_interpolated_in_speed() -> None:
    text = FRISWELL.read_text().replace('kxx = "1 MN/m"\nkyy = "1 MN/m"\n\n[[rotor.bearing]]\n'
                                        'station = 6',
                                        'kxx = { speed = ["0 rpm", "1000 rpm"], values = '
                                        '[1e6, 3e6] }\nkyy = "1 MN/m"\n\n[[rotor.bearing]]\n'
                                        'station = 6', 1)
    system = linear_system(loads(text))
    K = system.batch("Omega", np.array([0.0, 500 * np.pi / 30, 5000.0])).K
    assert np.allclose(K[:, 0, 0] - K[0, 0, 0], [0.0, 1e6, 2e6], rtol=1e-12, atol=1e-3)


@pytest.mark.parametrize("change, key", [
    (('kxx = "1 MN/m"', 'k = [[1e6, 0, 0], [0, 1e6, 0], [0, 0, 1]]'), "k"),
    (('name = "disc1"', 'name = "disc1"\nm = 10\nIp = -1\nIt = 1'), "Ip"),
    (('kxx = "1 MN/m"', 'kxx = { speed = [0, 100, 50], values = [1, 2, 3] }'), "kxx"),
    (('station = 4', 'station = 40'), "station"),
    (('speed = "Omega"', 'speed = "W"'), "speed"),
])
def test_bad_rotor_section_names_entry_and_key(change: tuple[str, str], key: str,
                                               tmp_path) -> None:
    """A bearing matrix that is not given as 2 x 2 coefficients, a negative inertia, a
    speed table that does not increase, a station off the shaft: file, entry, key, exit 2."""
    path = tmp_path / "rotor.toml"
    path.write_text(FRISWELL.read_text().replace(*change, 1))
    with pytest.raises(ModelError) as info:
        loads(path.read_text(), source=str(path))
    assert any(p.key == key for p in info.value.problems), info.value
    status, _, err = run_cli(["campbell", path])
    assert status == 2 and "rotor.toml" in err and key in err


# -- the unbalance response -------------------------------------------------------------------

def test_jeffcott_unbalance_orbit_and_phase_closed_form() -> None:
    """Genta 2005 sec. 4.7 / Vance et al. 2010 sec. 2.7: the synchronous forward whirl
    X = m e Omega^2 / (k - m Omega^2 + i Omega c_e) (the rotating damping does not act on
    it), a circle, its lag atan2(c_e Omega, k - m Omega^2): 90 degrees at omega_n; to 1e-10."""
    m, k, ce = 10.0, 1e6, 20.0
    wn = np.sqrt(k / m)
    speeds = np.array([0.5 * wn, wn, 2 * wn])
    r = unbalance_response(linear_system(loads(JEFFCOTT.read_text())), speeds)
    exact = 1e-4 * speeds ** 2 / (k - m * speeds ** 2 + 1j * speeds * ce)
    assert np.allclose(r.major[:, 0], np.abs(exact), rtol=1e-10)
    assert np.allclose(r.minor[:, 0], np.abs(exact), rtol=1e-8)
    assert np.allclose(r.phase_lag[:, 0], np.arctan2(ce * speeds, k - m * speeds ** 2),
                       rtol=1e-10)
    assert r.phase_lag[1, 0] == pytest.approx(np.pi / 2, rel=1e-12)
    assert all(p == ("forward",) for p in r.precession)
    data = r.to_dict()
    assert data["amplitude_convention"].startswith("0-pk")
    assert np.allclose(data["stations"]["(x, y)"]["major_axis_pk_pk"], 2 * np.abs(exact))


def test_anisotropic_supports_whirl_backward_between_criticals() -> None:
    """A Jeffcott disc on supports stiffer in y: X = F / (k_x - m W^2 + i W c),
    Y = -i F / (k_y - m W^2 + i W c); between the two critical speeds the orbit is run
    backward (Vance et al. 2010 sec. 2.9), outside them forward; semi-axes to 1e-10."""
    model = loads('[parameters]\nW = 0\n[coordinates]\nx = ""\ny = ""\n[matrices]\n'
                  'M = [[1, 0], [0, 1]]\nK = [[100, 0], [0, 400]]\nC = [[0.5, 0], [0, 0.5]]\n'
                  'speed = "W"\n[[unbalance]]\nat = ""\namount = 0.01\n')
    speeds = np.array([5.0, 15.0, 30.0])
    r = unbalance_response(linear_system(model), speeds)
    X = 0.01 * speeds ** 2 / (100 - speeds ** 2 + 0.5j * speeds)
    Y = -1j * 0.01 * speeds ** 2 / (400 - speeds ** 2 + 0.5j * speeds)
    forward, backward = np.abs(X + 1j * Y) / 2, np.abs(np.conj(X) + 1j * np.conj(Y)) / 2
    assert np.allclose(r.major[:, 0], forward + backward, rtol=1e-10)
    assert np.allclose(r.minor[:, 0], np.abs(forward - backward), rtol=1e-10)
    assert [p[0] for p in r.precession] == ["forward", "backward", "forward"]


def test_unbalance_command(tmp_path) -> None:
    status, out, _ = run_cli(["unbalance", JEFFCOTT, "--to", "6000 rpm", "--points", "7",
                              "--plot", tmp_path / "u.png"])
    assert status == 0 and "0-pk" in out and "pk-pk" in out
    bad = tmp_path / "bad.toml"
    bad.write_text(JEFFCOTT.read_text().replace('at = ""', 'at = "disc9"'))
    status, _, err = run_cli(["unbalance", bad])
    assert status == 2 and "unbalance 1" in err and "at" in err


def test_large_rotor_uses_the_sparse_solver_and_agrees_with_dense() -> None:
    """A [rotor] of 404 coordinates (above the dense limit): the shift-invert modes at
    each speed are the dense kernel's lowest, to 1e-9."""
    import sys

    sys.path.insert(0, str(EXAMPLES.parent / "benchmarks"))
    from bench_rotor import rotor_toml

    system = linear_system(loads(rotor_toml(100)))
    assert system.n == 404
    result = campbell(system, [0.0, 200.0, 400.0], modes=4)
    point = system.numeric(Omega=400.0)
    s, _ = gyroscopic_modes(point.M, point.C, point.K)   # sparse: the kernel densifies
    assert np.allclose(np.sort(result.frequencies[-1]), np.sort(np.abs(s.imag[:4])),
                       rtol=1e-9)
    # the critical speeds (found on the modes near the branch, gyroscopic_modes_near): a
    # dense-kernel eigenvalue there has |Im s| = the speed, to the speed tolerance
    assert len(result.critical_speeds) >= 2
    c = result.critical_speeds[0]
    point = system.numeric(Omega=c.speed)
    s, _ = gyroscopic_modes(point.M, point.C, point.K)
    assert np.min(np.abs(np.abs(s.imag) - c.speed)) < 1e-10 * 400.0 * 10


# -- a threshold at the start of a bracket -------------------------------------------------

#: a damped Jeffcott rotor with a cross-coupled stiffness kxy = -kyx = q Omega (no G): in
#: z = x + i y, m z'' + c z' + (k - i q Omega) z = 0, whose forward root crosses Re s = 0 at
#: q Omega = c omega_n (Genta 2005, sec. 4.7, with the cross coupling in place of the
#: rotating damping): Omega_th = c sqrt(k/m) / q = 632.4555 rad/s for these values
CROSS_COUPLED = '''[parameters]
Omega = "0 rad/s"
m = "10 kg"
k = "1 MN/m"
c = "CDAMP N*s/m"
q = "10 N*s/m"
[matrices]
M = [["m", 0], [0, "m"]]
C = [["c", 0], [0, "c"]]
K = [["k", "q*Omega"], ["-q*Omega", "k"]]
G = [[0, 0], [0, 0]]
speed = "Omega"
'''


@pytest.mark.parametrize("grid, offset", [
    ("bracket", 1e-8),    # a grid speed just above the threshold: marginal there already
    ("first", 1e-8),      # the range starts just above the threshold
    ("first", -1e-8),     # the range starts just below it: the root lies just after it
])
def test_threshold_at_the_start_of_a_bracket(grid: str, offset: float) -> None:
    """The threshold where the unstable branch is marginal (|Re s| within the kernel's
    stability tolerance) at the speed that starts its bracket, there being no change of
    sign to find: it is that speed, or the root just after it, and never 'stable in range'
    or a failed bracket. Closed form Omega_th = c omega_n / q (Genta 2005, sec. 4.7) to
    2e-8 (the offset of the grid speed, 1e-8, plus the root finder's 1e-10)."""
    m, k, c, q = 10.0, 1e6, 20.0, 10.0
    wn = np.sqrt(k / m)
    exact = c * wn / q
    near = exact * (1 + offset)
    speeds = [0.0, 300.0, near, 900.0] if grid == "bracket" else [near, 700.0, 900.0]
    system = linear_system(loads(CROSS_COUPLED.replace("CDAMP", str(c))))
    threshold = campbell(system, speeds, modes=2).threshold
    assert threshold.verdict == "threshold" and threshold.mode is not None
    assert threshold.speed == pytest.approx(exact, rel=2e-8)
    assert threshold.frequency == pytest.approx(wn, rel=1e-8)
    # the closed-form forward root at that speed is marginal to the kernel's tolerance
    root = np.roots([m, c, k - 1j * q * threshold.speed])
    assert np.max(root.real) <= 1e-9 * wn


def test_undamped_rotor_with_growing_cross_coupling_is_unstable_from_rest() -> None:
    """Undamped (c = 0) with kxy = q Omega: marginal at rest, m s^2 + k - i q Omega = 0 has a
    root with Re s > 0 at every Omega > 0, so the threshold is the first speed, 0 rad/s."""
    system = linear_system(loads(CROSS_COUPLED.replace("CDAMP", "0")))
    result = campbell(system, np.linspace(0, 500, 6), modes=2)
    assert np.max(result.eigenvalues[1:].real) > 0.5
    assert result.threshold.verdict == "threshold" and result.threshold.speed == 0.0
    assert result.threshold.frequency == pytest.approx(np.sqrt(1e5), rel=1e-12)
