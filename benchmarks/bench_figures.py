"""The CPU time of drawing and saving resonant's figures, one per figure kind.

``python benchmarks/bench_figures.py [--repeat 3] [--out DIR] [--profile KIND]``

Each kind is a CLI ``--plot`` run on a bundled example (as tests/test_every_plot_option.py
runs them): the same command without ``--plot`` is timed too, and the figure's cost is
the difference of the medians of the process's CPU time (``time.process_time``); the
time of saving (matplotlib's ``Figure.savefig`` and a layout run outside it) is reported
beside it.  ``--out`` keeps the
pictures (to look at them side by side with another version's); ``--profile KIND``
prints the top of a cProfile of that kind's plotting run.
"""

from __future__ import annotations

import argparse
import contextlib
import cProfile
import io
import pstats
import statistics
import sys
import tempfile
import time
from pathlib import Path

from matplotlib.figure import Figure
from matplotlib.layout_engine import ConstrainedLayoutEngine

from resonant.cli import main as cli

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
#: kind -> the command and its arguments beside the example
KINDS = {
    "simulate": ["simulate", "shear_building6.toml", "--duration", "0.1"],
    "modes": ["modes", "shear_building6.toml"],
    "sweep": ["sweep", "chain3_damped.toml", "--param", "omega", "--from", "15", "--to", "60",
              "--points", "21"],
    "random": ["random", "shaker_gevs.toml"],
    "srs": ["srs", "shock_half_sine.toml"],
    "campbell": ["campbell", "rotors/jeffcott_rotor.toml"],
    "speed-map": ["speed-map", "rotors/friswell_5_9_5.toml"],
    "unbalance": ["unbalance", "rotors/jeffcott_rotor.toml"],
    "fatigue": ["fatigue", "bracket_fatigue.toml"],
}
_SAVE = [0.0]
_DEPTH = [0]


def _timed(original):  # type: ignore[no-untyped-def]
    """``original`` adding its CPU time to _SAVE where it is not called inside another
    timed one (the layout engine's run inside savefig counts once)."""
    def timed(*args, **kwargs):  # type: ignore[no-untyped-def]
        start = time.process_time()
        _DEPTH[0] += 1
        try:
            return original(*args, **kwargs)
        finally:
            _DEPTH[0] -= 1
            if not _DEPTH[0]:
                _SAVE[0] += time.process_time() - start
    return timed


def run(arguments: list[str], picture: Path | None) -> tuple[float, float]:
    """CPU seconds of one in-process CLI run, and of its savefig calls."""
    args = [str(EXAMPLES / arguments[1]) if k == 1 else a for k, a in enumerate(arguments)]
    if picture is not None:
        args += ["--plot", str(picture)]
    _SAVE[0] = 0.0
    start = time.process_time()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        status = cli(args)
    spent = time.process_time() - start
    if status != 0:
        raise SystemExit(f"{' '.join(arguments)}: exit {status}")
    return spent, _SAVE[0]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--profile", default=None, choices=sorted(KINDS))
    parser.add_argument("--only", nargs="*", default=None)
    args = parser.parse_args(argv)
    Figure.savefig = _timed(Figure.savefig)  # type: ignore[method-assign]
    ConstrainedLayoutEngine.execute = _timed(  # type: ignore[method-assign]
        ConstrainedLayoutEngine.execute)
    folder = args.out or Path(tempfile.mkdtemp())
    folder.mkdir(parents=True, exist_ok=True)
    if args.profile:
        arguments = KINDS[args.profile]
        run(arguments, folder / f"{args.profile}.png")  # warm
        profile = cProfile.Profile()
        profile.enable()
        for _ in range(args.repeat):
            run(arguments, folder / f"{args.profile}.png")
        profile.disable()
        pstats.Stats(profile, stream=sys.stdout).sort_stats("tottime").print_stats(30)
        return 0
    print("| figure | command | plot CPU [s] | of it saving [s] | PNG [kB] |")
    print("| --- | --- | ---: | ---: | ---: |")
    for kind, arguments in KINDS.items():
        if args.only and kind not in args.only:
            continue
        picture = folder / f"{kind}.png"
        run(arguments, picture)  # warm: imports, caches
        bare = [run(arguments, None)[0] for _ in range(args.repeat)]
        plotted = [run(arguments, picture) for _ in range(args.repeat)]
        cost = statistics.median(p[0] for p in plotted) - statistics.median(bare)
        save = statistics.median(p[1] for p in plotted)
        size = picture.stat().st_size / 1000
        print(f"| {kind} | `{' '.join(arguments)}` | {cost:.3f} | {save:.3f} | {size:.0f} |",
              flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
