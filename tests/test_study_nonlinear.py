"""The nonlinear steady-state amplitude as a study quantity (``nonlinear_amplitude:NAME``,
docs/studies.md) and the slow upward sweep behind it (resonant.analyses.slow_sweep).

References: Duffing's equation m x'' + c x' + k x + k3 x^3 = F cos(w t) with one harmonic,
X cos(w t + phi), satisfies [(k - m w^2 + 3/4 k3 X^2)^2 + (c w)^2] X^2 = F^2 (Nayfeh & Mook,
Nonlinear Oscillations, 1979, Sect. 4.1.1).  Harmonic balance with H = 1 solves exactly
this relation, so its amplitude equals the relation's root to the Newton tolerance (1e-11
relative; asserted to 1e-9).  A slow upward sweep stays on the branch it is on while that
exists and is stable: for a hardening spring (k3 > 0) the largest root up to the fold
where the resonant branch ends, the only root beyond; for a softening spring (k3 < 0) the
smallest root up to the fold of the lower branch, then (after the jump up) the only root.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import run_json

import resonant
from resonant.analyses import slow_sweep
from resonant.analyses.harmonic_balance import nonlinear_sweep
from resonant.analyses.slow_sweep import NotConverged, swept_state
from resonant.errors import AnalysisError, ModelError
from resonant.studies import StudyJob, collect, engine_for, read_table, request, run_study
from resonant.studies.designs import NONLINEAR_CHUNK
from resonant.system import nonlinear_at, nonlinear_system

pytest.importorskip("pandas")
pytest.importorskip("pyarrow")

ROOT = Path(__file__).resolve().parents[1]
DUFFING = ROOT / "examples" / "duffing.toml"
BAND = {"parameter": "omega", "from": 0.5, "to": 2.5}


def duffing_roots(w: float, m: float, c: float, k: float, k3: float, F: float) -> np.ndarray:
    """The amplitudes X > 0 of the one-harmonic relation, ascending (a cubic in X^2)."""
    a = k - m * w * w
    r = np.roots([9 / 16 * k3 ** 2, 1.5 * k3 * a, a * a + (c * w) ** 2, -F ** 2])
    return np.sqrt(np.sort(r[(np.abs(r.imag) < 1e-9) & (r.real > 0)].real))


@pytest.fixture(scope="module")
def duffing():
    return nonlinear_system(resonant.load(DUFFING))


def at(system, **values):
    return nonlinear_at(system, {**dict(zip(system.parameters, system.parameter_values)),
                                 **values})


# -- the slow sweep against the closed form ----------------------------------------------------

@pytest.mark.parametrize("w", [0.8, 1.1, 1.25, 1.34])
def test_hardening_sweep_up_stays_on_the_resonant_branch(duffing, w):
    """m = 1, c = 0.1, k = 1, k3 = 0.5, F = 0.2 (examples/duffing.toml): three roots from
    w = 1.20 to the fold at 1.3516; the sweep up has the largest."""
    state = swept_state(duffing, "omega", 0.5, w, harmonics=1)
    expected = duffing_roots(w, 1, 0.1, 1, 0.5, 0.2)[-1]
    assert state.amplitudes["x"] == pytest.approx(expected, rel=1e-9)
    assert state.jumps == ()


@pytest.mark.parametrize("w, jumped", [(0.8, False), (0.9, False), (0.95, True), (1.1, True)])
def test_softening_sweep_up_jumps_up_at_the_fold_of_the_lower_branch(duffing, w, jumped):
    """c = 0.05, k3 = -0.1, F = 0.1: three roots up to w = 0.916; the sweep up keeps the
    smallest there, and after the jump (time integration) lands on the only root."""
    system = at(duffing, c=0.05, k3=-0.1, F=0.1, omega=w)
    state = swept_state(system, "omega", 0.3, w, harmonics=1)
    roots = duffing_roots(w, 1, 0.05, 1, -0.1, 0.1)
    assert len(roots) == (1 if jumped else 3)
    assert state.amplitudes["x"] == pytest.approx(roots[0], rel=1e-9)
    assert bool(state.jumps) == jumped
    if jumped:
        assert state.jumps[0][0] == pytest.approx(0.91543, abs=1e-4)


@pytest.mark.parametrize("w", [1.5, 2.0])
def test_hardening_sweep_up_jumps_down_beyond_the_fold(duffing, w):
    """Beyond the fold only the lower branch is left.  H = 7: the one-harmonic relation
    holds up to the third harmonic, a_3 ~ k3 X^3 / (4 (9 m w^2 - k)) (Nayfeh & Mook,
    Sect. 4.1; 2.7e-5 of X = 0.16 at w = 1.5); asserted within 1.5 a_3."""
    state = swept_state(duffing, "omega", 0.5, w, harmonics=7)
    assert len(state.jumps) == 1 and 1.35 < state.jumps[0][0] < 1.36
    roots = duffing_roots(w, 1, 0.1, 1, 0.5, 0.2)
    assert len(roots) == 1
    third = 0.5 * roots[0] ** 3 / (4 * (9 * w * w - 1))
    assert abs(state.amplitudes["x"] - roots[0]) <= 1.5 * third


def test_one_harmonic_past_its_fold_is_not_converged(duffing):
    """With H = 1 the fold comes before the true one (1.3516 < 1.3543): the full equations
    stay on the resonant branch where H = 1 has none -- said, not guessed."""
    with pytest.raises(NotConverged, match="raise the harmonics"):
        swept_state(duffing, "omega", 0.5, 1.5, harmonics=1)


# -- two routes: the sweep command at the same point ------------------------------------------

@pytest.mark.parametrize("start, w", [(0.5, 1.3), (1.6, 2.0)])
def test_equals_sweep_nonlinear_at_the_same_point(duffing, start, w):
    """``resonant sweep --nonlinear`` from ``start`` to w ends exactly at w; from 0.5 the
    slow sweep reaches 2.0 on the lower branch after a jump, which a sweep started at 1.6
    (beyond the fold) follows from the start."""
    data = run_json("sweep", DUFFING, "--param", "omega", "--from", str(start), "--to",
                    str(w), "--nonlinear", "--harmonics", "7")
    last = data["branch"][-1]
    assert last["value"] == w
    state = swept_state(duffing, "omega", 0.5, w, harmonics=7)
    assert state.amplitudes["x"] == pytest.approx(last["amplitudes"]["x"], rel=1e-9)


def test_default_harmonics_as_sweep_nonlinear(duffing):
    """Without harmonics H is raised at the point until the highest carry < 1e-6."""
    state = swept_state(duffing, "omega", 0.5, 1.3)
    assert state.harmonics >= 7 and state.truncation <= 1e-6
    reference = nonlinear_sweep(duffing, "omega", 0.5, 1.3, harmonics=state.harmonics,
                                linear=False)
    assert state.amplitudes["x"] == pytest.approx(reference.amplitudes["x"][-1], rel=1e-9)


def test_swept_state_checks_its_arguments(duffing):
    with pytest.raises(AnalysisError, match="start <= value"):
        swept_state(duffing, "omega", 1.0, 0.5)
    with pytest.raises(AnalysisError, match="not a parameter"):
        swept_state(duffing, "nope", 0.5, 1.0)
    with pytest.raises(AnalysisError, match="harmonics must be"):
        swept_state(duffing, "omega", 0.5, 1.0, harmonics=0)


def test_nonlinear_at_changes_the_numbers_not_the_equations(duffing):
    system = at(duffing, k3=2.0)
    assert system.parameter_point("omega", 1.5)[duffing.parameters.index("k3")] == 2.0
    assert nonlinear_at(system, dict(zip(duffing.parameters, duffing.parameter_values))) \
        .parameter_values.tolist() == duffing.parameter_values.tolist()


# -- the study quantity -------------------------------------------------------------------------

def _job(samples: int = 8, **options) -> StudyJob:
    model = resonant.load(DUFFING)
    options = {"band": BAND, "harmonics": 7, **options}
    spec = request(model, {"omega": "uniform(0.8, 2.0)", "k3": "uniform(0.3, 0.7)"},
                   ["nonlinear_amplitude:x", "amplitude:x"], samples=samples, seed=3,
                   **options)
    return StudyJob.of(model, spec)


def test_study_rows_equal_the_slow_sweep_and_the_closed_form(duffing):
    """Each row equals swept_state at its sample, and the one-harmonic relation's root
    the sweep up reaches, within 1.5 times the third harmonic (as above)."""
    table = collect(_job(), engine_for(0)).table
    assert (table["status"] == "ok").all()
    for row in table.itertuples():
        state = swept_state(at(duffing, omega=row.omega, k3=row.k3), "omega", 0.5,
                            row.omega, harmonics=7)
        value = getattr(row, "_4")  # nonlinear_amplitude:x
        assert value == state.amplitudes["x"]
        roots = duffing_roots(row.omega, 1, 0.1, 1, row.k3, 0.2)
        expected = roots[-1] if not state.jumps else roots[0]
        third = row.k3 * expected ** 3 / (4 * (9 * row.omega ** 2 - 1))
        assert abs(value - expected) <= 1.5 * third


def test_study_statuses_of_the_nonlinear_steady_state(tmp_path):
    model = resonant.load(DUFFING)
    spec = request(model, {"omega": [0.3, 1.3, 1.5]}, ["nonlinear_amplitude:x"],
                   design="grid", band={"parameter": "omega", "from": 0.5, "to": 2.0},
                   harmonics=1)
    table = collect(StudyJob.of(model, spec), engine_for(0)).table
    assert table["status"].tolist() == ["failed", "ok", "not converged"]
    assert "outside the band" in table["reason"][0]
    assert "raise the harmonics" in table["reason"][2]
    assert math.isnan(table["nonlinear_amplitude:x"][2])


def test_a_motion_that_does_not_settle_is_not_periodic(monkeypatch, duffing):
    monkeypatch.setattr(slow_sweep, "SETTLED_TOL", 0.0)
    monkeypatch.setattr(slow_sweep, "MAX_PERIODS", 10)
    model = resonant.load(DUFFING)
    spec = request(model, {"omega": [1.5]}, ["nonlinear_amplitude:x"], design="grid",
                   band=BAND, harmonics=3)
    table = collect(StudyJob.of(model, spec), engine_for(0)).table
    assert table["status"].tolist() == ["not periodic"]
    assert "did not settle" in table["reason"][0]


def test_same_bytes_in_process_and_on_two_local_workers(tmp_path):
    """Two chunks of NONLINEAR_CHUNK samples: one for each worker."""
    job = _job(samples=2 * NONLINEAR_CHUNK)
    here, there = tmp_path / "here.parquet", tmp_path / "there.parquet"
    run_study(job, here, engine_for(0))
    summary = run_study(job, there, engine_for(2))
    assert summary.where == "2 local workers"
    assert here.read_bytes() == there.read_bytes()
    assert len(read_table(here)) == 2 * NONLINEAR_CHUNK


@pytest.mark.parametrize("options, message", [
    ({}, "nonlinear_amplitude: quantities need a band"),
    ({"band": BAND, "harmonics": 0}, "harmonics must be a whole number from 1 to 200"),
    ({"band": BAND, "harmonics": True}, "harmonics must be a whole number"),
])
def test_bad_nonlinear_requests_are_named(options, message):
    model = resonant.load(DUFFING)
    with pytest.raises(ModelError, match=message):
        request(model, {"k3": "uniform(0.3, 0.7)"}, ["nonlinear_amplitude:x"], **options)


def test_study_section_and_cli_harmonics(tmp_path, cli):
    path = tmp_path / "d.toml"
    path.write_text(DUFFING.read_text() + '\n[study]\nvary = { k3 = [0.4, 0.6] }\n'
                    'quantities = ["nonlinear_amplitude:x"]\ndesign = "grid"\n'
                    'band = { parameter = "omega", from = 0.5, to = 2 }\nharmonics = 5\n')
    out = tmp_path / "r.csv"
    status, stdout, err = cli(["study", str(path), "-o", str(out), "--workers", "0",
                               "--json"])
    assert status == 0, err
    data = json.loads(stdout)
    assert data["study"]["harmonics"] == 5 and data["status"] == {"ok": 2}
    status, _, err = cli(["study", str(path), "-o", str(out), "--harmonics", "999"])
    assert status == 2 and "--harmonics" in err


def test_a_matrix_model_has_no_nonlinear_steady_state(tmp_path, cli):
    path = ROOT / "examples" / "matrices" / "frame.toml"
    status, _, err = cli(["study", str(path), "-o", str(tmp_path / "r.csv"), "--vary",
                          "k=[2e5, 3e5]", "--quantity", "nonlinear_amplitude:x1", "--band",
                          "omega=1:20", "--workers", "0"])
    assert status == 3 and "energies" in err, err


def test_outputs_of_the_full_equations_and_one_that_has_none(tmp_path):
    """An output is reported as sweep --nonlinear reports it; one with a third derivative
    has no full form: its samples fail with that reason (no traceback)."""
    path = tmp_path / "d.toml"
    path.write_text(DUFFING.read_text() + "\n[outputs]\nv = \"x'\"\nj = \"x'''\"\n")
    model = resonant.load(path)
    band = {"parameter": "omega", "from": 0.5, "to": 2.0}
    good = request(model, {"omega": [1.3]}, ["nonlinear_amplitude:v"], design="grid",
                   band=band, harmonics=5)
    table = collect(StudyJob.of(model, good), engine_for(0)).table
    data = run_json("sweep", path, "--param", "omega", "--from", "0.5", "--to", "1.3",
                    "--nonlinear", "--harmonics", "5")
    assert table["nonlinear_amplitude:v"][0] == pytest.approx(
        data["branch"][-1]["amplitudes"]["v"], rel=1e-9)
    bad = request(model, {"omega": [1.3]}, ["nonlinear_amplitude:j"], design="grid",
                  band=band, harmonics=5)
    table = collect(StudyJob.of(model, bad), engine_for(0)).table
    assert table["status"][0] == "failed" and "'j'" in table["reason"][0]
