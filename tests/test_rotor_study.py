"""Rotor quantities of a study: ``critical_speed:K[@R]``, ``stability_threshold`` and
``log_decrement:K@SPEED`` (docs/rotors.md, docs/studies.md).

References:
- the Jeffcott rotor with stationary damping c_e and rotating damping c_i (Genta, Dynamics
  of Rotating Systems, Springer 2005, sec. 4.7): the threshold of instability is
  Omega_th = omega_n (1 + c_e / c_i); at rest the whirl roots solve
  m s^2 + (c_e + c_i) s + k = 0, whose log decrement is 2 pi (c_e + c_i) / (2 m omega_d);
- each sample of a study against ``campbell()`` of the model with the sample's values (the
  two routes must agree to the speed tolerance, 1e-10 of the top speed).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import EXAMPLES
from resonant.analyses.campbell import campbell, log_decrement
from resonant.errors import ModelError
from resonant.model import load, loads
from resonant.studies.quantities import evaluate_samples
from resonant.studies.run import request
from resonant.system import linear_system

JEFFCOTT = EXAMPLES / "rotors" / "jeffcott_rotor.toml"
FRISWELL = EXAMPLES / "rotors" / "friswell_5_9_1.toml"

#: Friswell's Example 5.9.1 with its bearings' stiffness a parameter kb and a cross
#: coupling kxy = -kyx = q Omega (so that it has a threshold in the range)
ROTOR_ON_KB = FRISWELL.read_text().replace(
    'Omega = "0 rpm"', 'Omega = "0 rpm"\nkb = "1 MN/m"\nq = "150 N*s/m"').replace(
    'kxx = "1 MN/m"\nkyy = "1 MN/m"',
    'kxx = "kb"\nkyy = "kb"\nkxy = "q*Omega"\nkyx = "-q*Omega"\ncxx = "300 N*s/m"\n'
    'cyy = "300 N*s/m"').replace('to = "4000 rpm"', 'to = "6000 rpm"').replace(
    "modes = 6", "modes = 4").replace("orders = [1]", "orders = [1, 2]")


def _run(model, quantities, vary):
    spec = request(model, vary, quantities, design="grid")
    values = {k: np.asarray(v, dtype=float) for k, v in vary.items()}
    return evaluate_samples(linear_system(model), spec, values)


@pytest.fixture(scope="module")
def jeffcott():
    return load(JEFFCOTT)


def test_jeffcott_threshold_and_log_decrement_closed_form(jeffcott) -> None:
    """Genta 2005 sec. 4.7: Omega_th = sqrt(k/m)(1 + c_e/c_i) to 1e-9; beyond the range
    (k = 2e6: 1341.6 rad/s > 1256.6) it is NaN, not extrapolated; the log decrement at
    rest from the quadratic's root to 1e-9."""
    ks = [5e5, 1e6, 2e6]
    rows = _run(jeffcott, ["stability_threshold", "log_decrement:1@0 rpm", "critical_speed:1"],
                {"k": ks})
    m, ce, ci = 10.0, 20.0, 10.0
    assert list(rows["status"]) == ["ok"] * 3
    for i, k in enumerate(ks):
        threshold = math.sqrt(k / m) * (1 + ce / ci)
        if threshold < 12000 * 2 * math.pi / 60:
            assert rows["stability_threshold"][i] == pytest.approx(threshold, rel=1e-9)
        else:
            assert math.isnan(rows["stability_threshold"][i])
        s = np.roots([m, ce + ci, k])[0]
        assert rows["log_decrement:1@0 rpm"][i] == pytest.approx(
            2 * math.pi * -s.real / abs(s.imag), rel=1e-9)


def test_study_over_bearing_stiffness_reproduces_campbell() -> None:
    """Each sample of a study over the bearing stiffness kb is campbell() of the model
    with that kb: critical speeds of order 1 and 2, the threshold, to 1e-10 of the top
    speed; the log decrement at 3000 rpm is the Campbell branch's there (the kernel's
    order at that speed) to 1e-8."""
    model = loads(ROTOR_ON_KB, source="rotor_kb.toml")
    kbs = [0.6e6, 1.5e6]
    quantities = ["critical_speed:1", "critical_speed:2", "critical_speed:1@2",
                  "stability_threshold", "log_decrement:1@3000 rpm"]
    rows = _run(model, quantities, {"kb": kbs})
    top = 6000 * 2 * math.pi / 60
    for i, kb in enumerate(kbs):
        reference = campbell(linear_system(loads(ROTOR_ON_KB, overrides={"kb": kb})))
        first = [c.speed for c in reference.critical_speeds if c.order == 1]
        second = [c.speed for c in reference.critical_speeds if c.order == 2]
        assert rows["critical_speed:1"][i] == pytest.approx(first[0], abs=1e-10 * top)
        assert rows["critical_speed:2"][i] == pytest.approx(first[1], abs=1e-10 * top)
        assert rows["critical_speed:1@2"][i] == pytest.approx(second[0], abs=1e-10 * top)
        assert reference.threshold.speed is not None
        assert rows["stability_threshold"][i] == pytest.approx(reference.threshold.speed,
                                                              abs=1e-10 * top)
        at = int(np.argmin(np.abs(reference.speeds - 3000 * 2 * math.pi / 60)))
        lowest = int(np.argmin(reference.frequencies[at]))
        assert rows["log_decrement:1@3000 rpm"][i] == pytest.approx(
            reference.log_decrements[at, lowest], rel=1e-8)
    # a stiffer bearing raises the first critical speed
    assert rows["critical_speed:1"][1] > rows["critical_speed:1"][0]


def test_fewer_critical_speeds_than_asked_is_nan(jeffcott) -> None:
    rows = _run(jeffcott, ["critical_speed:5"], {"k": [1e6]})
    assert math.isnan(rows["critical_speed:5"][0]) and rows["status"][0] == "ok"


def test_log_decrement_function_checks_its_mode(jeffcott) -> None:
    system = linear_system(jeffcott)
    assert log_decrement(system, 100.0, 2) > 0
    with pytest.raises(ModelError, match="modes must be between 1 and 2"):
        log_decrement(system, 100.0, 3)


@pytest.mark.parametrize(("quantity", "message"), [
    ("critical_speed:x", "needs a number counted from 1"),
    ("critical_speed:1@-2", "positive excitation order"),
    ("log_decrement:1", "needs a speed after '@'"),
    ("log_decrement:1@3 m/s", "not an angular speed"),
    ("stability_threshold:1", "takes no ':'"),
])
def test_bad_rotor_quantities(jeffcott, quantity: str, message: str) -> None:
    with pytest.raises(ModelError, match=message) as caught:
        request(jeffcott, {"k": [1e6]}, [quantity])
    problem = caught.value.problems[0]
    assert (problem.section, problem.key) == ("study", "quantities")
    assert problem.file.endswith("jeffcott_rotor.toml")


def test_study_section_without_campbell_names_the_section() -> None:
    """A [study] asking for a critical speed in a model without [campbell]: file,
    section, key (exit 2 through the CLI, as every ModelError)."""
    text = JEFFCOTT.read_text()
    text = text[:text.index("[campbell]")] + (
        '[study]\nvary = { k = [1e6] }\nquantities = ["critical_speed:1"]\n')
    with pytest.raises(ModelError, match=r"\[campbell\]") as caught:
        loads(text, source="no_campbell.toml")
    problem = caught.value.problems[0]
    assert (problem.file, problem.section) == ("no_campbell.toml", "campbell")
