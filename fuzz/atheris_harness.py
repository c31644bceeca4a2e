"""Coverage-guided fuzzing of the model loader and ``resonant solve`` with atheris.

    pip install atheris
    PYTHONPATH=src python fuzz/atheris_harness.py -atheris_runs=20000 [-max_total_time=300]

The corpus starts from the bundled examples.  Every input must end with exit 0, 2 or 3
and a message (see ``run_fuzz.verdict``); anything else raises, which atheris reports as
a crash and saves as ``crash-*``.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import atheris

import numpy  # noqa: F401  (imported first so that only resonant is instrumented)
import sympy  # noqa: F401

with atheris.instrument_imports(include=["resonant"]):
    import resonant.cli  # noqa: F401  (instrumented for coverage feedback)
    import resonant.expressions  # noqa: F401
    import resonant.model  # noqa: F401

sys.path.insert(0, str(Path(__file__).parent))
import run_fuzz  # noqa: E402

WORKDIR = Path(tempfile.mkdtemp(prefix="resonant-atheris-"))
MODEL = WORKDIR / "model.toml"


def test_one_input(data: bytes) -> None:
    MODEL.write_bytes(data)
    status, out, err = run_fuzz.run_one(
        ["solve", str(MODEL), "--json", "--timeout", "2"], budget=10.0)
    bug = run_fuzz.verdict(status, out, err, json_expected=True)
    if bug:
        raise RuntimeError(f"{bug}: {err.strip()[-300:]}")


def main() -> None:
    corpus = WORKDIR / "corpus"
    corpus.mkdir()
    for path in run_fuzz.EXAMPLES:
        (corpus / path.name).write_bytes(path.read_bytes())
    atheris.Setup([*sys.argv, str(corpus)], test_one_input)
    atheris.Fuzz()


if __name__ == "__main__":
    main()
