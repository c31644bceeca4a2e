"""Studies, the page and nonlinear elements under faults and hostile input.

Each case ended in an internal error (exit 1), a hang or a wrong verdict; each must end
as docs/errors.md says: exit 2 (invalid input: the model, a file, an option) or 3 (the
analysis is impossible), one message naming the file, section and key, within the time
limit.  No local Dask cluster is started here (the scheduler cases use sockets that never
answer or refuse).
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from conftest import run_cli
from resonant.errors import ModelError
from resonant.studies.engine import Engine, machine_workers, parse_scheduler
from resonant.studies.result import bootstrap_seed
from test_study import SDOF

pytest.importorskip("pandas")
pytest.importorskip("pyarrow")
pytest.importorskip("SALib")

ROOT = Path(__file__).resolve().parents[1]
SRC = str(ROOT / "src")

# the single-DOF model of tests/test_study.py (SDOF), imported above

MATRIX_NL = """
[parameters]
w = 3
[coordinates]
q1 = ""
q2 = ""
[matrices]
M = [[1, 0], [0, 1]]
K = [[2, -1], [-1, 2]]
C = [[0.1, 0], [0, 0.1]]
[[harmonic]]
omega = "w"
F_S = [1, 0]
[[nonlinear]]
name = "bad"
coordinates = ["q2"]
force = "FORCE"
"""


@pytest.fixture
def model(tmp_path: Path) -> Path:
    path = tmp_path / "sdof.toml"
    path.write_text(SDOF)
    return path


def study(model: Path, output: Path | str, *extra: str) -> tuple[int, str, str]:
    return run_cli(["study", str(model), "--vary", "k=uniform(90, 110)", "--quantity",
                    "natural_frequency:1", "--quantity", "stable", "--samples", "40",
                    "--workers", "0", "-o", str(output), *extra])


# -- 1. output paths: checked once, before any work ------------------------------------------

def test_unwritable_output_folder(model):
    code, _, err = study(model, "/proc/self/x.csv")
    assert code == 2, err
    assert err.startswith("error: /proc/self/x.csv: cannot write the study's output")


@pytest.mark.parametrize("companion", [".part", ".study.json"])
def test_output_companion_is_a_folder(model, tmp_path, companion):
    out = tmp_path / "s.csv"
    Path(str(out) + companion).mkdir()
    code, _, err = study(model, out)
    assert code == 2, err
    assert f"s.csv{companion}' is a folder" in err and err.startswith(f"error: {out}:")


def test_output_is_a_folder_for_every_writing_command(model, tmp_path):
    for command, name in (("report", "r.html"), ("explore", "p.html"), ("draw", "d.svg")):
        (tmp_path / name).mkdir()
        code, _, err = run_cli([command, str(model), "-o", str(tmp_path / name)])
        assert code == 2, (command, err)
        assert f"{tmp_path / name}: cannot write" in err and "it is a folder" in err


# -- 1. --resume reads its files back as untrusted input ----------------------------------

@pytest.fixture
def finished(model, tmp_path):
    """A finished study of 40 rows in CSV and Parquet."""
    paths = {}
    for ending in ("csv", "parquet"):
        out = tmp_path / f"s.{ending}"
        code, _, err = study(model, out)
        assert code == 0, err
        paths[ending] = out
    return paths


def test_resume_of_an_intact_file_keeps_its_bytes(model, finished):
    for out in finished.values():
        before = out.read_bytes()
        code, _, err = study(model, out, "--resume")
        assert code == 0, err
        assert out.read_bytes() == before


def test_resume_csv_with_an_edited_value(model, finished):
    out = finished["csv"]
    lines = out.read_text().splitlines()
    lines[5] = "4,abc,def,ok,"
    out.write_text("\n".join(lines) + "\n")
    code, _, err = study(model, out, "--resume")
    assert code == 2, err
    assert err.startswith(f"error: {out}: cannot resume from this file: column 'k' holds "
                          "'abc' in row 5, not a number")


def test_resume_csv_with_a_huge_whole_number(model, finished):
    """Found by fuzz/study_fuzz.py: 400 nines, which pandas reads as a Python int."""
    out = finished["csv"]
    lines = out.read_text().splitlines()
    lines[3] = "9" * 400 + lines[3][1:]
    out.write_text("\n".join(lines) + "\n")
    code, _, err = study(model, out, "--resume")
    assert code == 2 and "column 'sample' holds '999" in err, err


def test_resume_csv_with_an_edited_header(model, finished):
    out = finished["csv"]
    lines = out.read_text().splitlines()
    lines[0] = lines[0].replace("natural_frequency:1", "x")
    out.write_text("\n".join(lines) + "\n")
    code, _, err = study(model, out, "--resume")
    assert code == 2 and "its header is 'sample,k,x,stable,status,reason'" in err, err


def test_resume_csv_without_its_description(model, finished):
    out = finished["csv"]
    Path(str(out) + ".study.json").unlink()
    code, _, err = study(model, out, "--resume")
    assert code == 2 and "its study description 's.csv.study.json' is missing" in err, err


def test_resume_parquet_with_damaged_pages(model, finished):
    out = finished["parquet"]
    data = bytearray(out.read_bytes())
    data[8:400] = b"\xab" * 392  # the data pages; the footer (schema, metadata) is intact
    out.write_bytes(bytes(data))
    code, _, err = study(model, out, "--resume")
    assert code == 2, err
    assert err.startswith(f"error: {out}: cannot resume from this file: its rows cannot be "
                          "read (damaged or truncated)")


def test_resume_truncated_parquet_is_not_called_another_study(model, finished):
    out = finished["parquet"]
    out.write_bytes(out.read_bytes()[:1000])
    code, _, err = study(model, out, "--resume")
    assert code == 2 and "not a readable Parquet file" in err and "different" not in err, err


def test_resume_of_another_study_names_the_file(model, finished):
    out = finished["parquet"]
    code, _, err = run_cli(["study", str(model), "--vary", "k=uniform(80, 110)", "--quantity",
                            "stable", "--samples", "40", "--workers", "0", "-o", str(out),
                            "--resume"])
    assert code == 2 and err.startswith(f"error: {out}: the file holds a different study"), err


# -- 1. the scheduler's address is parsed by us ------------------------------------------

@pytest.mark.parametrize("address", ["tcp://[::1", "tcp://host", "tcp://h:99999",
                                     "http://h:1", "tcp://h:1/x", "tcp://:1"])
def test_bad_scheduler_addresses(model, tmp_path, address):
    with pytest.raises(ModelError, match="scheduler '"):
        parse_scheduler(address)
    code, _, err = run_cli(["study", str(model), "--vary", "k=uniform(90, 110)", "--quantity",
                            "stable", "-o", str(tmp_path / "s.csv"), "--scheduler", address])
    assert code == 2 and err.startswith(f"error: scheduler '{address}'"), err
    code, _, err = run_cli(["exercise", str(model), "--variants", "2", "-o",
                            str(tmp_path / "ex"), "--scheduler", address])
    assert code == 2 and err.startswith(f"error: scheduler '{address}'"), err


def test_good_scheduler_addresses():
    for address in ("tcp://127.0.0.1:8786", "tcp://[::1]:8786", "tls://a.b:1", "inproc://x"):
        assert parse_scheduler(address) == address


# -- 1. non-finite element forces ---------------------------------------------------------

@pytest.mark.parametrize("force", ["1/0*q2", "0/0 + q2^3", "q2/(1 - 1)", "log(0) + q2"])
def test_non_finite_element_force(tmp_path, force):
    path = tmp_path / "nl.toml"
    path.write_text(MATRIX_NL.replace("FORCE", force))
    for args in (["check"], ["sweep", "--nonlinear", "--param", "w", "--from", "1", "--to",
                             "3", "--points", "5"]):
        code, _, err = run_cli([args[0], str(path), *args[1:]])
        assert code == 2, err
        assert err.startswith(f"error: {path}: [nonlinear 'bad'] force: the expression is not "
                              "finite"), err


# -- 1. the page's size bound, decided before anything is derived ---------------------------

def test_explore_of_a_huge_energy_model_is_refused_quickly(tmp_path):
    n = 2000
    names = [f"a{i}" for i in range(1, n + 1)]
    text = ("[parameters]\nm = 1\nk = 100\nF0 = 1\nomega = 5\n[coordinates]\n"
            + "".join(f'{q} = ""\n' for q in names)
            + '[signals]\nF = "F0*sin(omega*t)"\n[energy]\n'
            + 'T = "m*(' + "+".join(f"{q}'^2" for q in names) + ')/2"\n'
            + 'U = "k*(' + "+".join(f"{q}^2" for q in names) + ')/2"\n'
            + f'[[force]]\ngeneralized = {{ a{n} = "F" }}\n')
    path = tmp_path / "chain.toml"
    path.write_text(text)
    start = time.perf_counter()
    code, _, err = run_cli(["explore", str(path), "-o", str(tmp_path / "c.html")])
    assert code == 2, err
    assert "2000 coordinates are more than the explore page shows" in err
    assert "[coordinates]" in err and not (tmp_path / "c.html").exists()
    assert time.perf_counter() - start < 30


# -- 2. --timeout bounds connecting to a scheduler ----------------------------------------

@pytest.fixture
def silent_scheduler():
    """A socket on 127.0.0.1 that accepts connections and never answers."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    held: list[socket.socket] = []
    stop = threading.Event()

    def accept() -> None:
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                held.append(server.accept()[0])
            except OSError:
                continue

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    stop.set()
    thread.join()
    for s in held:
        s.close()
    server.close()


def closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("kind", ["silent", "closed"])
def test_scheduler_that_does_not_answer_ends_within_the_limit(model, tmp_path,
                                                              silent_scheduler, kind):
    address = silent_scheduler if kind == "silent" else f"tcp://127.0.0.1:{closed_port()}"
    start = time.perf_counter()
    code, _, err = run_cli(["study", str(model), "--vary", "k=uniform(90, 110)", "--quantity",
                            "stable", "-o", str(tmp_path / "s.csv"), "--scheduler", address,
                            "--timeout", "2"])
    elapsed = time.perf_counter() - start
    assert code == 2, err
    assert err.startswith(f"error: scheduler '{address}': cannot reach the Dask scheduler: "
                          "it did not answer within the time limit of 2 s"), err
    assert elapsed < 2 + 2.5, elapsed  # the limit, plus loading the model and Dask
    assert not (tmp_path / "s.csv").exists()


# -- 2. local workers bounded by the machine -------------------------------------------------

def test_more_workers_than_the_machine_runs(model, tmp_path):
    most, cores, _ = machine_workers()
    for count in (most + 1, 1024):
        code, _, err = study(model, tmp_path / "s.csv", "--workers", str(count))
        assert code == 2, err
        assert f"{count} local workers are more than this machine runs: it has {cores} " \
               "cores" in err and f"ask for at most {most}" in err
    with pytest.raises(ModelError, match="local workers"):
        Engine(mode="local", workers=most + 1)


