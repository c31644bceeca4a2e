"""A Sphinx extension that makes the gallery of the bundled examples while the site builds.

For every model in ``examples/`` (and its ``parts/`` and ``teaching/`` folders) it writes a
page ``gallery/<name>.md`` with the model file, the mechanism drawn from its parts, the
mode shapes, the frequency response about the natural frequencies and, for the models
that are nonlinear beyond small oscillations, the nonlinear frequency response with its
stability — every figure computed by resonant's own API at build time, so the gallery
shows what the code does today.  ``gallery/`` is generated (listed in ``.gitignore``).

A model with loads beyond a sine shows its own analysis, and its page suggests the command
that computes it (``resonant solve`` prints a zero amplitude for a random or shock input):
``[random]`` the response densities (``resonant random --plot``, the figure that command
draws), ``[shock]`` the pulse's and a response's shock response spectra (``resonant srs
--plot``), ``[periodic]`` the summed response over one period and its harmonics, and
``[fatigue]`` the damage of the stress output by each spectral method.  The guide's
pages use these figures too (docs/random.md shows the GEVS densities and the half-sine's
SRS): they are computed here, never committed.
"""

from __future__ import annotations

import contextlib
import io
import re
import shutil
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import resonant  # noqa: E402
from resonant.analyses.fatigue import METHODS, SNCurve, spectral_fatigue  # noqa: E402
from resonant.analyses.periodic_load import periodic_load_response  # noqa: E402
from resonant.analyses.random_response import random_response  # noqa: E402
from resonant.charts import save_figure  # noqa: E402
from resonant.cli import main as run_command  # noqa: E402
from resonant.errors import ResonantError  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
FOLDERS = ("", "parts", "teaching", "rotors", "matrices")
#: examples whose nonlinear steady state the gallery shows
NONLINEAR = ("duffing.toml", "two_dof_cubic.toml")


def example_files() -> list[Path]:
    """The bundled model files, in a stable order."""
    return [path for folder in FOLDERS
            for path in sorted((ROOT / "examples" / folder).glob("*.toml"))]


def _save(figure: Any, path: Path) -> str:
    # save_figure leaves "tight" out for a figure its layout engine fits, and lays that
    # one out once instead of drawing it twice (docs/performance.md, "Figures")
    save_figure(figure, path, dpi=90, bbox_inches="tight")
    plt.close(figure)
    return path.name


def _frequency_range(system: Any) -> tuple[float, float] | None:
    frequencies = system.modes().natural_frequencies
    positive = frequencies[frequencies > 0]
    if positive.size == 0:
        return None
    return 0.3 * float(positive.min()), 1.6 * float(positive.max())


def _command(arguments: list[str]) -> None:
    """Run one of resonant's commands as a user would (its text output discarded)."""
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        status = run_command(arguments)
    if status != 0:
        raise RuntimeError(f"resonant {' '.join(arguments)} exited {status}")


def sweep_parameter(model: Any) -> str | None:
    """The parameter of the excitation's frequency: ``omega``, else the name multiplying
    t in a signal (``Omega`` in ``e*cos(Omega*t)``); None if there is none."""
    if "omega" in model.parameters:
        return "omega"
    for expression in model.signals.values():
        for name in re.findall(r"\b([A-Za-z_]\w*)\s*\*\s*t\b", expression.text):
            if name in model.parameters:
                return str(name)
    return None


def _response_name(model: Any, wanted: tuple[str, ...]) -> str | None:
    """The first output named in ``wanted``, else the first output, else None."""
    outputs = list(model.outputs)
    return next((n for n in wanted if n in outputs), outputs[0] if outputs else None)


def _periodic_figure(model: Any, system: Any) -> tuple[str, Any]:
    """The summed response over one period above the harmonics' amplitudes (the first
    responses of the first one's unit; lengths in mm)."""
    from resonant.model.units_display import result_units

    result = periodic_load_response(system)
    units = result_units(model)
    si = dict(units.si) if units is not None else {}
    first = si.get(result.names[0], "")
    names = [n for n in result.names if si.get(n, "") == first][:3]
    scale, unit = (1e3, "mm") if first == "m" else (1.0, first or "SI")
    figure, (history, bars) = plt.subplots(2, 1, figsize=(7, 5.6),
                                           constrained_layout=True)
    t = np.asarray(result.time)
    for name in names:
        history.plot(t, scale * np.asarray(result.history[name]), label=name)
    history.set(xlabel="time $t$ [s]", ylabel=f"response [{unit}]",
                title=f"summed response over one period (T = {result.series.period:g} s, "
                      f"{result.series.harmonics} harmonics)")
    history.legend(frameon=False)
    shown = min(12, result.series.harmonics)
    n = np.arange(1, shown + 1)
    width = 0.8 / len(names)
    for k, name in enumerate(names):
        amplitude = np.abs(np.asarray(result.harmonics[name])[:shown])
        bars.bar(n + (k - (len(names) - 1) / 2) * width, scale * amplitude, width, label=name)
    bars.set(xlabel="harmonic $n$", ylabel=f"amplitude $|z_n|$ [{unit}]", xticks=n,
             title="the response to each harmonic of the Fourier series")
    bars.legend(frameon=False)
    return ("The periodic load's stationary response: the sum over one period and the "
            "harmonics' amplitudes (`resonant solve` prints them)"), figure


