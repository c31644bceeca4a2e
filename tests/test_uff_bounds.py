"""Universal Files refused from their bytes before pyuff parses them
(resonant.model.uff_bounds): the memory estimate is an upper bound of what pyuff and
resonant really allocate (measured with tracemalloc), a file above the budget or a header
announcing more points than its record holds is a ModelError naming the file (exit 2), and
so are truncated and unknown records, with no traceback."""

from __future__ import annotations

import shutil
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from conftest import run_cli
from resonant.errors import ModelError
from resonant.model import uff_bounds
from resonant.model.measured import MeasuredData, MeasuredFunction, read_uff, write_uff
from resonant.model.uff_bounds import check_uff, peak_bytes, scan_uff

pytest.importorskip("pyuff")
EXAMPLE = Path("examples/chain3_lab.toml")


def _file(tmp_path: Path, points: int, binary: bool = False, name: str = "big.uff") -> Path:
    t = np.arange(points) / 1024.0
    functions = (MeasuredFunction("d3", "time", t, np.sin(t), "s", "m", (3, 3), (3, 3)),
                 MeasuredFunction("H33", "frf", np.arange(1, points + 1) * 0.1,
                                  1 / (1 + 1j * t), "Hz", "m/N", (3, 3), (3, 3)))
    path = tmp_path / name
    write_uff(path, MeasuredData(name, functions), binary=binary)
    return path


@pytest.mark.parametrize("binary", [False, True])
def test_estimate_bounds_the_real_peak(tmp_path, binary):
    path = _file(tmp_path, 20_000, binary)
    estimate = peak_bytes(scan_uff(path))
    tracemalloc.start()
    try:
        data = read_uff(path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert len(data.functions) == 2
    # an upper bound, and not a wild one (within 12 times the truth)
    assert peak <= estimate <= 12 * peak, (peak, estimate)


def test_above_the_budget_refused_before_pyuff(tmp_path, monkeypatch):
    path = _file(tmp_path, 20_000)
    monkeypatch.setenv("RESONANT_MEMORY", "1M")
    import pyuff

    monkeypatch.setattr(pyuff, "UFF", lambda *a: pytest.fail("pyuff was called"))
    with pytest.raises(ModelError, match=r"big\.uff: reading it .* above the budget of "
                                         r"1 MiB \(RESONANT_MEMORY\)"):
        read_uff(path)


def test_huge_declared_size_refused(tmp_path):
    path = _file(tmp_path, 64, name="liar.uff")
    lines = path.read_text().splitlines(keepends=True)
    # record 7 of the first dataset 58 (its 9th line): type, points, spacing, min, step
    at = next(k for k, line in enumerate(lines) if line.startswith("    58")) + 7
    fields = lines[at].split()
    lines[at] = f"{int(fields[0]):>10}{10**9:>10}{int(fields[2]):>10}" + lines[at][30:]
    path.write_text("".join(lines))
    with pytest.raises(ModelError, match=r"liar\.uff: record 2 \(dataset 58\) announces "
                                         r"1000000000 numbers .* truncated, or a wrong "
                                         "header"):
        read_uff(path)


def test_too_many_records_refused(tmp_path, monkeypatch):
    monkeypatch.setattr(uff_bounds, "MAX_RECORDS", 2)
    path = tmp_path / "many.uff"
    path.write_text("    -1\n   164\n         1SI\n    -1\n" * 3)
    with pytest.raises(ModelError, match=r"many\.uff: more than 2 records"):
        check_uff(path)


def test_line_breaks_only_record_costs_its_lines(tmp_path):
    path = tmp_path / "breaks.uff"
    path.write_bytes(b"    -1\n    58b\n" + b"\n" * 100_000 + b"    -1\n")
    scan = scan_uff(path)
    assert scan.records[0].lines == 100_002 and scan.records[0].binary
    assert peak_bytes(scan) >= uff_bounds.BYTES_PER_LINE * 100_000


def test_hostile_files_exit_2_without_traceback(tmp_path, monkeypatch):
    model = tmp_path / "chain3_lab.toml"
    shutil.copy(EXAMPLE, model)
    good = _file(tmp_path, 2048)
    cases = {"cut.uff": good.read_bytes()[:-3000],
             "wrong.uff": b"    -1\n  2414\nresults\nNONE\n    -1\n",
             "noise.uff": bytes(range(256)) * 8}
    for name, content in cases.items():
        (tmp_path / name).write_bytes(content)
        status, _, err = run_cli(["frf", model, tmp_path / name])
        assert status == 2 and f"{name}" in err and "Traceback" not in err, (name, err)
    monkeypatch.setenv("RESONANT_MEMORY", "1M")
    big = _file(tmp_path, 20_000)
    status, _, err = run_cli(["frf", model, big])
    assert status == 2 and "big.uff: reading it" in err and "Traceback" not in err, err
