"""Nonlinear frequency response of large matrix models with local nonlinear elements.

    python benchmarks/bench_nonlinear_fe.py [--sizes 1000,3000,10000] [--points 100]
    python benchmarks/bench_nonlinear_fe.py --pyharm-sizes 10,20,50 [--pyharm-nldofs]

A fixed-free chain of n masses 1/n on springs n (a discretized rod: its first natural
frequency pi/2 whatever n, Rayleigh damping C = 0.02 M + 0.002 K) with a cubic spring
at its free end and a stop (gap) at its middle: m = 2 nonlinear coordinates.  For each
n, ``condensed_sweep`` follows the periodic response over omega = 1.0 ... 2.4 (across
the first resonance, through its folds) with H = 7 and the stability of every point, in
this process after the model is loaded; reported: the whole time, the share of the
reduced model of the linear part (its build, including the factorizations), the branch
points and the time per point.  The goal: a 10,000-DOF
model's 200-point branch with stability in <= 10 s, and the time beyond the reduced
model's build flat in n at fixed m.

With ``--pyharm-sizes 10,20,50`` the same rods are also run in pyHarm (``pip install
pyHarm-os``; not a dependency of resonant, skipped when it is missing), which forms
and solves the full n(2H+1) system: ``Maestro`` with a ``Base`` system (H = 7, 2048
time samples like resonant's for a gap), the rod's dense M, C, K as one substructure
(one dof per node), connectors ``CosinusForcing`` (0.01 at the tip), ``CubicSpring``
(k = 2 at the tip) and ``PenaltyUnilateralGap`` (g = 0.2, k = 0.5 at the middle: force
k (q - g) for q >= g, else 0 -- resonant's ``kind = "gap"``); study ``frf`` from 1.0 to
2.4, tangent predictor, arc-length corrector, ``acceptance`` step sizer (ds0 = 0.01,
ds_max = 0.02), solver ``scipyroot``; with ``--pyharm-nldofs`` also with its
``NLdofs`` reductor (Newton on the nonlinear dofs only, the linear ones solved for
at every evaluation).  Each side runs in a fresh process (``--timeout`` seconds at
most), one BLAS thread each (the machine has 2 cores and is shared: multithreaded
BLAS there slows small dense factorizations a hundredfold); timed: the curve's
computation (pyHarm's ``Maestro.operate()``, resonant's ``condensed_sweep`` call
with the stability of every point) and the whole child process.  Checked: the tip's
largest amplitude (relative 1e-3) and the folds' frequencies (1e-3), pyHarm's
refined by a parabola through its three points around each extremum.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "src"))


def write_rod(directory: Path, n: int) -> Path:
    """The chain's matrices (.npz) and model file."""
    import numpy as np
    import scipy.sparse as sp

    directory.mkdir(parents=True, exist_ok=True)
    main = np.full(n, 2.0 * n)
    main[-1] = n
    K = sp.diags([np.full(n - 1, -1.0 * n), main, np.full(n - 1, -1.0 * n)], [-1, 0, 1],
                 format="csr")
    M = sp.identity(n, format="csr") / n
    for name, matrix in (("M", M), ("K", K), ("C", (0.02 * M + 0.002 * K).tocsr())):
        sp.save_npz(directory / f"{name}.npz", matrix)
    force = ", ".join(["0"] * (n - 1) + ["0.01"])
    path = directory / f"rod{n}.toml"
    path.write_text(
        f'title = "Rod of {n} masses, cubic spring at the end, stop at the middle"\n'
        "[parameters]\nomega = 1\n"
        '[matrices]\nM = "M.npz"\nC = "C.npz"\nK = "K.npz"\n'
        f'[[harmonic]]\nomega = "omega"\nF_C = [{force}]\n'
        f'[[nonlinear]]\nname = "spring"\ncoordinates = ["q{n}"]\nforce = "2*q{n}^3"\n'
        f'[[nonlinear]]\nname = "stop"\ncoordinates = ["q{n // 2}"]\nkind = "gap"\n'
        "gap = 0.2\nstiffness = 0.5\n", encoding="utf-8")
    return path


