"""Fuzzing the loader and the command line with mutated examples.

A short, deterministic CI run of the mutation fuzzer in ``fuzz/run_fuzz.py``
(hypothesis chooses the seeds, so a failure shrinks to one seed and is replayed):
every mutant of an example must end with exit 0, 2 or 3 and a message -- never an
internal error (exit 1), a traceback, NaN in the JSON or a hang.  The long run and
its statistics are in docs/fuzzing.md.
"""

from __future__ import annotations

import random
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import EXAMPLES, run_cli, without_units

sys.path.insert(0, str(Path(__file__).parents[1] / "fuzz"))
import run_fuzz  # noqa: E402

#: per input: the derivation budget (--timeout) and the hang detector above it
DERIVATION_BUDGET = 2.0
HANG_BUDGET = 8.0


@settings(max_examples=300, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(min_value=0, max_value=2**32 - 1))
def test_mutated_examples_never_crash_or_hang(seed, tmp_path_factory):
    workdir = tmp_path_factory.mktemp("fuzz")
    example, kind, command, status, bug, err = run_fuzz.fuzz_one(
        random.Random(seed), workdir, HANG_BUDGET, DERIVATION_BUDGET)
    assert bug is None, f"{example} mutated by {kind}, resonant {command}: {bug}\n{err}"


@pytest.mark.parametrize("kind", sorted(run_fuzz.MUTATORS))
def test_each_mutator_changes_the_text(kind):
    rng = random.Random(3)
    text = (EXAMPLES / "cart_pendulum.toml").read_text()
    assert any(run_fuzz.MUTATORS[kind](text, rng) != text for _ in range(5))


def test_the_toml_writer_round_trips_every_example():
    import tomllib

    for path in sorted(EXAMPLES.glob("*.toml")):
        data = tomllib.loads(path.read_text())
        assert tomllib.loads(run_fuzz.dump_toml(data)) == data, path.name


def test_verdict_flags_each_kind_of_bug():
    assert run_fuzz.verdict("hang", "", "", False) == "hang"
    assert run_fuzz.verdict(1, "", "internal error", False) == "exit status 1"
    assert run_fuzz.verdict(2, "", "Traceback (most recent call last)", False) == "traceback"
    assert run_fuzz.verdict(3, "", "", False) == "failure without a message"
    assert run_fuzz.verdict(0, '{"a": NaN}', "", True).startswith("bad JSON")
    assert run_fuzz.verdict(0, '{"a": 1}', "", True) is None
    assert run_fuzz.verdict(2, "", "error: x", False) is None


def test_run_one_detects_a_hang(monkeypatch):
    import resonant.cli

    def spin(argv):
        while True:
            pass
    monkeypatch.setattr(resonant.cli, "main", spin)
    status, _, _ = run_fuzz.run_one(["solve", "x.toml"], 0.2)
    assert status == "hang"


# -- regressions: the bugs the fuzzer found (docs/fuzzing.md) -------------------------------

# the examples give units; these regressions are about the numbers, in SI
ROTATING = without_units((EXAMPLES / "rotating_unbalance.toml").read_text())
CART = without_units((EXAMPLES / "cart_pendulum.toml").read_text())
PENDULUM = without_units((EXAMPLES / "pendulum.toml").read_text())


@pytest.mark.parametrize("name, text, words", [
    # log(0) in an output made a zoo coefficient that lambdify could not compile (KeyError)
    ("zoo-output", ROTATING.replace('F_T = "k*x + c*x\'"', 'F_T = "log((k*x + c*x\')^3)"'),
     ("not finite",)),
    # a huge power overflowed Python float arithmetic in the compiled code (OverflowError)
    ("float-overflow", CART.replace('U = "k*(x1 - r)^2/2 - m2*g*l/2*cos(phi)"',
                                    'U = "(k*(x1 - r)^2/2 - m2*g*l/2*cos(phi))^999"')
     .replace("m2 = 1", 'm2 = "cos(1)"'), ("not finite",)),
    # an overflow while checking the equilibrium (mpmath OverflowError)
    ("equilibrium-overflow", CART.replace('D = "0"', 'D = "0"\nV = "0"').replace(
        '\nV = "0"', "").replace('U = "k*(x1 - r)^2/2', 'U = "exp(exp(exp(exp(x1 + 10)))) + k*(x1 - r)^2/2'),
     ("overflowed",)),
    # a signal that enters only at second order left Q empty, and the numeric
    # evaluation misaligned its values (ValueError: cannot reshape)
    ("empty-excitation", PENDULUM.replace(
        'T = "m/2*((s\' + l*cos(theta)*theta\')^2 + (l*sin(theta)*theta\')^2)"',
        'T = "(m/2*((s\' + l*cos(theta)*theta\')^2 + (l*sin(theta)*theta\')^2))^2"'),
     ("mass matrix M is singular",)),
    # M^-1 K overflowed to infinity in the state matrix (LinAlgError)
    ("state-matrix-overflow", CART.replace("m1 = 2", "m1 = 1e-299").replace("m2 = 1", "m2 = 1e-299")
     .replace("k = 100", "k = 1e299"), ("not finite",)),
])
def test_found_bugs_stay_fixed(name, text, words, tmp_path):
    assert text not in (ROTATING, CART, PENDULUM), \
        "the regression input no longer applies"
    path = tmp_path / "model.toml"
    path.write_text(text)
    code, out, err = run_cli(["solve", str(path), "--json"])
    assert code in (2, 3), f"{name}: {code} {err}"
    assert "internal error" not in err
    for word in words:
        assert word in err, err


