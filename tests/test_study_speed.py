"""What a linear study's process pays for (docs/performance-studies.md): the imports it
needs and no others, and its summary built from the rows it wrote, not read back."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

import resonant
from conftest import EXAMPLES
from resonant.studies import Engine, StudyJob, collect, read_table, request, run

SRC = Path(__file__).resolve().parents[1] / "src"


def test_a_linear_study_does_not_import_scipy(tmp_path: Path) -> None:
    """The reference exercise's amplitude study solves 2 x 2 systems in closed form: scipy
    (0.1-0.2 s of imports, scipy.linalg alone) is not needed, and the nonlinear
    quantities' modules that the study imports do not import it either."""
    code = ("import sys\nfrom resonant.cli import main\n"
            f"code = main(['study', {str(EXAMPLES / 'cart_pendulum.toml')!r}, '-o', "
            f"{str(tmp_path / 'r.parquet')!r}, '--vary', 'k=uniform(80, 120)', "
            "'--quantity', 'amplitude:x2', '--samples', '1000', '--workers', '0'])\n"
            "print(code, sorted(m for m in sys.modules if m.split('.')[0] == 'scipy'))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(SRC)}, timeout=300)
    assert done.stdout.strip().splitlines()[-1] == "0 []", (done.stdout[-2000:],
                                                             done.stderr[-2000:])


@pytest.mark.parametrize("columns", [None, ["k", "amplitude:x2", "status"]])
def test_the_rows_kept_as_written_are_the_file_read_back(tmp_path: Path,
                                                         monkeypatch: pytest.MonkeyPatch,
                                                         columns: list[str] | None) -> None:
    """collect() builds a Parquet study's table from the rows as they were written (the
    file is not read back): the same DataFrame as ``read_table`` of the file -- types,
    values, categories in the same order -- over chunks of 7 rows whose statuses differ
    (ok, unstable), and after a resume that keeps the file's rows."""
    model = resonant.load(EXAMPLES / "cart_pendulum.toml")
    k = [100.0, -50.0, 90.0] * 10 + [100.0]
    spec = request(model, {"k": k}, ["amplitude:x2", "stable"],
                   design="random", samples=len(k))
    monkeypatch.setattr(run, "chunk_size", lambda spec, n: 7)
    path = tmp_path / "r.parquet"
    job = StudyJob.of(model, spec)


    def unread(*args: object) -> None:
        raise AssertionError("the file was read back")

    monkeypatch.setattr(run, "read_table", unread)
    first = collect(job, Engine("process"), path, columns=columns)
    again = collect(job, Engine("process"), path, columns=columns, resume=True)
    read = read_table(path, columns)
    assert len(set(read["status"])) > 1, read
    pd.testing.assert_frame_equal(first.table, read, check_exact=True)
    pd.testing.assert_frame_equal(again.table, read, check_exact=True)
