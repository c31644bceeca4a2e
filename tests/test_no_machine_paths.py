"""No output of resonant carries an absolute path of the machine it ran on.

A report, a page, a study file or an answer key is something one hands on: it names the
model by its file name only. Every bundled example is run by its *absolute* path (the worst
case: the path the user typed is the full one) through every output format that applies to
it -- ``solve``/``modes``/``energies`` ``--json`` and text, the report as HTML (and as
Markdown and LaTeX for one model of each kind of content), the interactive page, the
drawing, the study's Parquet file, ``--json`` and pictures, the exercise in every format
(HTML, Markdown, LaTeX, Moodle XML, the JSON key) and ``grade --json`` -- and every byte
written (text or binary: Parquet metadata, PNG and SVG metadata) and every printed text is
searched for the repository's path, the home directory and the test's temporary directory (a
terminal message may repeat the output path the user typed: that one is not counted).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from conftest import EXAMPLES, run_cli

ROOT = Path(__file__).parents[1].resolve()
MODELS = sorted(p.resolve() for p in EXAMPLES.rglob("*.toml"))


def _needles(tmp_path: Path) -> list[bytes]:
    """The machine's paths: the checkout, the home directory, the temporary directory."""
    found = {str(ROOT), str(tmp_path.resolve()), str(tmp_path)}
    home = str(Path.home())
    if len(home) > 4:  # "/" or "/tmp" would match any path-like text
        found.add(home)
    return sorted(n.encode() for n in found)


def _check(tmp_path: Path, texts: dict[str, str]) -> None:
    """No written file under ``tmp_path`` and no printed text holds a machine path."""
    needles = _needles(tmp_path)
    leaks = []
    for name, text in texts.items():
        leaks += [f"{name}: {n.decode()}" for n in needles if n in text.encode()]
    files = [p for p in tmp_path.rglob("*") if p.is_file()]
    for path in files:
        data = path.read_bytes()
        leaks += [f"{path.name}: {n.decode()}" for n in needles if n in data]
    assert not leaks, "absolute paths in the outputs:\n" + "\n".join(leaks)


def _run(args: list[object], texts: dict[str, str], allowed: tuple[int, ...] = (0,)) -> None:
    status, out, err = run_cli([str(a) for a in args])
    assert status in allowed, (args, status, err)
    # a terminal message may repeat where it wrote the files the user asked for, as typed
    for arg in args[2:]:
        if isinstance(arg, Path):
            out = out.replace(str(arg), "OUTPUT")
    texts[" ".join(str(a) for a in args[:1] + args[2:])] = out


#: one model of each kind of content: energies, parts, matrix files, a rotor, random, shock,
#: periodic and fatigue loads, a nonlinear model, a teaching copy
EVERY_WRITER = {"cart_pendulum.toml", "parts/quarter_car.toml", "matrices/inboard_fixed.toml",
                "rotors/jeffcott_rotor.toml", "shaker_gevs.toml", "shock_half_sine.toml",
                "periodic_sawtooth.toml", "bracket_fatigue.toml", "two_dof_cubic.toml",
                "teaching/fourier_square.toml"}


def _relative(model: Path) -> str:
    return model.relative_to(EXAMPLES.resolve()).as_posix()


def _has_parts(model: Path) -> bool:
    return "[[part]]" in model.read_text(encoding="utf-8") or \
        "[parts" in model.read_text(encoding="utf-8")


@pytest.mark.parametrize("model", MODELS, ids=_relative)
def test_every_output_names_the_model_by_its_file_name(tmp_path: Path, model: Path) -> None:
    texts: dict[str, str] = {}
    # an analysis may be impossible for a model (exit 3, e.g. a free body): its message
    # still may not carry a path, so it is kept too
    _run(["solve", model, "--json"], texts, (0, 3))
    _run(["solve", model], texts, (0, 3))
    _run(["modes", model, "--json"], texts, (0, 3))
    # every model's report as HTML; as Markdown and LaTeX (the same blocks, other writers)
    # for one model of each kind of content, which covers every writer's own output
    suffixes = ("html", "md", "tex") if _relative(model) in EVERY_WRITER else ("html",)
    for suffix in suffixes:
        _run(["report", model, "-o", tmp_path / f"report.{suffix}"], texts, (0, 3))
    _run(["explore", model, "-o", tmp_path / "page.html"], texts, (0, 3))
    if _has_parts(model):
        _run(["energies", model, "--json"], texts)
        _run(["draw", model, "-o", tmp_path / "drawing.svg"], texts)
    _check(tmp_path, texts)


def test_a_study_records_the_file_name_only(tmp_path: Path) -> None:
    model = (EXAMPLES / "absorber_tolerances.toml").resolve()
    texts: dict[str, str] = {}
    _run(["study", model, "--samples", "40", "--workers", "0", "-o", tmp_path / "s.parquet",
          "--plot", tmp_path / "plots", "--json"], texts)
    _run(["study", model, "--samples", "16", "--design", "grid", "--workers", "0",
          "-o", tmp_path / "g.parquet", "--plot", tmp_path / "grid"], texts)
    assert (tmp_path / "s.parquet").stat().st_size > 0
    assert any((tmp_path / "plots").iterdir())
    _check(tmp_path, texts)


def test_an_exercise_in_every_format_records_the_file_name_only(tmp_path: Path) -> None:
    model = (EXAMPLES / "teaching" / "cart_pendulum.toml").resolve()
    texts: dict[str, str] = {}
    out = tmp_path / "variants"
    _run(["exercise", model, "--variants", "2", "--seed", "1", "-o", out,
          "--format", "html,md,tex,moodle,json"], texts)
    keys = sorted(out.rglob("*.json"))
    assert keys, sorted(p.name for p in out.rglob("*"))
    key = json.loads(keys[0].read_text(encoding="utf-8"))
    assert key.get("model") in (None, model.name), key.get("model")
    answers = tmp_path / "answers.json"
    answers.write_text(json.dumps({name: 1.0 for name in key.get("answers", [])}),
                       encoding="utf-8")
    _run(["grade", keys[0], answers, "--variant", "1", "--json"], texts, (0, 1, 2, 3))
    _check(tmp_path, texts)