def write_plate(directory: Path, n: int, name: str = "plate") -> tuple[Path, int]:
    """A structure of ``benchmarks/corpus.py`` (``plate``: the clamped Kirchhoff plate,
    Morley triangles; ``grid``: the 2-D spring-mass grid with Rayleigh damping; about n
    coordinates) with a cubic spring and the harmonic force at its loaded coordinate: the
    model file and the 0-based coordinate of spring and force.

    Scaled so that the rod's range and children serve unchanged: frequencies in units of
    w1 / (pi/2) (w1 the plate's first natural frequency: M' = s^2 M, C' = s C), stiffness
    in units of K's entry at the spring, the force F0 such that the linear response's
    peak there is 1, the cubic spring k3 = k_eff / 2 (k_eff the static stiffness there):
    at the linear peak its force is half the linear one, a hardening of about 20 % in
    frequency with two folds inside 1.0 ... 2.4."""
    import numpy as np
    import scipy.sparse as sp
    from scipy.sparse.linalg import spsolve

    sys.path.insert(0, str(HERE))
    import corpus

    structure = corpus.build(name, n)
    at = int(np.flatnonzero(structure.b)[0])
    # the first elastic frequency: a free structure's rigid-body modes (w = 0) come first
    rigid = int(structure.meta.get("rigid_modes", 0))
    w1 = float(corpus._lowest(structure.M, structure.K, rigid + 1, -1.0 if rigid else 0.0)[rigid])
    s = w1 / (np.pi / 2)
    k0 = float(structure.K[at, at])
    M, C, K = ((scale * a / k0).tocsr() for scale, a in
               ((s * s, structure.M), (s, structure.C), (1.0, structure.K)))
    e = np.zeros(M.shape[0])
    e[at] = 1.0
    peak = abs(spsolve((K - (np.pi / 2) ** 2 * M + 1j * (np.pi / 2) * C).tocsc(),
                       e.astype(complex))[at])
    k_eff = 1.0 / float(spsolve(K.tocsc(), e)[at])
    F0, k3 = float(1.0 / peak), float(0.5 * k_eff)
    directory.mkdir(parents=True, exist_ok=True)
    for key, matrix in (("M", M), ("C", C), ("K", K)):  # not `name`: the file's name below
        sp.save_npz(directory / f"{key}.npz", matrix)
    q = f"q{at + 1}"
    path = directory / f"{name}{M.shape[0]}.toml"
    path.write_text(
        f'title = "{name}, {M.shape[0]} coordinates, cubic spring at {q}"\n'
        "[parameters]\nomega = 1\n"
        '[matrices]\nM = "M.npz"\nC = "C.npz"\nK = "K.npz"\n'
        f'[[harmonic]]\nomega = "omega"\nF_C = {{ {q} = "{F0!r}" }}\n'
        f'[[nonlinear]]\nname = "spring"\ncoordinates = ["{q}"]\nforce = "{k3!r}*{q}^3"\n',
        encoding="utf-8")
    (directory / "connectors.json").write_text(json.dumps({
        "load": {"type": "CosinusForcing", "connect": {"rod": [at]}, "dirs": [0], "amp": F0},
        "spring": {"type": "CubicSpring", "connect": {"rod": [at]}, "dirs": [0], "k": k3}}))
    return path, at


def write_model(structure: str, directory: Path, n: int) -> tuple[Path, int]:
    """The rod or the plate: the model file and the 0-based coordinate observed (the
    rod's tip; the plate's spring)."""
    if structure in ("plate", "grid"):
        return write_plate(directory, n, structure)
    path = write_rod(directory, n)
    (directory / "connectors.json").write_text(json.dumps(ROD_CONNECTORS(n)))
    return path, n - 1


