"""A rotor's ``[[unbalance]]`` in a time simulation (docs/rotors.md, The unbalance in time).

References:

* the unbalance response (:func:`resonant.analyses.unbalance.unbalance_response`, the
  harmonic solve at the speed) is the steady state the simulation settles to: after the
  transient has decayed by exp(-12) the simulated amplitudes of x and y and the orbit's
  major semi-axis equal it (1e-4: the integrator's tolerance and the sampled peak; the
  transient left is 6e-6 of it), and the simulation's stationary prediction, written in
  time, is Re(X e^(i Omega t)) of the unbalance response (1e-9: the same solve);
* an anisotropic rotor (Friswell et al. 2010, Example 5.9.2, bearings stiffer in x than in y: an
  elliptical orbit) and an unbalance at 30 deg: the stationary amplitudes of the loaded
  system are |X|, |Y| of the unbalance response (1e-9).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import EXAMPLES, run_cli
from resonant.analyses.simulate import simulate
from resonant.analyses.stationary import stationary
from resonant.analyses.unbalance import unbalance_response
from resonant.api import loads
from resonant.model.unbalance_loads import with_unbalance_loads
from resonant.system import linear_system

JEFFCOTT = EXAMPLES / "rotors" / "jeffcott_rotor.toml"
FRISWELL = EXAMPLES / "rotors" / "friswell_5_9_2.toml"


def at_speed(path, rpm: float, phase: str = "0 deg"):  # type: ignore[no-untyped-def]
    text = path.read_text().replace('Omega = "0 rpm"', f'Omega = "{rpm} rpm"')
    return loads(text.replace('phase = "0 deg"', f'phase = "{phase}"'))


def test_the_simulated_orbit_settles_to_the_unbalance_response() -> None:
    model = at_speed(JEFFCOTT, 800.0, "30 deg")
    system = model.linearize()
    sim = simulate(system)
    assert not sim.warnings, sim.warnings
    speed = 800.0 * 2 * math.pi / 60
    response = unbalance_response(system, np.array([speed, 1.01 * speed]))
    X, Y = response.X[0, 0], response.Y[0, 0]
    assert sim.steady_amplitudes["x"] == pytest.approx(abs(X), rel=1e-4)
    assert sim.steady_amplitudes["y"] == pytest.approx(abs(Y), rel=1e-4)
    window = sim.t >= sim.window[0]
    orbit = np.hypot(sim.states["x"][window], sim.states["y"][window]).max()
    assert orbit == pytest.approx(response.major[0, 0], rel=1e-4)
    # the phase: the prediction in time is Re(X e^(i Omega t)), Re(Y e^(i Omega t))
    turn = np.exp(1j * speed * sim.t)
    for name, Z in (("x", X), ("y", Y)):
        assert np.allclose(sim.linear_response[name], (Z * turn).real, rtol=0,
                           atol=1e-9 * abs(Z))


def test_an_elliptical_orbit_and_a_phase() -> None:
    model = at_speed(FRISWELL, 3000.0, "30 deg")
    speed = 3000.0 * 2 * math.pi / 60
    system = model.linearize()
    response = unbalance_response(system, np.array([speed, 1.01 * speed]))
    solution = stationary(linear_system(with_unbalance_loads(model)).numeric())
    assert not np.allclose(abs(response.X[0]), abs(response.Y[0]), rtol=1e-2)  # ellipses
    for i, station in enumerate(response.stations):
        assert solution.amplitudes[f"{station}_x"] == pytest.approx(abs(response.X[0, i]),
                                                                    rel=1e-9)
        assert solution.amplitudes[f"{station}_y"] == pytest.approx(abs(response.Y[0, i]),
                                                                    rel=1e-9)


def test_the_command_simulates_the_unbalance_and_says_so_at_rest() -> None:
    status, out, err = run_cli(["simulate", JEFFCOTT, "--duration", "0.2", "--set",
                                "Omega=800 rpm", "--json"])
    assert status == 0, err
    assert "nothing excites" not in err
    status, out, err = run_cli(["simulate", JEFFCOTT, "--duration", "0.2"])
    assert status == 0, err
    assert "the rotor is at rest (Omega = 0): its [[unbalance]] loads nothing" in err