def _fatigue_figure(model: Any, system: Any) -> tuple[str, Any] | None:
    """The damage of the stress output over the section's duration, by method."""
    spec = model.fatigue_section
    response = random_response(system)
    stresses = [n for n, unit in response.units.items() if unit == "Pa"]
    if not stresses:
        return None
    name = stresses[0]
    try:
        fatigue = spectral_fatigue(response.frequency, response.psd[name],
                                   SNCurve(spec.C, spec.k), spec.duration, methods=METHODS)
    except (ImportError, ResonantError):
        return None
    figure, axes = plt.subplots(figsize=(7, 3.4), constrained_layout=True)
    methods = list(fatigue.damage)
    values = [float(fatigue.damage[m]) for m in methods]
    axes.barh(methods, values, color="#4c72b0")
    for row, value in enumerate(values):
        axes.text(value, row, f"  {value:.3g}", va="center")
    axes.set(xlabel=f"Miner's damage over {spec.duration:g} s", xlim=(0, 1.3 * max(values)),
             title=f"fatigue of '{name}' (RMS {response.rms[name] / 1e6:.3g} MPa; "
                   f"S-N: k = {spec.k:g})")
    return (f"Fatigue damage of `{name}` by the spectral methods (FLife) over the "
            f"`[fatigue]` section's duration (the study quantity `damage:{name}`)", figure)


def _load_figures(model: Any, path: Path, out: Path, stem: str,
                  system: Any) -> list[tuple[str, str]]:
    """The figures of the loads beyond a sine: random, shock, periodic, fatigue."""
    figures: list[tuple[str, str]] = []
    file = str(path)
    if model.random_section is not None:
        png = out / f"{stem}_random.png"
        _command(["random", file, "--plot", str(png)])
        figures.append(("Response spectral densities with each curve's RMS "
                        "(`resonant random --plot`)", png.name))
    if model.shock_section is not None:
        png = out / f"{stem}_srs.png"
        _command(["srs", file, "--plot", str(png)])
        figures.append(("The pulse and its shock response spectrum (`resonant srs --plot`)",
                        png.name))
        output = _response_name(model, ("a", "acceleration"))
        if output is not None:
            png = out / f"{stem}_srs_{output}.png"
            _command(["srs", file, "--output", output, "--plot", str(png)])
            figures.append((f"The shock `{output}` sees: the SRS of its response "
                            f"(`resonant srs --output {output} --plot`)", png.name))
    if model.periodic_section is not None:
        caption, figure = _periodic_figure(model, system)
        figures.append((caption, _save(figure, out / f"{stem}_periodic.png")))
    if model.fatigue_section is not None and model.random_section is not None:
        found = _fatigue_figure(model, system)
        if found is not None:
            figures.append((found[0], _save(found[1], out / f"{stem}_fatigue.png")))
    return figures


def _figures(model: Any, path: Path, out: Path) -> list[tuple[str, str]]:
    """(caption, image file) for each figure of one example."""
    stem = page_name(path)
    figures: list[tuple[str, str]] = []
    if model.parts is not None:
        figures.append(("The mechanism, drawn from its parts (`resonant draw`)",
                        _save(model.draw(), out / f"{stem}_drawing.png")))
    system = model.linearize()
    loads = _load_figures(model, path, out, stem, system)
    # a single mode is one bar: the page of a one-DOF model under its own load shows that
    if len(model.coordinates) > 1 or not loads:
        figures.append(("Mode shapes (`resonant modes --plot`)",
                        _save(system.modes().plot(), out / f"{stem}_modes.png")))
    band = _frequency_range(system)
    param = sweep_parameter(model)
    if band is not None and param is not None and not loads:
        values = np.linspace(band[0], band[1], 400)
        try:
            response = system.sweep(param, values)
        except ResonantError:
            response = None
        if response is not None:
            figures.append(("Frequency response about the natural frequencies "
                            f"(`resonant sweep --param {param}`)",
                            _save(response.plot(), out / f"{stem}_sweep.png")))
    if model.campbell_section is not None:
        figures.append(("Campbell diagram: modes tracked over the speed, critical speeds, "
                        "log decrements (`resonant campbell --plot`)",
                        _save(model.campbell().plot(), out / f"{stem}_campbell.png")))
    if path.name in NONLINEAR and band is not None:
        low = float(system.modes().natural_frequencies.min())
        branch = model.nonlinear_sweep("omega", 0.5 * low, 2.5 * low, harmonics=3,
                                       points=150)
        figures.append(("Nonlinear frequency response: stable solid, unstable dashed, "
                        "special points marked (`resonant sweep --nonlinear`)",
                        _save(branch.plot(), out / f"{stem}_nonlinear.png")))
    return figures + loads


