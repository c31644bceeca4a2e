"""The damped critical speed map (``critical_speed_map(..., damped=True)``, docs/rotors.md):
the bearings keep their damping and cross coupling, their direct stiffness becomes k.

Reference: a Jeffcott rotor (a rigid disc of mass m) on an isotropic damped bearing with
cross-coupled stiffness, kxx = kyy = k, kxy = -kyx = q, cxx = cyy = c.  In z = x + i y the
motion is m z'' + c z' + (k - i q) z = 0 (derived in the complex coordinate; the form of the
Jeffcott rotor with rotating damping, Genta, Dynamics of Rotating Systems, 2005, sec. 4.7,
with q for Omega c_i, as in tests/test_rotor.py), so the forward whirl's
eigenvalue is the root of m s^2 + c s + (k - i q) = 0 with Im s > 0, the backward one's that
of m s^2 + c s + (k + i q) = 0; nothing depends on the speed, so the damped 1x critical
speeds are Omega = Im s of each, their damping ratios -Re s / |s|.  The two frequencies are
equal (Im sqrt(a - i b) = Im sqrt(a + i b) up to sign), the forward mode less damped (the
cross coupling feeds it).  Closed form, met to 1e-9 (the bisection stops at 1e-10 of the
top speed).
"""

from __future__ import annotations

import numpy as np
import pytest

from resonant import loads
from resonant.errors import ModelError

MASS, C, Q = 10.0, 200.0, 2e4


def jeffcott(c: float = C, q: float = Q, k: float = 1e6, campbell: bool = True) -> str:
    section = "[campbell]\nfrom = 0\nto = 2000\npoints = 21\nmodes = 2\n" if campbell else ""
    return f"""
title = "Jeffcott rotor on a damped, cross-coupled bearing"
[parameters]
Omega = 0
[rotor]
speed = "Omega"
disc = [{{ station = 0, name = "d", m = {MASS}, Ip = 0, It = 1 }}]
bearing = [{{ station = 0, kxx = {k}, kyy = {k}, kxy = {q}, kyx = {-q}, cxx = {c}, cyy = {c} }}]
{section}"""


def closed_form(k: float, c: float = C, q: float = Q) -> dict[str, complex]:
    """The forward and backward eigenvalues (Im s > 0)."""
    return {
        whirl: next(r for r in np.roots([MASS, c, k - sign * 1j * q]) if r.imag > 0)
        for whirl, sign in (("forward", 1), ("backward", -1))
    }


def test_damped_map_of_a_cross_coupled_jeffcott_rotor_closed_form() -> None:
    stiffness = np.array([4e5, 1e6, 1e7])
    result = loads(jeffcott()).critical_speed_map(
        stiffness, modes=2, damped=True, speeds=np.linspace(0.0, 2000.0, 21)
    )
    assert result.damped and result.speeds.shape == (3, 1, 2)
    for i, k in enumerate(stiffness):
        exact = closed_form(k)
        assert set(result.whirl[i][0]) == {"forward", "backward"}
        for j, whirl in enumerate(result.whirl[i][0]):
            s = exact[whirl]
            assert result.speeds[i, 0, j] == pytest.approx(s.imag, rel=1e-9)
            assert result.damping_ratios[i, 0, j] == pytest.approx(-s.real / abs(s), rel=1e-6)
        assert exact["forward"].real > exact["backward"].real
    assert "damped" in result.summary() and "damped" in result.chart().title


def test_damped_map_meets_the_campbell_critical_speeds_and_the_undamped_map() -> None:
    """At the bearing's own stiffness the damped map's critical speeds are the Campbell
    diagram's (tracked, Brent); without damping and cross coupling it is the undamped map."""
    model = loads(jeffcott())
    damped = model.critical_speed_map([1e6], modes=2, damped=True)  # the [campbell] range
    tracked = sorted(c.speed for c in model.campbell().critical_speeds)
    assert np.allclose(damped.speeds[0, 0], tracked, rtol=1e-8)
    plain = loads(jeffcott(c=0.0, q=0.0))
    both = [plain.critical_speed_map([1e5, 1e7], modes=2, damped=d) for d in (True, False)]
    assert np.allclose(both[0].speeds, both[1].speeds, rtol=1e-9)
    assert both[0].whirl == both[1].whirl and both[1].damping_ratios is None


def test_damped_map_without_a_speed_range_is_refused() -> None:
    with pytest.raises(ModelError, match="needs a speed range") as info:
        loads(jeffcott(campbell=False), source="r.toml").critical_speed_map([1e6], damped=True)
    assert info.value.problems[0].key == "to"


def test_damped_map_on_soft_damped_bearings_has_no_critical_speed_at_rest() -> None:
    """Friswell et al. (2010) Example 5.9.5 on soft bearings (3e5 N/m, 3 kN s/m): its
    lowest modes are overdamped at rest (real double roots), and the speed's gyroscopic
    coupling splits each into a pair whose |Im s| grows from 0 with the speed.  Those meet
    1x only at 0 rpm, which is no critical speed; every critical speed the map gives is one
    where a mode's damped frequency equals the speed (checked on the state eigenvalues
    there, to 1e-8), of a mode that is not overdamped."""
    from pathlib import Path

    text = (Path(__file__).parents[1] / "examples" / "rotors" / "friswell_5_9_5.toml"
            ).read_text(encoding="utf-8")
    model = loads(text, source="friswell_5_9_5.toml")
    result = model.critical_speed_map([3e5], modes=4, damped=True)
    speeds, ratios = result.speeds[0, 0], result.damping_ratios[0, 0]
    assert np.all(np.isfinite(speeds)) and np.all(speeds > 10.0)  # rad/s; was 2e-6 (0 rpm)
    assert np.all(ratios < 1.0)
    soft = loads(text.replace('"1 MN/m"', '"0.3 MN/m"'), source="soft.toml")
    campbell = soft.campbell(speeds=np.sort(speeds), modes=12)
    for speed in speeds:
        at = int(np.argmin(np.abs(campbell.speeds - speed)))
        frequencies = np.abs(np.asarray(campbell.eigenvalues)[at].imag)
        assert np.min(np.abs(frequencies - speed)) <= 1e-8 * speed