# -- hostile [matrices] files and special files (fuzz/matrix_fuzz.py) ------------------------

import matrix_fuzz  # noqa: E402

#: the known scipy crash (fuzz/crashes/mtx-integer-no-final-newline-sigsegv): an integer
#: Matrix Market file whose last entry has a fraction and no final newline
SCIPY_MTX_SEGV = b"%%MatrixMarket matrix coordinate integer general\n3 3 1\n2 1 1.5"


@pytest.mark.parametrize("seed", range(40))
def test_hostile_matrix_files_never_crash_hang_or_blow_up(seed, tmp_path):
    result = matrix_fuzz.fuzz_case(random.Random(seed), tmp_path / "case", budget=20.0)
    assert result["bug"] is None, \
        f"{result['kind']}, resonant {result['command']}: {result['bug']}\n{result['stderr']}"


def test_the_matrix_sample_covers_every_generator(tmp_path):
    kinds = {matrix_fuzz.make_case(random.Random(seed), tmp_path / str(seed))[0].split("+")[0]
             for seed in range(40)}
    assert kinds == set(matrix_fuzz.GENERATORS)


def test_special_cases_make_fifos_links_and_escapes(tmp_path):
    import stat

    seen = set()
    for seed in range(200):
        folder = tmp_path / str(seed)
        rng = random.Random(seed)
        folder.mkdir()
        value = matrix_fuzz._special(rng, folder)
        entry = folder / value if value.startswith("K.") and len(value) == 5 else None
        if entry is not None and entry.is_symlink():
            seen.add("link")
        elif entry is not None and entry.exists() and stat.S_ISFIFO(entry.lstat().st_mode):
            seen.add("fifo")
        elif value.startswith("/") or ".." in value:
            seen.add("escape")
    assert seen == {"link", "fifo", "escape"}


def _forked(monkeypatch, body, **kwargs):
    import resonant.cli

    monkeypatch.setattr(resonant.cli, "main", body)
    return matrix_fuzz.run_forked(["solve", "x.toml"], **kwargs)


def test_the_forked_runner_sees_a_signal_a_hang_and_memory(monkeypatch):
    import os
    import signal

    status, *_ = _forked(monkeypatch, lambda argv: os.kill(os.getpid(), signal.SIGSEGV),
                         budget=10)
    assert status == "signal SIGSEGV"
    assert matrix_fuzz.verdict(status, "", "", 0) == "signal SIGSEGV"

    def spin(argv):
        while True:
            pass
    status, *_ = _forked(monkeypatch, spin, budget=0.5)
    assert status == "hang"

    def allocate(argv):  # beyond RLIMIT_AS: a MemoryError, not a dead machine
        return len(bytearray(3 * 2**30))
    status, out, err, _, _ = _forked(monkeypatch, allocate, budget=10)
    assert matrix_fuzz.verdict(status, out, err, 0) in ("exit status 1", "MemoryError")

    def touch(argv):  # 300 MiB really used: peak RSS over a 200 MiB bound
        block = bytearray(300 * 2**20)
        block[::4096] = b"x" * len(block[::4096])
        return 0
    status, out, err, _, rss = _forked(monkeypatch, touch, budget=10)
    assert status == 0 and rss > 300 * 2**20
    assert matrix_fuzz.verdict(status, out, err, rss, 200 * 2**20).startswith("peak RSS")


def test_matrix_verdict():
    assert matrix_fuzz.verdict(2, "", "error: bad file", 10) is None
    assert matrix_fuzz.verdict(0, "{}", "", 10) is None
    assert matrix_fuzz.verdict(1, "", "internal error", 10) == "exit status 1"
    assert matrix_fuzz.verdict(2, "", "internal error: x", 10) == "internal error"
    assert matrix_fuzz.verdict(2, "", "Traceback (most", 10) == "traceback"
    assert matrix_fuzz.verdict(2, "", "", 10) == "failure without a message"
    assert matrix_fuzz.verdict("hang", "", "", 10) == "hang"


def test_known_scipy_mtx_segfault_is_survived(tmp_path):
    """scipy.io.mmread (fast_matrix_market, scipy 1.17.1) segfaults on this file (an
    `integer` file whose last entry has a fraction and no final newline); resonant hands
    scipy a newline-terminated `real` copy, so the file is simply read."""
    (tmp_path / "K.mtx").write_bytes(SCIPY_MTX_SEGV)
    (tmp_path / "model.toml").write_text(matrix_fuzz._model('"K.mtx"'))
    status, out, err, _, rss = matrix_fuzz.run_forked(
        ["solve", str(tmp_path / "model.toml")], budget=20)
    assert matrix_fuzz.verdict(status, out, err, rss) is None and status in (0, 2), (status, err)