def test_workers_that_cannot_start_are_one_line():
    from resonant.errors import AnalysisError
    from resonant.studies.engine import _local_cluster

    def failing(**_: object) -> None:
        raise RuntimeError("Nanny failed to start.\nTraceback ...")

    with pytest.raises(AnalysisError, match=r"^3 local workers could not start \(Nanny "
                                            r"failed to start.\); ask for fewer"):
        with _local_cluster(failing, 3):
            pass


# -- 4. Sobol with failed samples or constant quantities -------------------------------------

def sobol(model: Path, out: Path, *extra: str) -> tuple[int, str, str]:
    return run_cli(["study", str(model), "--vary", "m=uniform(-1, 3)", "--vary",
                    "k=uniform(90, 110)", "--design", "sobol", "--samples", "32",
                    "--workers", "0", "-o", str(out), *extra])


def test_sobol_with_failed_samples(model, tmp_path):
    # m < 0 makes a sample unstable: no amplitude there
    args = ["--quantity", "amplitude:x", "--quantity", "natural_frequency:1"]
    code, out, err = sobol(model, tmp_path / "s.parquet", *args, "--json")
    assert code == 0, err
    found = json.loads(out)["sensitivity"]
    amplitude = found["amplitude:x"]
    assert all(v is not None and np.isfinite(v) for v in amplitude["S1"] + amplitude["ST"])
    assert amplitude["note"].startswith("from ") and "of 32 base samples" in amplitude["note"]
    code, text, err = sobol(model, tmp_path / "s.csv", *args)
    assert code == 0, err
    assert "Sobol indices of amplitude:x: m S1 " in text and "of 32 base samples" in text


def test_sobol_of_a_constant_quantity(model, tmp_path):
    code, out, err = run_cli(["study", str(model), "--vary", "k=uniform(90, 110)",
                              "--quantity", "stable", "--design", "sobol", "--samples", "16",
                              "--workers", "0", "-o", str(tmp_path / "s.csv"), "--json"])
    assert code == 0, err
    entry = json.loads(out)["sensitivity"]["stable"]
    assert entry["S1"] == [None] and entry["ST_conf"] == [None]
    assert entry["note"] == "no indices: the quantity is constant"


