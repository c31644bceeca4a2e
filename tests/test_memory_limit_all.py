"""Every analysis under a 2 GiB address-space limit, on models that make the naive size
explode: each command finishes or refuses with exit 3 naming the size or the limit (never
an internal MemoryError, a traceback, a kill or a hang).

Each command runs through the CLI in a subprocess (``test_memory_budget.run_limited``)
with a timeout; the models are written once per module.

The big chain is a sparse Rayleigh-damped chain of 20,000 coordinates
(``test_memory_budget.sparse_chain_model``) with ``[random] lines = 1000000``, a
``[shock]`` of 400 s total (4 10^6 samples) and a harmonic load at its last mass:

- ``resonant simulate chain.toml --duration 1000``: refused (exit 3, dense M, C and K);
- ``resonant modes chain.toml``: finishes (the lowest modes of the sparse matrices);
- ``resonant energies chain.toml``: finishes;
- ``resonant random chain.toml``: refused (exit 3, the responses kept at every line),
  before any reduced model is built for them;
- ``resonant srs chain.toml``: the SRS of the pulse finishes in seconds (it took 85 s:
  the oscillators were stepped through the 400 s of zeros after the 10 ms pulse, whose
  response is the free vibration found exactly);
- ``resonant srs chain.toml --largest`` (and likewise ``--output q1``, by the same
  check): refused (exit 3, the dense form of the 20,000 x 20,000 matrices the exact
  transient needs);
- ``resonant sweep chain.toml --points 100000 --only`` (2,000 names): refused (exit 3,
  the results kept) before any solve;
- ``resonant sweep chain.toml --points 100000`` (the loaded coordinate): bounded by
  ``--timeout`` (exit 3 naming the limit; about 1 ms a point, 120 s at the default);
- ``resonant report chain.toml`` and ``resonant explore chain.toml``: refused (exit 3,
  above 4,000 coordinates) in seconds.

A chain of 600 coordinates with one ``[[nonlinear]]`` cubic element at its last mass
(above ``condensed.EXACT_SIZE``, so its linear part is a reduced model):

- ``resonant sweep chain.toml --nonlinear``: finishes.  (On the 20,000-coordinate chain
  it is bounded by ``--timeout``: its linear part's modes are computed under the
  deadline, checked at every Lanczos step, and the reduced model's evaluation at every
  chunk of frequencies.)

A chain of 60 coordinates with a ``[shock]`` of 3 10^6 samples (samples x states of its
state space would be 2.7 GiB):

- ``resonant srs chain.toml --largest``: refused (exit 3, the histories of all 60
  coordinates, 1.39 GiB) before it steps;
- ``resonant srs chain.toml --output q1``: finishes within its time limit and the memory
  (one history kept, the states a block of samples at a time);
- ``resonant report chain.toml``: finishes, its shock section saying why the shock
  response cannot be computed (the same size);
- ``resonant study chain.toml --quantity srs:q1@100`` under ``RESONANT_MEMORY=64M``: each
  sample fails with the size as its reason (status ``failed``), the study finishes.

Not covered: a ``[shock]`` with huge durations (refused at load, exit 2, by the model's
own check).
"""

from __future__ import annotations

import csv
import resource
from pathlib import Path

import pytest

from test_memory_budget import run_limited, sparse_chain_model

N = 20_000
SECTIONS = ("[parameters]\nomega = 1\n"
            '[[harmonic]]\nomega = "omega"\nF_C = "load.npy"\n'
            "[random]\nband = [0.1, 20]\nlines = 1000000\n"
            '[random.psd.W]\nvalues = 1\nload = "load.npy"\n'
            f'[shock]\nsignal = "q{N}"\npulse = "half-sine"\n'
            "amplitude = 1\nduration = 0.01\nstep = 1e-4\ntotal = 400\n")
#: the nonlinear chain's size and its element
NONLINEAR = 600
ELEMENT = (f'[parameters]\nomega = 1\n[[harmonic]]\nomega = "omega"\nF_C = "load.npy"\n'
           f'[[nonlinear]]\nname = "mount"\ncoordinates = ["q{NONLINEAR}"]\n'
           f'force = "1e4*q{NONLINEAR}^3"\n')
#: the shocked chain: a 10 ms half-sine at 1e-5 s over 30 s, 3 10^6 samples
SHOCKED = 60
SHOCK = ('[parameters]\np = 1\n[shock]\nsignal = "q60"\npulse = "half-sine"\namplitude = 1\n'
         "duration = 0.01\nstep = 1e-5\ntotal = 30\n")
SWEEP = ["--param", "omega", "--from", "0.1", "--to", "100", "--points", "100000"]


