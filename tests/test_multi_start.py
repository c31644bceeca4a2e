"""Multi-start model updating on the study engine (resonant.studies.multi_start).

References: the model itself.  A ridge: the mass m and stiffness k of the 3-mass chain
(examples/chain3_damped.toml) fitted to its first frequency 5 % higher determine only k/m,
which every start must reach (k/m = 1.05^2 x 1000 s^-2 to 1e-6) from distinct ends (the
ridge reported).  A unique fit: the stiffnesses k1 = 1100, k2 = 950, k3 = 1000 N/m of
examples/chain3_lab.toml from the model's FRFs, every start ends there to 1e-6, one minimum.
The starts run in this process (Engine(mode="process")); the local and cluster engines are
the study engine's own (tests/test_local_workers.py), not started again here for time.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import resonant
from resonant.analyses.frf_update import FRFUpdate, model_frf
from resonant.errors import ModelError
from resonant.model.measurement_spec import ChannelMap
from resonant.studies.engine import Engine
from resonant.studies.multi_start import multi_start_update

HERE = Engine(mode="process")


def test_a_ridge_is_reported():
    model = resonant.load("examples/chain3_damped.toml")
    r = multi_start_update(model, {"k": ("500 N/m", "2 kN/m"), "m": ("0.5 kg", "2 kg")},
                           "modes", {"target_frequency": [2.2399 * 1.05]}, starts=3,
                           engine=HERE)
    ratio = r.ends[:, 0] / r.ends[:, 1]
    np.testing.assert_allclose(ratio, 1.05 ** 2 * 1000, rtol=2e-4)
    np.testing.assert_allclose(ratio, ratio[0], rtol=1e-6)
    assert r.minima == 3 and any("3 distinct minima" in w for w in r.warnings)
    assert r.starts.shape == (3, 2) and r.starts[0].tolist() == [1000.0, 1.0]
    text = json.dumps(r.to_dict())
    assert json.loads(text)["minima"] == 3 and "distinct minima" in r.summary()
    assert len(r.chart().panels[0].bars[0].x) == 3


def test_frf_fit_from_every_start():
    model = resonant.load("examples/chain3_lab.toml")
    truth = {"k1": 1100.0, "k2": 950.0, "k3": 1000.0}
    channels = {"d1": ChannelMap("x1"), "d3": ChannelMap("x3")}
    f = np.linspace(0.5, 12.0, 60)
    measured = model_frf(model.linearize(), "F", f, channels, **truth)
    r = multi_start_update(model, {k: ("500 N/m", "2 kN/m") for k in truth}, "frf",
                           {"frequency": f, "measured": measured, "signal": "F",
                            "channels": channels}, starts=3, seed=4, engine=HERE)
    assert isinstance(r.best, FRFUpdate) and r.minima == 1 and not r.warnings
    np.testing.assert_allclose(r.ends, np.tile([1100.0, 950.0, 1000.0], (3, 1)), rtol=1e-6)
    assert len({tuple(s) for s in r.starts.tolist()}) == 3


def test_bad_requests():
    model = resonant.load("examples/chain3_damped.toml")
    with pytest.raises(ModelError, match="'shape' is not one of modes, frf"):
        multi_start_update(model, {"k": (500, 2000)}, "shape", {}, engine=HERE)
    with pytest.raises(ModelError, match="starts must be from 1 to"):
        multi_start_update(model, {"k": (500, 2000)}, "modes", {}, starts=0, engine=HERE)
    with pytest.raises(ModelError, match="'kk' is not a parameter"):
        multi_start_update(model, {"kk": (500, 2000)}, "modes",
                           {"target_frequency": [2.0]}, engine=HERE)


def test_cli_update_with_starts(tmp_path):
    pytest.importorskip("pyuff")
    from conftest import run_cli
    from resonant.model.measured import MeasuredData, MeasuredFunction, write_uff

    model = resonant.load("examples/chain3_lab.toml")
    f = np.linspace(0.5, 12.0, 40)
    measured = model_frf(model.linearize(), "F", f, {"d3": ChannelMap("x3")}, k1=1100.0)
    path = tmp_path / "frf.uff"
    write_uff(path, MeasuredData("frf.uff", (MeasuredFunction(
        "d3", "frf", f, measured["d3"], "Hz", "m/N", (3, 3), (3, 3)),)))
    toml = tmp_path / "chain.toml"
    toml.write_text(open("examples/chain3_lab.toml").read().replace(
        'd1 = "x1"\nd2 = "x2"\n', ""))
    status, out, err = run_cli(["update", toml, path, "--fit", "frf", "--vary",
                                "k1=500 N/m:2 kN/m", "--starts", "2", "--workers", "0",
                                "--json"])
    assert status == 0, err
    result = json.loads(out)
    assert len(result["costs"]) == 2 and result["minima"] == 1
    assert result["best"]["parameters"]["k1"]["fitted"] == pytest.approx(1100.0, rel=1e-5)