def test_sobol_confidence_intervals_are_reproducible(model, tmp_path):
    """SALib takes a seed of 0 for none: the bootstrap must get a seed that is not 0."""
    assert bootstrap_seed(0) != 0
    runs = []
    for k in range(2):
        code, out, err = sobol(model, tmp_path / f"s{k}.csv", "--quantity", "amplitude:x",
                               "--json")
        assert code == 0, err
        runs.append(json.loads(out)["sensitivity"])
    assert runs[0] == runs[1]


# -- 5. options ------------------------------------------------------------------------------

def test_the_same_parameter_varied_twice(model, tmp_path):
    code, _, err = run_cli(["study", str(model), "--vary", "k=uniform(90, 110)", "--vary",
                            "k=[1, 2]", "--quantity", "stable", "-o", str(tmp_path / "s.csv")])
    assert code == 2 and "names 'k' twice" in err, err


def test_study_honours_allow_path(tmp_path):
    outside, inside = tmp_path / "outside", tmp_path / "model"
    outside.mkdir()
    inside.mkdir()
    np.save(outside / "K.npy", np.diag([100.0, 200.0]))
    path = inside / "m.toml"
    path.write_text('[parameters]\nw = 3\ns = 1\n[matrices]\nM = [[1, 0], [0, 1]]\n'
                    'K = "../outside/K.npy"\n[[harmonic]]\nomega = "w"\nF_S = ["s", 0]\n')
    args = ["study", str(path), "--vary", "w=[1, 2]", "--quantity", "amplitude:q1",
            "--workers", "0", "-o", str(tmp_path / "s.csv")]
    code, _, err = run_cli(args)
    assert code == 2 and "outside" in err, err
    code, out, err = run_cli([*args, "--allow-path", str(outside)])
    assert code == 0, err


# -- 3. interrupts ---------------------------------------------------------------------------

def test_interrupt_leaves_a_resumable_file(model, tmp_path, monkeypatch):
    """An interrupt after the first chunk: one line, exit 130, the file the line names
    exists, and a resume completes it to the bytes of an uninterrupted run."""
    from resonant.studies import files

    args = ["--vary", "k=uniform(90, 110)", "--quantity", "amplitude:x", "--samples",
            "70000", "--workers", "0"]  # two chunks of at most 65,536 samples
    whole = tmp_path / "whole.csv"
    assert run_cli(["study", str(model), *args, "-o", str(whole)])[0] == 0
    write = files.ResultWriter.write

    def interrupted(self, columns):
        write(self, columns)
        raise KeyboardInterrupt

    out = tmp_path / "s.csv"
    monkeypatch.setattr(files.ResultWriter, "write", interrupted)
    code, _, err = run_cli(["study", str(model), *args, "-o", str(out)])
    assert code == 130, err
    assert err == f"the study stopped: {out} holds the samples done so far; run the same " \
                  "command with --resume to complete it\n"
    assert 0 < len(out.read_text().splitlines()) - 1 < 70000
    monkeypatch.setattr(files.ResultWriter, "write", write)
    assert run_cli(["study", str(model), *args, "-o", str(out), "--resume"])[0] == 0
    assert out.read_bytes() == whole.read_bytes()


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_interrupt_before_the_first_chunk_leaves_a_resumable_file(model, tmp_path,
                                                                  monkeypatch, suffix):
    """An interrupt before any chunk is written: the file the line names holds the study's
    description and no rows, and a resume completes it to the bytes of an uninterrupted
    run."""
    from resonant.studies import files

    args = ["--vary", "k=uniform(90, 110)", "--quantity", "amplitude:x", "--quantity",
            "stable", "--samples", "50", "--workers", "0"]
    whole = tmp_path / f"whole{suffix}"
    assert run_cli(["study", str(model), *args, "-o", str(whole)])[0] == 0
    write = files.ResultWriter.write

    def interrupted(self, columns):
        raise KeyboardInterrupt

    out = tmp_path / f"s{suffix}"
    monkeypatch.setattr(files.ResultWriter, "write", interrupted)
    code, _, err = run_cli(["study", str(model), *args, "-o", str(out)])
    assert code == 130, err
    assert err == f"the study stopped: {out} holds the study's description and no samples " \
                  "yet; run the same command with --resume to complete it\n"
    assert files.completed_rows(out) == 0
    assert files.read_description(out) == files.read_description(whole)
    monkeypatch.setattr(files.ResultWriter, "write", write)
    assert run_cli(["study", str(model), *args, "-o", str(out), "--resume"])[0] == 0
    assert out.read_bytes() == whole.read_bytes()