def ROD_CONNECTORS(n: int) -> dict:  # noqa: N802 - a table of the rod's size
    """The rod's elements in pyHarm's words."""
    return {"load": {"type": "CosinusForcing", "connect": {"rod": [n - 1]}, "dirs": [0],
                     "amp": 0.01},
            "spring": {"type": "CubicSpring", "connect": {"rod": [n - 1]}, "dirs": [0],
                       "k": 2.0},
            "stop": {"type": "PenaltyUnilateralGap", "connect": {"rod": [n // 2 - 1]},
                     "dirs": [0], "g": 0.2, "k": 0.5}}


def measure(n: int, points: int, directory: Path, structure: str = "rod",
            harmonics: int | None = None) -> dict:
    """One size: load, follow the branch, time it (H = ``harmonics``, None: automatic)."""
    import resonant
    from resonant.analyses import condensed
    from resonant.system import nonlinear_system

    path, _ = write_model(structure, directory / f"n{n}", n)
    model = resonant.load(path)
    system = nonlinear_system(model)
    built: dict[str, float] = {}
    original = condensed.linear_part

    def timed_linear_part(*args, **kwargs):  # the reduced model's share of the time
        part = original(*args, **kwargs)  # once per band: again where H is raised
        built["seconds"] = built.get("seconds", 0.0) + part.seconds
        built["size"] = part.size
        return part

    condensed.linear_part = timed_linear_part
    try:
        start, cpu = time.perf_counter(), time.process_time()
        result = condensed.condensed_sweep(system, "omega", 1.0, 2.4, points=points,
                                           harmonics=harmonics, linear=False)
        seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    finally:
        condensed.linear_part = original
    return {"n": system.n, "seconds": seconds, "cpu_seconds": cpu,
            "harmonics": result.harmonics,
            "reduced_model_seconds": built["seconds"],
            "reduced_size": built["size"], "branch_points": len(result.values),
            "unstable_points": int((~result.stable).sum()),
            "folds": sum(s.kind == "fold" for s in result.special_points),
            "per_point_ms": 1e3 * (seconds - built["seconds"]) / len(result.values),
            "warnings": list(result.warnings)}


HARMONICS = 7
SAMPLES = 2048  # resonant's default for an element with kinks (a gap)
#: time samples for the plate, whose one element (a cubic spring) is smooth: 8 per
#: harmonic coefficient, resonant's default (docs/nonlinear.md)
SMOOTH_SAMPLES = 120
START, STOP = 1.0, 2.4

RESONANT_CHILD = """
import json, sys, time
import numpy as np
import resonant
from resonant.analyses import condensed
from resonant.system import nonlinear_system
path, n, at = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
model = resonant.load(path)
system = nonlinear_system(model)
t1 = time.perf_counter()
r = condensed.condensed_sweep(system, "omega", @START@, @STOP@, harmonics=@H@,
                              points=100, samples=@SAMPLES@, linear=False)
t2 = time.perf_counter()
tip = f"q{at + 1}"
peaks = [p.amplitudes[tip] for p in r.special_points if p.kind == "peak"]
print(json.dumps({"curve_s": t2 - t1, "points": int(r.values.size),
                  "folds": sorted(p.value for p in r.special_points if p.kind == "fold"),
                  "peak": float(max([float(np.max(r.amplitudes[tip]))] + peaks)),
                  "unstable": int((~r.stable).sum())}))
"""

PYHARM_CHILD = """
import json, logging, sys, time
import numpy as np
import scipy.sparse as sp
import pyHarm
logging.disable(logging.CRITICAL)
folder, n, reductor, at = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
H = @H@
lin = {name: sp.load_npz(f"{folder}/{name}.npz").toarray() for name in ("M", "C", "K")}
lin["G"] = np.zeros((n, n))
INP = {
    "analysis": {"FRF": {"study": "frf", "puls_inf": @START@, "puls_sup": @STOP@,
                         "ds0": 1e-2, "ds_min": 1e-8, "ds_max": 2e-2, "sign_ds": 1,
                         "verbose": False, "stepsizer": "acceptance",
                         "predictor": "tangent", "corrector": "arc_length",
                         "stopper": "bounds", "solver": "scipyroot",
                         "reductors": [{"type": reductor}]}},
    "system": {"type": "Base", "nh": H, "nti": @SAMPLES@},
    "substructures": {"rod": {"matrix": lin, "ndofs": 1}},
    "connectors": json.load(open(f"{folder}/connectors.json")),
}
maestro = pyHarm.Maestro(INP)
t1 = time.perf_counter()
maestro.operate()
t2 = time.perf_counter()
study = maestro.nls["FRF"]
sols = [s for s in study.SolList if s.flag_accepted]
om = np.array([s.x[-1] for s in sols])
X = np.array([s.x[:-1] for s in sols])
dofs = study.system.expl_dofs
# the tip's coefficients in pyHarm's order [a0, a1, b1, ..., aH, bH]
rows = dofs[dofs["node_num"] == at].sort_values(["harm", "cs"]).index.to_numpy()
tau = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
basis = [np.ones_like(tau)]
for k in range(1, H + 1):
    basis += [np.cos(k * tau), np.sin(k * tau)]
amp = np.abs(X[:, rows] @ np.array(basis)).max(axis=1)
print(json.dumps({"curve_s": t2 - t1, "points": len(sols), "om": om.tolist(),
                  "amp": amp.tolist()}))
"""


def _fill(code: str, samples: int = SAMPLES) -> str:
    """The children's constants, written into their code."""
    for key, value in (("@START@", START), ("@STOP@", STOP), ("@H@", HARMONICS),
                       ("@SAMPLES@", samples)):
        code = code.replace(key, repr(value))
    return code


def _vertex(y: list[float], i: int) -> float:
    """The extremum of the parabola through points i-1, i, i+1 (equally weighted)."""
    a, b, c = y[i - 1], y[i], y[i + 1]
    den = a - 2 * b + c
    if den == 0:
        return b
    t = 0.5 * (a - c) / den
    return b - 0.25 * (a - c) * t


def pyharm_extrema(om: list[float], amp: list[float]) -> tuple[list[float], float]:
    """pyHarm's folds (turns of omega) and the tip's largest amplitude, refined."""
    folds = [_vertex(om, i) for i in range(1, len(om) - 1)
             if (om[i] - om[i - 1]) * (om[i + 1] - om[i]) < 0]
    k = max(range(len(amp)), key=amp.__getitem__)
    peak = _vertex(amp, k) if 0 < k < len(amp) - 1 else amp[k]
    return sorted(folds), peak


def _child_env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(HERE.parent / "src")] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        env[name] = "1"
    return env


def _child(code: str, args: list[str], timeout: float) -> dict:
    """One side in a fresh process: its JSON, the whole process's time, or a timeout."""
    start = time.perf_counter()
    try:
        proc = subprocess.run([sys.executable, "-c", code, *args], capture_output=True,
                              text=True, env=_child_env(), timeout=timeout,
                              cwd=tempfile.gettempdir())
    except subprocess.TimeoutExpired:
        return {"timeout": timeout}
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        return {"error": proc.stderr[-1500:]}
    return {**json.loads(proc.stdout.strip().splitlines()[-1]), "process_s": wall}


def pyharm_available() -> bool:
    """Whether pyHarm imports in a child process."""
    return subprocess.run([sys.executable, "-c", "import pyHarm"], capture_output=True,
                          env=_child_env()).returncode == 0


def compare(n: int, directory: Path, timeout: float, nldofs: bool, structure: str = "rod"
            ) -> dict:
    """The same rod (or plate) in resonant and in pyHarm, each in a fresh process."""
    path, at = write_model(structure, directory / f"n{n}", n)
    n = _coordinates(path)
    samples = SMOOTH_SAMPLES if structure in ("plate", "grid") else SAMPLES
    row: dict = {"n": n, "structure": structure, "samples": samples, "resonant": _child(
        _fill(RESONANT_CHILD, samples), [str(path), str(n), str(at)], timeout)}
    for reductor in ("noreductor",) + (("NLdofs",) if nldofs else ()):
        side = _child(_fill(PYHARM_CHILD, samples),
                      [str(path.parent), str(n), reductor, str(at)], timeout)
        if "om" in side:
            side["folds"], side["peak"] = pyharm_extrema(side.pop("om"), side.pop("amp"))
        row["pyHarm" if reductor == "noreductor" else "pyHarm NLdofs"] = side
    ours = row["resonant"]
    for name in ("pyHarm", "pyHarm NLdofs"):
        theirs = row.get(name, {})
        if "peak" in theirs and "peak" in ours:
            # resonant's time / this side's (< 1: resonant faster)
            theirs["ratio_curve"] = ours["curve_s"] / theirs["curve_s"]
            theirs["ratio_process"] = ours["process_s"] / theirs["process_s"]
            theirs["peak_rel_diff"] = abs(theirs["peak"] / ours["peak"] - 1)
            theirs["fold_diffs"] = ([abs(a - b) for a, b in zip(ours["folds"], theirs["folds"])]
                                    if len(ours["folds"]) == len(theirs["folds"]) else None)
            theirs["agree"] = bool(theirs["peak_rel_diff"] < 1e-3
                                   and theirs["fold_diffs"] is not None
                                   and max(theirs["fold_diffs"], default=0) < 1e-3)
    return row


def _coordinates(path: Path) -> int:
    """The number of coordinates of a model written here (its M.npz)."""
    import scipy.sparse as sp

    return int(sp.load_npz(path.parent / "M.npz").shape[0])


def _side_text(side: dict) -> str:
    if "timeout" in side:
        return f"did not finish in {side['timeout']:.0f} s"
    if "error" in side:
        return "failed: " + side["error"].strip().splitlines()[-1]
    text = (f"curve {side['curve_s']:.2f} s, process {side['process_s']:.2f} s, "
            f"{side['points']} points, folds "
            + ", ".join(f"{f:.5f}" for f in side["folds"]) + f", tip peak {side['peak']:.6f}")
    if "ratio_curve" in side:
        diffs = side["fold_diffs"]
        text += (f"; resonant / this: curve {side['ratio_curve']:.3g}x, process "
                 f"{side['ratio_process']:.3g}x; peak differs by {side['peak_rel_diff']:.1e}"
                 + (f", folds by {max(diffs):.1e}" if diffs else ", folds differ in number")
                 + f" -> agree: {side['agree']}")
    return text


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default=None,
                        help="comma-separated numbers of coordinates (even; default "
                             "1000,3000,10000, none with --pyharm-sizes alone)")
    parser.add_argument("--points", type=int, default=100,
                        help="about this many continuation steps across the range")
    parser.add_argument("--json", action="store_true", help="print JSON")
    parser.add_argument("--harmonics", default=str(HARMONICS),
                        help=f"H of the sizes' runs (default {HARMONICS}; 'auto': resonant's "
                             "automatic choice, raised from 7 by the truncation)")
    parser.add_argument("--pyharm-sizes", default="",
                        help="comma-separated sizes (even) to run in both pyHarm and resonant")
    parser.add_argument("--pyharm-nldofs", action="store_true",
                        help="also run pyHarm with its NLdofs reductor")
    parser.add_argument("--structure", choices=("rod", "plate", "grid"), default="rod",
                        help="the rod (a chain with a cubic spring and a stop) or the clamped "
                             "Kirchhoff plate of benchmarks/corpus.py with a cubic spring")
    parser.add_argument("--timeout", type=float, default=900.0,
                        help="seconds allowed to each side of the comparison")
    args = parser.parse_args(argv)
    pyharm_sizes = [int(s) for s in args.pyharm_sizes.split(",") if s.strip()]
    if pyharm_sizes:
        if not pyharm_available():
            print("pyHarm is not installed (pip install pyHarm-os): no comparison")
        else:
            with tempfile.TemporaryDirectory() as tmp:
                rows = []
                for n in pyharm_sizes:
                    rows.append(compare(n, Path(tmp), args.timeout, args.pyharm_nldofs,
                                        args.structure))
                    if not args.json:
                        print(f"{args.structure}, n = {rows[-1]['n']}, H = {HARMONICS}, "
                              f"omega {START} .. {STOP}:")
                        for name in ("resonant", "pyHarm", "pyHarm NLdofs"):
                            if name in rows[-1]:
                                print(f"  {name:14s} {_side_text(rows[-1][name])}",
                                      flush=True)
            if args.json:
                print(json.dumps(rows, indent=1))
        if args.sizes is None:
            return 0
    sizes = [int(s) for s in (args.sizes or "1000,3000,10000").split(",") if s.strip()]
    with tempfile.TemporaryDirectory() as tmp:
        H = None if args.harmonics == "auto" else int(args.harmonics)
        rows = [measure(n, args.points, Path(tmp), args.structure, H) for n in sizes]
    if args.json:
        print(json.dumps(rows, indent=1))
        return 0
    print(f"{'n':>8} {'H':>3} {'total s':>8} {'CPU s':>7} {'ROM s':>7} {'ROM size':>8} "
          f"{'points':>7} {'unstable':>8} {'folds':>5} {'ms/point':>8}")
    for r in rows:
        print(f"{r['n']:>8} {r['harmonics']:>3} {r['seconds']:>8.2f} {r['cpu_seconds']:>7.2f} "
              f"{r['reduced_model_seconds']:>7.2f} "
              f"{r['reduced_size']:>8} {r['branch_points']:>7} {r['unstable_points']:>8} "
              f"{r['folds']:>5} {r['per_point_ms']:>8.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
