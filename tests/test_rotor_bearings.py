"""Pedestal (support) masses in ``[rotor]`` bearings and the bearing forces of the unbalance
response (docs/rotors.md), against the closed form of a two-mass chain.

Reference: a rigid disc (mass m) on a bearing (k_b, c_b) on a pedestal (mass m_p) on a
support (k_s): in the complex coordinate z = x + i y of an isotropic rotor the unbalance
m e Omega^2 e^(i Omega t) on the disc gives

    [[k_b + i Omega c_b - m Omega^2, -(k_b + i Omega c_b)],
     [-(k_b + i Omega c_b), k_b + i Omega c_b + k_s - m_p Omega^2]] (z_d, z_p) = (m e Omega^2, 0)

(Vance, Zeidan & Murphy 2010, sec. 2.9, a flexible support; a two-degree-of-freedom
chain), the bearing force (k_b + i Omega c_b)(z_d - z_p), a forward circle, and without
damping the natural frequencies solve m m_p w^4 - (m (k_b + k_s) + m_p k_b) w^2 + k_b k_s = 0.
"""

from __future__ import annotations

import numpy as np
import pytest

from resonant.analyses.unbalance import unbalance_response
from resonant.errors import ModelError
from resonant.modal import gyroscopic_modes
from resonant.model import loads
from resonant.system import linear_system

M, MP, KB, CB, KS, ME = 10.0, 20.0, 1e6, 100.0, 4e6, 1e-4


def chain(cb: float = CB, pedestal: bool = True) -> str:
    support = (f', pedestal = {{ m = "{MP} kg", kxx = "{KS} N/m", kyy = "{KS} N/m" }}'
               if pedestal else "")
    return f"""
title = "disc on a bearing on a pedestal"
[parameters]
Omega = 0
[rotor]
speed = "Omega"
disc = [{{ station = 0, name = "d", m = {M}, Ip = 0.1, It = 0.05 }}]
bearing = [{{ station = 0, kxx = {KB}, kyy = {KB}, cxx = {cb}, cyy = {cb}{support} }}]
[[unbalance]]
at = "d"
amount = {ME}
"""


def test_pedestal_coordinates_and_natural_frequencies() -> None:
    """The undamped chain's two frequencies (each twice: x and y) to 1e-10."""
    model = loads(chain(cb=0.0))
    system = linear_system(model)
    assert system.coordinates[-2:] == ("d_pedestal_x", "d_pedestal_y")
    point = system.numeric(Omega=0.0)
    s, _ = gyroscopic_modes(point.M, point.C, point.K)
    found = np.sort(np.abs(s.imag[np.abs(s) > 1.0]))
    w2 = np.roots([M * MP, -(M * (KB + KS) + MP * KB), KB * KS])
    expected = np.sort(np.repeat(np.sqrt(w2), 2))
    assert np.allclose(found, expected, rtol=1e-10)


def test_bearing_force_through_a_pedestal_closed_form() -> None:
    """The disc's orbit and the bearing force at 5 speeds (through both resonances) to
    1e-9; a forward circle."""
    speeds = np.array([50.0, 180.0, 300.0, 700.0, 1200.0])
    result = unbalance_response(linear_system(loads(chain())), speeds)
    assert result.bearings == ("d",)   # named after its station
    for i, w in enumerate(speeds):
        b = KB + 1j * w * CB
        A = np.array([[b - M * w * w, -b], [-b, b + KS - MP * w * w]])
        zd, zp = np.linalg.solve(A, [ME * w * w, 0.0])
        force = b * (zd - zp)
        assert result.major[i, 0] == pytest.approx(abs(zd), rel=1e-9)
        assert result.bearing_force[i, 0] == pytest.approx(abs(force), rel=1e-9)
        fx, fy = result.bearing_forces[i, 0]
        assert fx == pytest.approx(force, rel=1e-9)
        assert fy == pytest.approx(-1j * force, rel=1e-9)   # forward: y lags x by 90 deg
    data = result.to_dict()["bearing_forces"]["d"]
    assert data["major_axis_pk_pk_N"][2] == pytest.approx(2 * result.bearing_force[2, 0])
    assert "peak force 0-pk [N]" in result.summary()


def test_grounded_bearing_force_is_k_x_plus_c_xdot() -> None:
    """Without a pedestal the force is (k + i Omega c) X of the station, exactly."""
    result = unbalance_response(linear_system(loads(chain(pedestal=False))),
                                np.array([100.0, 316.0]))
    X = result.X[:, 0]
    expected = (KB + 1j * result.speeds * CB) * X
    assert np.allclose(result.bearing_forces[:, 0, 0], expected, rtol=1e-12)


@pytest.mark.parametrize(("pedestal", "key", "message"), [
    ('"heavy"', "pedestal", "a pedestal is a table"),
    ('{ kxx = 1e6 }', "m", "missing"),
    ('{ m = 10, mass = 3 }', "mass", "unknown key"),
    ('{ m = -10 }', "m", "must be positive"),
])
def test_bad_pedestal(pedestal: str, key: str, message: str) -> None:
    text = chain().replace(
        f'pedestal = {{ m = "{MP} kg", kxx = "{KS} N/m", kyy = "{KS} N/m" }}',
        f"pedestal = {pedestal}")
    with pytest.raises(ModelError, match=message) as caught:
        loads(text, source="p.toml")
    problem = caught.value.problems[0]
    assert (problem.file, problem.key) == ("p.toml", key)
    assert problem.section.startswith("rotor.bearing 1")


# -- the undamped critical speed map --------------------------------------------------------