def test_starting_local_workers_is_bounded_by_the_time_limit():
    """A cluster that takes longer to start than the limit: the run ends at the limit."""
    from resonant.deadline import AnalysisTimeout, Deadline
    from resonant.studies.engine import _local_cluster

    started = threading.Event()

    def slow(**_: object) -> None:
        started.set()
        time.sleep(5)

    begin = time.monotonic()
    with pytest.raises(AnalysisTimeout, match=r"exceeded the time limit of 0.5 s while "
                                              r"starting 2 local workers"):
        with _local_cluster(slow, 2, Deadline(0.5)):
            pass
    assert started.is_set() and time.monotonic() - begin < 2.0


def test_timeout_while_workers_start_ends_the_study_within_it(model, tmp_path):
    """The real program: a limit shorter than starting workers and running the study ends
    it with exit 3 in one line, and leaves a file to resume."""
    out = tmp_path / "s.parquet"
    env = dict(os.environ, PYTHONPATH=SRC)
    begin = time.monotonic()
    proc = subprocess.run([sys.executable, "-m", "resonant", "study", str(model), "--vary",
                           "k=uniform(90, 110)", "--quantity", "amplitude:x", "--samples",
                           "20", "--workers", "2", "--timeout", "1", "-o", str(out)],
                          capture_output=True, text=True, env=env, timeout=60)
    assert proc.returncode == 3, proc.stderr
    # the limit passes while the workers start or while they work, as the machine goes
    assert ("while starting 2 local workers" in proc.stderr
            or "while waiting for the workers" in proc.stderr), proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert time.monotonic() - begin < 15
    from resonant.studies import files

    assert files.completed_rows(out) == 0 and files.read_description(out)["rows"] == 20


def test_sigint_to_the_program_is_one_line(model, tmp_path):
    """A real SIGINT to the program while it studies: exit 130, one line, and the file it
    names (if any) can be resumed."""
    out = tmp_path / "s.csv"
    env = dict(os.environ, PYTHONPATH=SRC)
    args = [sys.executable, "-m", "resonant", "study", str(model), "--vary",
            "k=uniform(90, 110)", "--quantity", "peak:x", "--band", "omega=1:30:4000",
            "--samples", "7000", "--workers", "0", "-o", str(out)]  # many chunks
    # a runner started in the background ignores SIGINT, and its children inherit that:
    # the program gets Ctrl-C's default, as from a terminal
    proc = subprocess.Popen(args, stderr=subprocess.PIPE, stdout=subprocess.PIPE, env=env,
                            text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 60
    while not Path(str(out) + ".part").exists() and time.monotonic() < deadline:
        time.sleep(0.02)
    proc.send_signal(2)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert len(err.strip().splitlines()) == 1 and err.startswith("the study stopped"), err
    if out.exists():
        assert f"{out} holds the" in err
        from resonant.studies import files

        description = files.read_description(out)  # what --resume reads first: valid
        rows = files.completed_rows(out)
        assert description["rows"] == 7000 and 0 < rows < 7000
        files.check_rows(out, ["sample", "k", "peak:x", "peak_frequency:x", "status",
                               "reason"], ("status", "reason"), rows)


def test_resume_csv_cut_in_the_middle_of_a_row_recomputes_it(model, finished):
    out = finished["csv"]
    whole = out.read_bytes()
    out.write_bytes(whole[:-7])  # the last row loses its end (and its newline)
    code, _, err = study(model, out, "--resume")
    assert code == 0, err
    assert out.read_bytes() == whole


# -- 7. the study fuzzer, a few cases of each generator -------------------------------------

@pytest.mark.parametrize("kind", ["request", "study_section", "explore_section", "nonlinear",
                                  "resume"])
def test_study_fuzzer_cases(kind, tmp_path):
    sys.path.insert(0, str(ROOT / "fuzz"))
    import random

    import study_fuzz

    rng = random.Random(2026)
    for _ in range(4):
        case, status, bug, err, _ = study_fuzz.fuzz_case(rng, kind, tmp_path, 30.0, 5.0)
        assert bug is None, f"{' '.join(case)}: {bug}\n{err}"
