"""``resonant example``: the bundled examples, from a checkout and from a built package.

The package build (``setup.py``'s ``build_py``) is run into a temporary folder: the
example model files must be in the built ``resonant/examples`` and be found there by
the command, so that ``pip install resonant`` then ``resonant example cart_pendulum`` and
``resonant solve examples/cart_pendulum.toml`` work without the repository.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import EXAMPLES, run_cli

ROOT = Path(__file__).resolve().parents[1]


def test_the_list_names_every_example(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = run_cli(["example"])
    assert status == 0
    listed = [line.split()[0] for line in out.splitlines()]
    expected = sorted(p.relative_to(EXAMPLES).with_suffix("").as_posix()
                      for p in EXAMPLES.rglob("*.toml"))
    assert listed == expected
    assert "Cart with pendulum under force and support excitation" in out


def test_an_example_is_written_where_the_guide_expects_it(tmp_path: Path,
                                                          monkeypatch: pytest.MonkeyPatch
                                                          ) -> None:
    monkeypatch.chdir(tmp_path)
    assert run_cli(["example", "cart_pendulum"])[0] == 0
    written = tmp_path / "examples" / "cart_pendulum.toml"
    assert written.read_text(encoding="utf-8") == \
        (EXAMPLES / "cart_pendulum.toml").read_text(encoding="utf-8")
    assert run_cli(["solve", "examples/cart_pendulum.toml"])[0] == 0
    assert run_cli(["example", "cart_pendulum"])[0] == 0  # the same file: nothing to do
    written.write_text("changed", encoding="utf-8")
    status, _, err = run_cli(["example", "cart_pendulum"])
    assert status == 2 and "exists and differs" in err
    status, out, _ = run_cli(["example", "parts/quarter_car", "-o", "-"])
    assert status == 0 and 'title = "Quarter car' in out
    status, _, err = run_cli(["example", "cart"])
    assert status == 2 and "did you mean" in err and "cart_pendulum" in err


def test_an_example_gets_its_data_file_beside_it(tmp_path: Path,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    """``matrices/inboard_fixed`` reads ``inboard_fixed.op4`` beside it: written with it,
    then the model runs where it was written (Nastran's 6.129345 Hz, inboard.out)."""
    pytest.importorskip("pyyeti")
    monkeypatch.chdir(tmp_path)
    status, _, err = run_cli(["example", "matrices/inboard_fixed"])
    assert status == 0 and "inboard_fixed.op4" in err
    copy = tmp_path / "examples" / "matrices" / "inboard_fixed.op4"
    assert copy.read_bytes() == (EXAMPLES / "matrices" / "inboard_fixed.op4").read_bytes()
    status, out, _ = run_cli(["modes", "examples/matrices/inboard_fixed.toml", "--json"])
    assert status == 0
    hz = json.loads(out)["frequencies_hz"][0]
    assert hz == pytest.approx(6.129345, rel=5e-7)
    assert run_cli(["example", "matrices/inboard_fixed"])[0] == 0  # the same files
    copy.write_bytes(b"changed")
    target = tmp_path / "examples" / "matrices" / "inboard_fixed.toml"
    target.unlink()
    status, _, err = run_cli(["example", "matrices/inboard_fixed"])
    assert status == 2 and "inboard_fixed.op4' exists and differs" in err
    assert not target.exists()  # refused before anything is written
    status, _, err = run_cli(["example", "matrices/inboard_fixed", "-o", "-"])
    assert status == 0 and "reads inboard_fixed.op4 beside it" in err


def test_a_built_package_carries_the_examples(tmp_path: Path) -> None:
    build = tmp_path / "lib"
    run = subprocess.run([sys.executable, "setup.py", "-q", "build_py", "--build-lib",
                          str(build)], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-2000:]
    shipped = sorted(p.relative_to(build / "resonant" / "examples").as_posix()
                     for p in (build / "resonant" / "examples").rglob("*.toml"))
    assert shipped == sorted(p.relative_to(EXAMPLES).as_posix() for p in EXAMPLES.rglob("*.toml"))
    data = build / "resonant" / "examples" / "matrices" / "inboard_fixed.op4"
    assert data.read_bytes() == (EXAMPLES / "matrices" / "inboard_fixed.op4").read_bytes()
    # the built package alone (no checkout on the path) finds and writes them
    work = tmp_path / "work"
    work.mkdir()
    env = {**os.environ, "PYTHONPATH": str(build)}
    done = subprocess.run([sys.executable, "-m", "resonant", "example", "cart_pendulum"],
                          cwd=work, env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert (work / "examples" / "cart_pendulum.toml").is_file()
    done = subprocess.run([sys.executable, "-m", "resonant", "example",
                           "matrices/inboard_fixed"], cwd=work, env=env, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert (work / "examples" / "matrices" / "inboard_fixed.op4").read_bytes() == \
        data.read_bytes()
    solved = subprocess.run([sys.executable, "-m", "resonant", "solve",
                             "examples/cart_pendulum.toml"], cwd=work, env=env,
                            capture_output=True, text=True, timeout=300)
    assert solved.returncode == 0, solved.stderr
    assert "natural" in solved.stdout
