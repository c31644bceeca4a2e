"""Measured data: H1 of many channels against scipy.signal, LSCF against sdypy-EMA.

``python benchmarks/bench_testdata.py [--channels 64] [--samples 1000000] [--lines 4000]
[--order 40] [--repeat 3]``

* H1: one random input and ``channels`` responses of ``samples`` each (the input through
  a 3-tap filter plus noise; 8 distinct responses made once, channel k reads the
  (k mod 8)-th, so the run holds 8 channels, not 64), Hann segments of 4096 samples
  overlapping by half; both sides warmed up once (scipy.signal's import) before timing.  resonant's
  ``estimate_frf`` (the input's transform once, each response's once) against what a user
  writes with scipy: ``scipy.signal.csd`` and ``scipy.signal.welch`` per channel
  (``detrend=False``, the same numbers to 1e-10).
* LSCF: ``channels`` FRFs of ``lines`` lines written from 6 modes, the poles of every
  order 2, 4, ..., ``order``: resonant's LSCF sums and roots (``_lscf_sums``,
  ``_lscf_roots``, the stage sdypy-EMA's ``get_poles`` does) and ``identify_modes`` as a
  whole (with each order's LSFD shapes for the MAC criterion) against
  ``sdypy.EMA.Model(..., pol_order_high=order // 2).get_poles()``.

* MIMO H1 (``--only mimo``): ``inputs`` independent random inputs and ``channels``
  responses, Hann segments of 4096 overlapping by half: ``estimate_frf_matrix`` against
  what a user writes with scipy: ``scipy.signal.csd`` for every input pair and every
  input-response pair, then ``numpy.linalg.solve`` of G_xx H^T = G_xy at every line.
* The Universal File check (``--only uff``): a file of ``functions`` ASCII dataset 58
  records of ``points`` values each; ``resonant.model.uff_bounds.check_uff`` (the scan
  before pyuff) against ``read_uff`` as a whole (the check, pyuff's parsing and
  resonant's checks): what the refusal of hostile files costs a good one.

One BLAS thread (threadpoolctl) for both sides.  Reported: median times and their ratio.
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Iterator, Mapping

import numpy as np

from resonant.analyses.frf_estimate import estimate_frf
from resonant.analyses.frf_mimo import estimate_frf_matrix
from resonant.analyses.identify import _lscf_roots, _lscf_sums, identify_modes


class Channels(Mapping[str, np.ndarray]):
    """``count`` channels reading 8 distinct responses in turn (the input through a short
    filter plus noise)."""

    def __init__(self, x: np.ndarray, count: int) -> None:
        self.count = count
        self.pool = []
        for k in range(min(8, count)):
            rng = np.random.default_rng(k)
            taps = np.array([1.0, 0.5 + 0.01 * k, -0.2])
            self.pool.append(np.convolve(x, taps, mode="same")
                             + 0.1 * rng.standard_normal(len(x)))

    def __getitem__(self, key: str) -> np.ndarray:
        return self.pool[int(key[2:]) % len(self.pool)]

    def __iter__(self) -> Iterator[str]:
        return (f"ch{k}" for k in range(self.count))

    def __len__(self) -> int:
        return self.count


def bench_h1(channels: int, samples: int, repeat: int) -> str:
    from scipy import signal

    x = np.random.default_rng(0).standard_normal(samples)
    ys = Channels(x, channels)
    estimate_frf(x[:8192], {"y": x[:8192]}, 1e-3, segment=4096)       # warm up both
    signal.csd(x[:8192], x[:8192], 1000.0, "hann", 4096, 2048, detrend=False)
    ours, theirs = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        mine = estimate_frf(x, ys, 1e-3, segment=4096)
        ours.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        reference = {}
        for name, y in ys.items():
            _, gxy = signal.csd(x, y, 1000.0, "hann", 4096, 2048, detrend=False)
            _, gxx = signal.welch(x, 1000.0, "hann", 4096, 2048, detrend=False)
            reference[name] = gxy / gxx
        theirs.append(time.perf_counter() - t0)
    worst = max(float(np.max(np.abs(mine.frf[k] / reference[k] - 1))) for k in reference)
    a, b = statistics.median(ours), statistics.median(theirs)
    return (f"H1 {channels} channels x {samples} samples: resonant {a:.2f} s, scipy "
            f"csd+welch {b:.2f} s (ratio {a / b:.2f}); largest difference {worst:.1e}")


def modal_frfs(channels: int, lines: int) -> tuple[np.ndarray, np.ndarray]:
    f = np.linspace(0.0, 100.0, lines)
    fn = np.array([8.0, 17.0, 31.0, 44.0, 62.0, 80.0])
    rng = np.random.default_rng(1)
    phi = rng.standard_normal((channels, len(fn)))
    w, wr = 2 * np.pi * f[None, :, None], 2 * np.pi * fn[None, None, :]
    H = (phi[:, None, :] * phi[0][None, None, :] / (wr ** 2 - w ** 2 + 0.04j * wr * w)
         ).sum(axis=2)
    return f, H


def bench_lscf(channels: int, lines: int, order: int, repeat: int) -> str:
    f, H = modal_frfs(channels, lines)
    band = f >= 2.0
    times: dict[str, list[float]] = {"sums": [], "identify": [], "sdypy": []}
    for _ in range(repeat + 1):          # the first round warms up (imports, caches)
        t0 = time.perf_counter()
        sums = _lscf_sums(f[band], H[:, band], order)
        for n in range(2, order + 1, 2):
            _lscf_roots(sums, n)
        times["sums"].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        identify_modes(f[band], {f"p{k}": h for k, h in enumerate(H[:, band])},
                       max_order=order)
        times["identify"].append(time.perf_counter() - t0)
        try:
            from sdypy import EMA
        except ImportError:
            continue
        t0 = time.perf_counter()
        EMA.Model(frf=H, freq=f, lower=2.0, upper=100.0, pol_order_high=order // 2,
                  frf_form="receptance").get_poles(show_progress=False)
        times["sdypy"].append(time.perf_counter() - t0)
    med = {k: statistics.median(v[1:]) if len(v) > 1 else float("nan")
           for k, v in times.items()}
    return (f"LSCF {channels} FRFs x {lines} lines, orders 2..{order}: resonant poles "
            f"{med['sums']:.3f} s, identify_modes {med['identify']:.3f} s, sdypy-EMA "
            f"get_poles {med['sdypy']:.3f} s (ratio poles/sdypy "
            f"{med['sums'] / med['sdypy']:.2f})")


def bench_mimo(inputs: int, channels: int, samples: int, repeat: int) -> str:
    from scipy import signal

    rng = np.random.default_rng(0)
    xs = {f"in{i}": rng.standard_normal(samples) for i in range(inputs)}
    total = sum(xs.values())
    ys = Channels(total, channels)
    estimate_frf_matrix({"a": total[:8192]}, {"y": total[:8192]}, 1e-3, segment=4096)
    kw = dict(fs=1000.0, window="hann", nperseg=4096, noverlap=2048, detrend=False)
    ours, theirs = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        mine = estimate_frf_matrix(xs, ys, 1e-3, segment=4096)
        ours.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        names = list(xs)
        Gxx = np.array([[signal.csd(xs[a], xs[b], **kw)[1] for b in names] for a in names]
                       ).transpose(2, 0, 1)
        reference = {}
        for name, y in ys.items():
            Gxy = np.array([signal.csd(xs[a], y, **kw)[1] for a in names]).T
            reference[name] = np.linalg.solve(Gxx, Gxy[..., None])[..., 0]
        theirs.append(time.perf_counter() - t0)
    worst = max(float(np.max(np.abs(mine.H[:, r, :] / reference[n] - 1)))
                for r, n in enumerate(ys))
    a, b = statistics.median(ours), statistics.median(theirs)
    return (f"MIMO H1 {inputs} inputs, {channels} channels x {samples} samples: resonant "
            f"{a:.2f} s, scipy csd + solve {b:.2f} s (ratio {a / b:.2f}); largest "
            f"difference {worst:.1e}")


def bench_uff_check(functions: int, points: int, repeat: int) -> str:
    import os
    import tempfile

    from resonant.model.measured import MeasuredData, MeasuredFunction, read_uff, write_uff
    from resonant.model.uff_bounds import check_uff

    t = np.arange(points) * 1e-3
    data = MeasuredData("bench.uff", tuple(
        MeasuredFunction(f"a{k}", "time", t, np.sin((k + 1) * t), "s", "m/s^2", (k, 3), (0, 0))
        for k in range(functions)))
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "bench.uff")
        write_uff(path, data)
        size = os.path.getsize(path)
        checks, reads = [], []
        for _ in range(repeat):
            t0 = time.perf_counter()
            check_uff(path)
            checks.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            read_uff(path)
            reads.append(time.perf_counter() - t0)
    a, b = statistics.median(checks), statistics.median(reads)
    return (f"UFF {functions} x {points} points ({size / 2**20:.0f} MiB): check_uff {a:.3f} s, "
            f"read_uff {b:.2f} s (the check is {100 * a / b:.1f} % of the read)")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--channels", type=int, default=64)
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--lines", type=int, default=4000)
    parser.add_argument("--order", type=int, default=40)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--inputs", type=int, default=2, help="MIMO: the inputs")
    parser.add_argument("--functions", type=int, default=8, help="UFF: the records")
    parser.add_argument("--points", type=int, default=100_000, help="UFF: points a record")
    parser.add_argument("--only", choices=("h1", "lscf", "mimo", "uff"),
                        help="run one of them (default: h1 and lscf)")
    args = parser.parse_args(argv)
    from threadpoolctl import threadpool_limits

    with threadpool_limits(1):
        if args.only == "mimo":
            print(bench_mimo(args.inputs, args.channels, args.samples, args.repeat))
        elif args.only == "uff":
            print(bench_uff_check(args.functions, args.points, args.repeat))
        else:
            if args.only != "h1":
                print(bench_lscf(args.channels, args.lines, args.order, args.repeat))
            if args.only != "lscf":
                print(bench_h1(args.channels, args.samples, args.repeat))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