@pytest.fixture(scope="module")
def chain(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return sparse_chain_model(tmp_path_factory.mktemp("chain"), N, SECTIONS)


@pytest.fixture(scope="module")
def nonlinear(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return sparse_chain_model(tmp_path_factory.mktemp("nonlinear"), NONLINEAR, ELEMENT)


@pytest.fixture(scope="module")
def shocked(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return sparse_chain_model(tmp_path_factory.mktemp("shocked"), SHOCKED, SHOCK)


def clean(code: int, err: str) -> None:
    assert "internal error" not in err and "Traceback" not in err, err
    assert "MemoryError" not in err, err
    assert code in (0, 3), (code, err)


def test_simulate_is_refused_with_the_size(chain: Path) -> None:
    code, _, err = run_limited(["simulate", chain, "--duration", "1000"], timeout=25)
    assert code == 3 and f"dense M, C and K of {N} coordinates" in err, err


@pytest.mark.parametrize("command", ["modes", "energies"])
def test_sparse_analyses_finish(chain: Path, command: str) -> None:
    code, _, err = run_limited([command, chain], timeout=25)
    clean(code, err)
    assert code == 0, err


def test_random_with_a_million_lines_is_refused(chain: Path) -> None:
    code, _, err = run_limited(["random", chain], timeout=25)
    clean(code, err)
    assert code == 3 and "lines" in err, err


def test_the_srs_of_a_long_quiet_pulse_record_is_quick(chain: Path) -> None:
    """The 10 ms pulse in a 400 s record: the free vibration after it is exact, so the
    4 10^6 samples of zeros are not stepped through (85 s before, now under 5)."""
    code, out, err = run_limited(["srs", chain], timeout=20)
    clean(code, err)
    assert code == 0 and "signal 400 s" in out, err


def test_the_srs_of_the_responses_is_refused_with_the_size(chain: Path) -> None:
    code, _, err = run_limited(["srs", chain, "--largest"], timeout=20)
    clean(code, err)
    assert code == 3 and f"dense form of a {N} x {N} sparse matrix" in err, err


def test_a_sweep_keeping_many_coordinates_at_many_points_is_refused(chain: Path) -> None:
    names = ",".join(f"q{i}" for i in range(1, 2001))
    code, _, err = run_limited(["sweep", chain, *SWEEP, "--only", names], timeout=20)
    clean(code, err)
    assert code == 3 and "100000 values x 2000 reported quantities" in err, err


def test_a_sweep_of_many_points_is_bounded_by_its_time_limit(chain: Path) -> None:
    """One coordinate kept at 10^5 points is 1.6 MB: the bound is the time (about 1 ms a
    banded solve), reached with exit 3, not the memory."""
    code, _, err = run_limited(["sweep", chain, *SWEEP, "--timeout", "2"], timeout=20)
    clean(code, err)
    assert code == 3 and "exceeded the time limit of 2 s" in err, err


@pytest.mark.parametrize("command", ["report", "explore"])
def test_report_and_explore_are_refused_above_their_size(chain: Path, tmp_path: Path,
                                                         command: str) -> None:
    code, _, err = run_limited([command, chain, "-o", tmp_path / "page.html"], timeout=20)
    clean(code, err)
    assert code == 3 and f"{N} coordinates" in err and "limited to 4000" in err, err
    assert not (tmp_path / "page.html").exists()


def test_the_nonlinear_sweep_finishes(nonlinear: Path) -> None:
    code, out, err = run_limited(["sweep", nonlinear, "--nonlinear", "--param", "omega",
                                  "--from", "0.1", "--to", "1", "--points", "5"], timeout=20)
    clean(code, err)
    assert code == 0 and "peak of the stable branch" in out, err


def test_every_history_of_a_long_shock_is_refused_before_stepping(shocked: Path) -> None:
    code, _, err = run_limited(["srs", shocked, "--largest"], timeout=20)
    clean(code, err)
    assert code == 3 and "3000001 samples x 60 coordinates" in err, err
    assert "1.39 GiB" in err and "fewer names" in err, err


def test_the_srs_of_one_response_to_a_long_shock_is_bounded(shocked: Path) -> None:
    """One history kept (24 MB), the states a block of samples at a time, within the
    memory budget: the command takes under 2 s of CPU (15 s when the transient was
    stepped one sample at a time, 2026-12-03; CPU time, which a loaded machine stretches
    less than the wall time)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    code, out, err = run_limited(["srs", shocked, "--output", "q1", "--points", "2",
                                  "--timeout", "0"], timeout=180)
    cpu = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before
    clean(code, err)
    assert code == 0 and "maximax" in out, err
    assert cpu < 6, cpu


def test_the_report_of_a_long_shock_says_why_it_has_no_response(shocked: Path,
                                                                tmp_path: Path) -> None:
    page = tmp_path / "report.html"
    code, _, err = run_limited(["report", shocked, "-o", page], timeout=25)
    clean(code, err)
    assert code == 0, err
    text = page.read_text()
    assert "The shock response cannot be computed" in text
    assert "3000001 samples x 60 coordinates" in text


def test_a_study_of_a_long_shock_s_srs_fails_each_sample_with_the_size(shocked: Path,
                                                                       tmp_path: Path
                                                                       ) -> None:
    table = tmp_path / "study.csv"
    code, _, err = run_limited(["study", shocked, "--vary", "p=uniform(1, 2)", "--quantity",
                                "srs:q1@100", "--samples", "2", "-o", table], timeout=25,
                               env={"RESONANT_MEMORY": "64M"})
    clean(code, err)
    rows = list(csv.DictReader(table.open()))
    assert len(rows) == 2 and all(row["status"] == "failed" for row in rows), rows
    assert all("3000001 samples x 1 coordinates" in row["reason"] for row in rows), rows
