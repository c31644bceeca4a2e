"""Every command's ``--plot`` on every bundled example it applies to (docs/reference.md): each
run ends with exit 0, or with exit 2 and an error that names the model's missing part,
and never with an internal error (exit 1) or a traceback; where it succeeds, the picture
is written.  A plot option once crashed on the README's own example (a start kind the
plot's label table lacked), which only running it showed.

Which commands apply: ``modes``, ``simulate`` (0.1 s of motion) and ``sweep`` (the page's
excitation frequency, ``resonant.views.explore.frequency_parameter``, over 0.5 ... 2 times
its value, 21 points) to every example; ``random``, ``srs`` and ``fatigue`` to the
examples with their section; ``campbell``, ``unbalance`` and ``speed-map`` to the rotors
with ``[campbell]``.  The commands on measured data (``frf``, ``identify``,
``correlate``, ``update``) draw in tests/test_testdata_cli.py, ``study`` in
tests/test_figures.py.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import EXAMPLES, run_cli
from resonant.model import load
from resonant.system import linear_system
from resonant.views.explore import frequency_parameter

MODELS = sorted(EXAMPLES.glob("*.toml")) + sorted(EXAMPLES.glob("*/*.toml"))


def _text(path: Path) -> str:
    return path.read_text(encoding="utf-8")


def _runs() -> list[tuple[str, Path]]:
    runs = []
    for path in MODELS:
        text = _text(path)
        runs += [("modes", path), ("simulate", path), ("sweep", path)]
        runs += [(c, path) for c, section in (("random", "[random"), ("srs", "[shock"),
                                              ("fatigue", "[fatigue")) if section in text]
        if "[campbell" in text:
            runs += [("campbell", path), ("speed-map", path)]
            if "unbalance" in text:
                runs.append(("unbalance", path))
    return runs


def _arguments(command: str, path: Path) -> list[str] | None:
    """The command's arguments beside the model (None: nothing to sweep)."""
    if command == "simulate":
        return ["--duration", "0.1"]
    if command != "sweep":
        return []
    model = load(path)
    name = frequency_parameter(model, linear_system(model))
    if name is None:
        return None
    value = float(model.parameter_values.get(name, 0.0)) or 1.0
    return ["--param", name, "--from", f"{0.5 * value!r}", "--to", f"{2 * value!r}",
            "--points", "21"]


@pytest.mark.parametrize(("command", "path"), _runs(),
                         ids=lambda v: v if isinstance(v, str) else v.stem)
def test_the_plot_option_draws_or_says_why_not(command: str, path: Path,
                                               tmp_path: Path) -> None:
    arguments = _arguments(command, path)
    if arguments is None:
        pytest.skip(f"{path.name} has no excitation frequency to sweep")
    picture = tmp_path / "plot.png"
    status, _, err = run_cli([command, path, *arguments, "--plot", picture])
    assert "Traceback" not in err and "internal error" not in err, err
    assert status in (0, 2), err
    if status == 0:
        assert picture.stat().st_size > 5_000
    else:
        assert path.name in err and "error:" in err
