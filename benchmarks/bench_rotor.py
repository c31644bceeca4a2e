"""Benchmark: a rotor's Campbell diagram, resonant against ROSS's ``run_campbell``
(docs/performance.md, Rotors).

The model: a steel shaft (E 211 GPa, rho 7810 kg/m^3, G 81.2 GPa), 50 mm in diameter and
1.5 m long, in ``elements`` equal Timoshenko elements, two discs (Friswell et al. 2010,
Example 5.9.1: 70 mm thick, 280 and 350 mm in diameter) at a third and two thirds of its
length, isotropic bearings of 1 MN/m at both ends: Example 5.9.1 refined.  249 elements
are 250 stations, 1,000 lateral coordinates in resonant (ROSS adds the axial and
torsional ones: 1,500).

Sides, each in this process, one BLAS thread (the caller sets OMP_NUM_THREADS=1
OPENBLAS_NUM_THREADS=1):

``resonant``
    ``campbell(system, speeds, modes=K)`` on the ``[rotor]`` model (loading not timed):
    the modes at every speed by shift-invert Arnoldi, tracked by MAC with refinement,
    the 1x critical speeds and the threshold by Brent's method;
``ross``
    ``Rotor.run_campbell(speeds, frequencies=K)`` (ross-rotordynamics, optional: skipped
    when it does not import).

The frequencies of both at the highest speed are compared (each resonant branch against
the nearest ROSS frequency; ROSS's axial/torsional modes are left over).

``--one-speed`` (the sparse kernel against the dense route at one speed): the lowest
``modes`` complex modes at the top speed by ``resonant.modal.lowest_gyroscopic_modes``
(the sparse [rotor] assembly, shift-invert Arnoldi) and, up to ``--dense-max``
coordinates, by ``resonant.modal.gyroscopic_modes`` on the same matrices as dense arrays
(the whole state matrix's eigenvalues: what a user without a sparse eigensolver runs),
with the largest relative difference of the frequencies.  At 10^4 coordinates the dense
route (a 20,000 x 20,000 state matrix, 3.2 GB) and ROSS (whose state matrix is dense
too) are not run.

Examples
--------
>>> text = rotor_toml(6)
>>> "count = 6" in text
True
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))


def rotor_toml(elements: int, cross: float = 0.0) -> str:
    """The benchmark's rotor as a ``[rotor]`` model of ``elements`` shaft elements
    (a multiple of 3 puts the discs on stations); ``cross`` > 0 gives both bearings a
    cross-coupled stiffness kxy = -kyx = cross x Omega and a direct damping of 400 N s/m
    (a fluid film's destabilizing force: a threshold of instability)."""
    first, second = elements // 3, 2 * elements // 3
    film = (f'kxy = "{cross}*Omega"\nkyx = "-{cross}*Omega"\ncxx = 400\ncyy = 400\n'
            if cross > 0 else "")
    return f"""
title = "Example 5.9.1 refined: {elements} elements"
[parameters]
Omega = 0
[rotor]
speed = "Omega"
E = 211e9
rho = 7810
G = 81.2e9
[[rotor.shaft]]
length = 1.5
diameter = 0.05
count = {elements}
[[rotor.disc]]
station = {first}
name = "disc1"
width = 0.07
diameter = 0.28
inner_diameter = 0.05
[[rotor.disc]]
station = {second}
name = "disc2"
width = 0.07
diameter = 0.35
inner_diameter = 0.05
[[rotor.bearing]]
station = 0
kxx = 1e6
kyy = 1e6
{film}[[rotor.bearing]]
station = {elements}
kxx = 1e6
kyy = 1e6
{film}"""


def run_resonant(elements: int, speeds: np.ndarray, modes: int, cross: float = 0.0
                 ) -> tuple[float, float, np.ndarray, dict]:
    from resonant.analyses.campbell import campbell
    from resonant.model import loads
    from resonant.system import linear_system

    system = linear_system(loads(rotor_toml(elements, cross)))
    start, cpu = time.perf_counter(), time.process_time()
    result = campbell(system, speeds, modes=modes)
    return time.perf_counter() - start, time.process_time() - cpu, result.frequencies[-1], \
        result.threshold.to_dict()


def run_ross(elements: int, speeds: np.ndarray, modes: int
             ) -> tuple[float, float, np.ndarray] | None:
    try:
        import ross as rs
    except Exception:  # noqa: BLE001 - an optional library that may fail to import
        return None
    L = 1.5 / elements
    shaft = [rs.ShaftElement(L=L, material=rs.materials.steel, n=i, idl=0, odl=0.05)
             for i in range(elements)]
    discs = [rs.DiskElement.from_geometry(n=n, material=rs.materials.steel, width=0.07,
                                          i_d=0.05, o_d=d)
             for n, d in ((elements // 3, 0.28), (2 * elements // 3, 0.35))]
    bearings = [rs.BearingElement(n=n, kxx=1e6, kyy=1e6, cxx=0, cyy=0) for n in (0, elements)]
    rotor = rs.Rotor(shaft, discs, bearings)
    start, cpu = time.perf_counter(), time.process_time()
    result = rotor.run_campbell(speeds, frequencies=modes + 4)
    return time.perf_counter() - start, time.process_time() - cpu, np.asarray(result.wd)[-1]


def run_one_speed(elements: int, speed: float, modes: int, dense_max: int) -> dict:
    """The sparse kernel and (up to ``dense_max`` coordinates) the dense one at one speed."""
    from resonant.modal import gyroscopic_modes, lowest_gyroscopic_modes
    from resonant.model import loads
    from resonant.system import linear_system

    point = linear_system(loads(rotor_toml(elements))).numeric(Omega=speed)
    start, cpu = time.perf_counter(), time.process_time()
    s, _ = lowest_gyroscopic_modes(point.M, point.C, point.K, modes)
    report = {"coordinates": point.n, "modes": modes, "speed_rad_s": speed,
              "sparse_s": time.perf_counter() - start, "sparse_cpu_s": time.process_time() - cpu,
              "frequencies": np.abs(s.imag).tolist()}
    if point.n <= dense_max:
        start, cpu = time.perf_counter(), time.process_time()
        dense, _ = gyroscopic_modes(point.M, point.C, point.K)
        report.update({"dense_s": time.perf_counter() - start,
                       "dense_cpu_s": time.process_time() - cpu,
                       "largest_relative_difference": float(np.max(np.abs(
                           np.abs(dense[:modes].imag) - np.abs(s.imag)) / np.abs(s.imag)))})
        report["ratio"] = report["dense_s"] / report["sparse_s"]
        report["cpu_ratio"] = report["dense_cpu_s"] / report["sparse_cpu_s"]
    return report


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--elements", type=int, default=249)
    parser.add_argument("--speeds", type=int, default=200)
    parser.add_argument("--modes", type=int, default=8)
    parser.add_argument("--top", type=float, default=4000 * np.pi / 30)
    parser.add_argument("--one-speed", action="store_true",
                        help="the sparse kernel against the dense route at the top speed")
    parser.add_argument("--dense-max", type=int, default=2500)
    parser.add_argument("--no-ross", action="store_true")
    parser.add_argument("--cross", type=float, default=0.0,
                        help="cross-coupled bearing stiffness per rad/s (a threshold)")
    args = parser.parse_args()
    if args.one_speed:
        print(json.dumps(run_one_speed(args.elements, args.top, args.modes, args.dense_max),
                         indent=2))
        return
    speeds = np.linspace(0.0, args.top, args.speeds)
    ours, ours_cpu, frequencies, threshold = run_resonant(args.elements, speeds, args.modes,
                                                          args.cross)
    report = {"elements": args.elements, "coordinates": 4 * (args.elements + 1),
              "speeds": args.speeds, "modes": args.modes, "resonant_s": ours,
              "resonant_cpu_s": ours_cpu,
              "resonant_frequencies": frequencies.tolist(), "threshold": threshold}
    print(json.dumps(report), file=sys.stderr, flush=True)   # before ROSS's long run
    theirs = None if args.no_ross or args.cross else run_ross(args.elements, speeds,
                                                              args.modes)
    if theirs is not None:
        seconds, cpu, ross_wd = theirs
        nearest = np.array([ross_wd[np.argmin(np.abs(ross_wd - f))] for f in frequencies])
        report.update({"ross_s": seconds, "ross_cpu_s": cpu, "ratio": seconds / ours,
                       "cpu_ratio": cpu / ours_cpu,
                       "largest_relative_difference": float(np.max(np.abs(
                           nearest - frequencies) / frequencies))})
    else:
        report["ross"] = "not run (--no-ross)" if args.no_ross else \
            "not installed (or does not import)"
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