def test_critical_speed_map_of_the_chain_closed_form() -> None:
    """At each bearing stiffness the chain's two frequencies (forward and backward whirl
    alike: no gyroscopic coupling of the translations) to 1e-10; damping ignored."""
    from resonant.analyses.rotor_map import critical_speed_map

    stiffness = [1e5, 1e6, 1e7, 1e8]
    result = critical_speed_map(linear_system(loads(chain())), stiffness, modes=4)
    for i, k in enumerate(stiffness):
        w = np.sqrt(np.sort(np.roots([M * MP, -(M * (k + KS) + MP * k), k * KS])))
        assert np.allclose(result.speeds[i, 0], np.repeat(w, 2), rtol=1e-10)
    chart = result.chart()
    assert chart.xlog and chart.ylog and len(chart.curves) == 4
    assert "undamped" in result.summary()
    assert result.to_dict()["critical_speeds_rpm"][0][0][0] == pytest.approx(
        result.speeds[0, 0, 0] * 30 / np.pi)


def test_critical_speed_map_agrees_with_campbell() -> None:
    """Friswell et al. Example 5.9.1 (undamped, 1 MN/m bearings): the map's direct
    eigenproblem and campbell()'s tracked branches with Brent's method give the same 1x
    and 2x critical speeds below 4000 rpm, to 1e-8."""
    from conftest import EXAMPLES
    from resonant.analyses.campbell import campbell
    from resonant.analyses.rotor_map import critical_speed_map

    system = linear_system(loads((EXAMPLES / "rotors" / "friswell_5_9_1.toml").read_text()))
    top = 4000 * np.pi / 30
    tracked = campbell(system, np.linspace(0, top, 9), modes=4, orders=[1, 2])
    found = critical_speed_map(system, [1e6], modes=4, orders=[1, 2])
    for o, r in enumerate((1.0, 2.0)):
        expected = sorted(c.speed for c in tracked.critical_speeds if c.order == r)
        direct = found.speeds[0, o][found.speeds[0, o] < top]
        assert len(expected) == len(direct) >= 2
        assert np.allclose(direct, expected, rtol=1e-8)
        whirl = [c.whirl for c in sorted(tracked.critical_speeds, key=lambda c: c.speed)
                 if c.order == r]
        assert list(found.whirl[0][o][:len(whirl)]) == whirl


def test_critical_speed_map_bad_input() -> None:
    from resonant.analyses.rotor_map import critical_speed_map

    system = linear_system(loads(chain()))
    with pytest.raises(ModelError, match="positive and increasing"):
        critical_speed_map(system, [1e6, 1e5])
    plain = linear_system(loads("[matrices]\nM = [[1]]\nK = [[4]]\n"))
    with pytest.raises(ModelError, match="needs a \\[rotor\\] with bearings"):
        critical_speed_map(plain, [1e6])


def test_speed_map_command(tmp_path) -> None:
    import json

    from conftest import EXAMPLES, run_cli

    model = EXAMPLES / "rotors" / "friswell_5_9_1.toml"
    status, out, _ = run_cli(["speed-map", model, "--stiffness", "1e6:1e8:3", "--modes",
                              "2", "--json", "--plot", tmp_path / "map.svg"])
    assert status == 0 and (tmp_path / "map.svg").exists()
    data = json.loads(out)
    assert data["stiffness_N_m"] == pytest.approx([1e6, 1e7, 1e8])
    assert data["critical_speeds_rpm"][0][0] == pytest.approx([825.13, 829.87], abs=0.01)
    status, _, err = run_cli(["speed-map", EXAMPLES / "rotors" / "jeffcott_rotor.toml"])
    assert status == 2 and "[rotor] with bearings" in err
    status, _, err = run_cli(["speed-map", model, "--stiffness", "1e6:1e5:3"])
    assert status == 2 and "FROM:TO:N" in err


def test_pedestal_coefficients_that_depend_on_the_speed() -> None:
    """A pedestal support stiffening with the speed (an expression, and a table in speed):
    at each speed the chain's two frequencies with k_s(Omega), to 1e-10; the undamped map,
    solved for the speed directly, refuses it and the damped one takes it."""
    from resonant.analyses.rotor_map import critical_speed_map

    for support in ('"4e6 + 2000*Omega"', "{ speed = [0, 1000], values = [4e6, 6e6] }"):
        text = chain(cb=0.0).replace(f'kxx = "{KS} N/m", kyy = "{KS} N/m"',
                                     f"kxx = {support}, kyy = {support}")
        text = text.replace("Ip = 0.1", "Ip = 0")  # no nutation: the tilts stay at s = 0
        model = loads(text, source="p.toml")
        system = linear_system(model)
        for speed in (0.0, 400.0):
            ks = KS + 2000 * speed if "Omega" in support else np.interp(speed, [0, 1000],
                                                                         [4e6, 6e6])
            point = system.numeric(Omega=speed)
            s, _ = gyroscopic_modes(point.M, point.C, point.K)
            found = np.sort(np.abs(s.imag[np.abs(s) > 1.0]))
            w2 = np.roots([M * MP, -(M * (KB + ks) + MP * KB), KB * ks])
            assert np.allclose(found, np.sort(np.repeat(np.sqrt(w2), 2)), rtol=1e-10)
    with pytest.raises(ModelError, match="damped=True"):
        critical_speed_map(system, [1e6])
    damped = critical_speed_map(system, [1e6], modes=2, damped=True,
                                speeds=np.linspace(0, 800, 9))
    assert np.all(np.isfinite(damped.speeds))