def page_name(path: Path) -> str:
    """The gallery page (and figure prefix) of an example: its stem, with its folder."""
    return path.stem if path.parent.name == "examples" else f"{path.parent.name}_{path.stem}"


def commands(model: Any, path: Path) -> list[str]:
    """The commands the page suggests: those that compute what the model is about."""
    relative = path.relative_to(ROOT).as_posix()
    suggested = []
    if model.random_section is not None:
        only = [n for n in ("a", "stress") if n in model.outputs]
        suggested.append(f"resonant random {relative}"
                         + (f" --only {','.join(only)}" if only else "") + " --plot psd.png")
    if model.shock_section is not None:
        output = _response_name(model, ("a", "acceleration"))
        suggested.append(f"resonant srs {relative}"
                         + (f" --output {output}" if output else "") + " --plot srs.png")
    if model.fatigue_section is not None:
        if model.study_section is not None:  # its [study] varies what the damage depends on
            suggested.append(f"resonant study {relative} -o damage.csv")
    if model.periodic_section is not None or not suggested:
        suggested.insert(0, f"resonant solve {relative}")
    param = sweep_parameter(model)
    band = _frequency_range(model.linearize()) if param is not None else None
    if not suggested[1:] and band is not None and model.periodic_section is None:
        suggested.append(f"resonant sweep {relative} --param {param} --from {band[0]:.3g} "
                         f"--to {band[1]:.3g} --plot sweep.png")
    return suggested


def _title(path: Path, model: Any) -> str:
    """The example's title, with its folder where the folder's model shares it (the
    teaching copy of the reference exercise)."""
    title = model.title or path.stem
    folder = path.parent.name
    if folder != "examples" and f"({folder})" not in title:
        title += f" ({folder})"
    return title


def _page(path: Path, model: Any, figures: list[tuple[str, str]]) -> str:
    relative = path.relative_to(ROOT).as_posix()
    title = _title(path, model)
    lines = [f"# {title}", "", f"`{relative}`", "", "```console",
             *(f"$ {command}" for command in commands(model, path)), "```", ""]
    for caption, image in figures:
        lines += [f"```{{figure}} {image}", ":alt: " + caption.split(" (")[0], "",
                  caption, "```", ""]
    lines += ["## The model file", "", f"```{{literalinclude}} ../../{relative}",
              ":language: toml", "```", ""]
    return "\n".join(lines)


def build_gallery(app: Any) -> None:
    """Write ``gallery/`` into the source folder: an index and one page per example."""
    out = Path(app.srcdir) / "gallery"
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir()
    entries = []
    cards = []
    for path in example_files():
        model = resonant.load(path)
        name = page_name(path)
        figures = _figures(model, path, out)
        (out / f"{name}.md").write_text(_page(path, model, figures), encoding="utf-8")
        entries.append(name)
        # the card: the first figure (the mechanism where there are parts) as thumbnail
        thumbnail = figures[-1][1] if model.parts is None and len(figures) > 1 else \
            figures[0][1]
        cards += ["````{container} gallery-card", f"```{{image}} {thumbnail}",
                  f":alt: {_title(path, model)}", f":target: {name}.html", "```", "",
                  f"[{_title(path, model)}]({name}.md)", "````", ""]
    index = ["# Gallery of the bundled examples", "",
             "Every figure on these pages is computed by resonant when the site is built; "
             "`resonant example NAME` writes the model file of one of them.", "",
             "`````{container} gallery-grid", "", *cards, "`````", "",
             "```{toctree}", ":hidden:", ":maxdepth: 1", "", *entries, "```", ""]
    (out / "index.md").write_text("\n".join(index), encoding="utf-8")


def setup(app: Any) -> dict[str, Any]:
    """Register the gallery with Sphinx."""
    app.connect("builder-inited", build_gallery)
    return {"parallel_read_safe": True, "version": "1"}
