"""Run every benchmark, write the markdown report and the plot.

Usage::

    python benchmarks/run.py [--quick] [--out docs/performance.md] [--only NAME ...]

``--quick`` runs tiny sizes (< 1 minute); the default run takes up to about
15 minutes on a 2-core machine.  The plot goes next to the report
(``performance.png``), the raw numbers to ``benchmarks/results/<mode>.json``.
Run from anywhere; resonant is imported from ``src/`` of this checkout.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "src"))

from common import ROOT, fit_power_law, fmt_time  # noqa: E402

BENCHMARKS = ("derivation", "sweep", "end_to_end", "memory", "reduced")

CONFIG = {
    "quick": {
        "derivation_sizes": [2, 3, 4], "derivation_skip_after": 5.0,
        "derivation_timeout": 30.0, "derivation_repeats": 1,
        "sweep_cases": [("chain", 100, 200), ("chain", 300, 200), ("nonprop", 100, 200),
                        ("dense", 50, 100), ("dense", 100, 100)],
        "dense_budget": 2.0, "sweep_repeats": 1, "matmul_size": 1000,
        "e2e_runs": 3, "memory_case": (2000, 200),
        "reduced_sizes": [30], "reduced_n_f": 200, "reduced_subset": 20,
    },
    "full": {
        "derivation_sizes": [2, 3, 5, 7, 10, 14, 20, 30, 50, 70, 100],
        "derivation_skip_after": 60.0, "derivation_timeout": 400.0,
        "derivation_repeats": 3,
        "sweep_cases": [(v, n, n_f) for v in ("chain", "nonprop")
                        for n, n_f in ((100, 500), (1000, 1000), (2000, 2000), (10000, 500))]
        + [("dense", 100, 500), ("dense", 300, 500), ("dense", 1000, 100)],
        "dense_budget": 20.0, "sweep_repeats": 3, "matmul_size": 2000,
        "e2e_runs": 7, "memory_case": (10000, 500),
        "reduced_sizes": [100, 200], "reduced_n_f": 1000, "reduced_subset": 100,
    },
}

TARGETS = {
    "derivation_ratio": 1000.0,     # resonant >= 1000x faster than Lagrange+linearize at N=20
    "derivation_n100": 10.0,        # N = 100 in <= 10 s
    "sweep_vs_best": 1.5,           # never slower than 1.5x the best hand-written solve
    "flop_fraction": 0.5,           # >= half the dense matmul FLOP rate
    "memory_mb": 500.0,             # <= 500 MB at n = 10,000
    "agreement": 1e-9,
    "e2e_ratio": 1.3,
    "reduced_time": 2.0,            # reduced-order sweep of 10,000 DOF at 1,000 frequencies
    "reduced_error": 1e-6,
}


def log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def run_derivation(cfg: dict[str, Any]) -> dict[str, Any]:
    import bench_derivation

    return bench_derivation.run(cfg["derivation_sizes"], skip_after=cfg["derivation_skip_after"],
                                timeout=cfg["derivation_timeout"],
                                repeats=cfg["derivation_repeats"], log=log)


def run_sweep(cfg: dict[str, Any]) -> dict[str, Any]:
    import bench_sweep

    flop_rate = bench_sweep.matmul_flop_rate(cfg["matmul_size"])
    log(f"  matmul {cfg['matmul_size']}^2: {flop_rate / 1e9:.1f} GFLOP/s")
    rows: list[dict[str, Any]] = []
    for variant, n, n_f in cfg["sweep_cases"]:
        fit = bench_sweep.dense_loop_fit([r for r in rows if r["variant"] == variant])
        row = bench_sweep.run_case(variant, n, n_f, repeats=cfg["sweep_repeats"],
                                   dense_budget=cfg["dense_budget"], dense_fit=fit)
        if variant == "dense" and row.get("resonant"):
            row["resonant_flop_rate"] = row["flops"] / row["resonant"]
            row["best_flop_rate"] = row["flops"] / row["best"]
        rows.append(row)
        log(f"  {variant} n={n} n_f={n_f}: resonant {fmt_time(row['resonant'])} "
            f"({row['method']}), best {fmt_time(row['best'])}, loop "
            f"{fmt_time(row['loop'], bool(row['loop_subset'] is not None))}, "
            f"agreement {row.get('agreement_best', float('nan')):.1e}")
    return {"matmul_size": cfg["matmul_size"], "matmul_flop_rate": flop_rate, "rows": rows}


def run_end_to_end(cfg: dict[str, Any]) -> dict[str, Any]:
    import bench_end_to_end

    data = bench_end_to_end.measure(cfg["e2e_runs"])
    log(f"  solve {data['solve']:.3f} s, floor {data['floor']:.3f} s, "
        f"ratio {data['ratio']:.2f}")
    data["imports"] = bench_end_to_end.import_profile()
    data["profile"] = bench_end_to_end.run_profile()
    return data


def run_memory(cfg: dict[str, Any]) -> dict[str, Any]:
    import bench_sweep

    n, n_f = cfg["memory_case"]
    try:
        peak, report = bench_sweep.peak_rss(n, n_f)
        base, _ = bench_sweep.peak_rss(n, n_f, do_sweep=False)
        method = report["method"]
    except Exception as exc:  # e.g. the sweep module is missing
        return {"n": n, "n_f": n_f, "error": f"{type(exc).__name__}: {exc}"[:300]}
    log(f"  peak RSS n={n} n_f={n_f}: {peak:.0f} MB (without the sweep {base:.0f} MB)")
    return {"n": n, "n_f": n_f, "peak_mb": peak, "baseline_mb": base, "method": method,
            "reported": report["reported"], "self_maxrss_mb": report["self_maxrss_mb"]}


def run_reduced(cfg: dict[str, Any]) -> dict[str, Any]:
    import bench_reduced

    rows = [bench_reduced.run_case(nx, cfg["reduced_n_f"], cfg["reduced_subset"], log=log)
            for nx in cfg["reduced_sizes"]]
    return {"rows": rows}


# ---------------------------------------------------------------- report


def _ratio(a: float | None, b: float | None, extrapolated: bool = False) -> str:
    if not a or not b:
        return "n/a"
    r = a / b
    text = f"{r:,.0f}x" if r >= 100 else f"{r:.3g}x"
    return f"~{text}*" if extrapolated else text


def local_exponent(points: dict[Any, dict[str, Any]], count: int = 3) -> float | None:
    """The power-law exponent through the ``count`` largest measured sizes."""
    meas = sorted((int(n), p["time"]) for n, p in points.items()
                  if not p["extrapolated"] and p.get("time"))[-count:]
    if len(meas) < 2:
        return None
    return fit_power_law([m[0] for m in meas], [m[1] for m in meas])[0]


def derivation_section(d: dict[str, Any]) -> list[str]:
    res = d["results"]
    lines = ["| N | resonant | LagrangesMethod + linearize | Lagrange / resonant | "
             "KanesMethod + linearize | Kane / resonant | both sides agree |",
             "|---:|---:|---:|---:|---:|---:|:---|"]
    for n in d["sizes"]:
        r = res["resonant"].get(n) or res["resonant"].get(str(n))
        lg = res["lagrange"].get(n) or res["lagrange"].get(str(n)) or {}
        kn = res["kane"].get(n) or res["kane"].get(str(n)) or {}
        if r is None:
            continue
        checks = []
        for name, e in (("Lagrange", lg), ("Kane", kn)):
            if "dM" in e:
                checks.append(f"{name}: {'exact, ' if e.get('symbolic_equal') else ''}"
                              f"{max(e['dM'], e['dK']):.0e}")
        lines.append(
            f"| {n} | {fmt_time(r['time'], r['extrapolated'])} | "
            f"{fmt_time(lg.get('time'), lg.get('extrapolated', False))} | "
            f"{_ratio(lg.get('time'), r['time'], lg.get('extrapolated', False))} | "
            f"{fmt_time(kn.get('time'), kn.get('extrapolated', False))} | "
            f"{_ratio(kn.get('time'), r['time'], kn.get('extrapolated', False))} | "
            f"{'; '.join(checks) or '-'} |")
    fits = d["fits"]
    lines += ["", "Fitted scaling (least squares of log t on log N over the measured sizes "
              "N >= 5): " + ", ".join(f"{k} t ~ N^{v[0]:.2f}" for k, v in fits.items()) + "; "
              "through the three largest measured sizes only: " + ", ".join(
                  f"{k} N^{local_exponent(res[k]):.2f}" for k in fits
                  if local_exponent(res[k]) is not None) + ".",
              "", "`~ ... *` = extrapolated with the fitted power law of that side (not run: "
              "the previous size exceeded the time budget). 'exact' = expand(M_resonant - "
              "M_sympy) == 0 and the same for K (N <= 5); the number is the largest relative "
              "difference of M and K at random parameter values."]
    return lines


def sweep_section(s: dict[str, Any]) -> list[str]:
    lines = ["| model | n | n_f | resonant (method) | best hand-written | resonant / best | "
             "numpy dense loop | loop / resonant | agreement vs best | agreement vs loop |",
             "|:---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in s["rows"]:
        best_name = "banded" if r["variant"] != "dense" else "zgesv loop"
        extrap = r["loop_subset"] is not None
        loop_note = "" if not extrap else (
            " (n^p fit)" if r["loop_subset"] == 0 else f" ({r['loop_subset']} freq.)")
        loop_col = "= best" if r["variant"] == "dense" else \
            fmt_time(r["loop"], extrap) + loop_note
        lines.append(
            f"| {r['variant']} | {r['n']} | {r['n_f']} | "
            f"{fmt_time(r['resonant'])} ({r['method']}) | {fmt_time(r['best'])} ({best_name}) "
            f"| {_ratio(r['resonant'], r['best'])} | {loop_col} | "
            f"{_ratio(r['loop'], r['resonant'])} | "
            f"{r.get('agreement_best', float('nan')):.1e} | "
            f"{r.get('agreement_loop', float('nan')):.1e} |".replace("nan", "-"))
    lines += ["", f"Dense matmul ({s['matmul_size']}x{s['matmul_size']} float64, same run): "
              f"**{s['matmul_flop_rate'] / 1e9:.1f} GFLOP/s**."]
    dense = [r for r in s["rows"] if r["variant"] == "dense" and r.get("resonant_flop_rate")]
    if dense:
        lines += ["", "| dense model n | n_f | resonant effective GFLOP/s | fraction of matmul | "
                  "numpy loop GFLOP/s |", "|---:|---:|---:|---:|---:|"]
        for r in dense:
            lines.append(f"| {r['n']} | {r['n_f']} | {r['resonant_flop_rate'] / 1e9:.2f} | "
                         f"{r['resonant_flop_rate'] / s['matmul_flop_rate']:.2f} | "
                         f"{r['best_flop_rate'] / 1e9:.2f} |")
        lines += ["", "Effective rate = nominal FLOPs of a complex LU per frequency, "
                  "n_f (8/3 n^3 + 8 n^2), divided by the sweep's time."]
    lines += ["", "`~ ... *` = extrapolated: the dense loop ran on the stated number of "
              "frequencies (spread over the range; its cost does not depend on the frequency) "
              "and was scaled to n_f, or, where n x n complex matrices do not fit the budget at "
              "all, its time per frequency was extrapolated with the n^p power law fitted on "
              "the smaller sizes. Agreement = max over frequencies of "
              "max_j |z_j - z_ref,j| / max_j |z_ref,j| with z = L - iN (resonant's z rebuilt "
              "from its amplitudes and phases)."]
    return lines


def target_rows(results: dict[str, Any]) -> list[str]:
    lines = ["| target | measured | met? |", "|:---|:---|:---:|"]

    def add(name: str, figure: str, ok: bool | None) -> None:
        verdict = "n/a" if ok is None else ("yes" if ok else "**no**")
        lines.append(f"| {name} | {figure} | {verdict} |")

    d = results.get("derivation")
    if d:
        res = d["results"]
        for n in (20,):
            r, lg = res["resonant"].get(n), res["lagrange"].get(n)
            if r and lg and lg.get("time"):
                ratio = lg["time"] / r["time"]
                add(f"derivation >= {TARGETS['derivation_ratio']:.0f}x faster than Lagrange + "
                    f"linearize at N = {n}",
                    f"{ratio:,.0f}x (resonant {fmt_time(r['time'])}; sympy "
                    f"{fmt_time(lg['time'], lg['extrapolated'])}"
                    f"{', extrapolated' if lg['extrapolated'] else ''})",
                    ratio >= TARGETS["derivation_ratio"])
        r = res["resonant"].get(100)
        if r:
            add("derivation N = 100 in <= 10 s",
                fmt_time(r["time"], r["extrapolated"]),
                r["time"] <= TARGETS["derivation_n100"] and not r["extrapolated"])
    s = results.get("sweep")
    if s:
        rows = [r for r in s["rows"] if r.get("resonant")]
        if rows:
            worst = max(rows, key=lambda r: r["resonant"] / r["best"])
            add("sweep never slower than 1.5x the best hand-written solve",
                f"worst {worst['resonant'] / worst['best']:.2f}x ({worst['variant']}, "
                f"n = {worst['n']}, n_f = {worst['n_f']})",
                worst["resonant"] / worst["best"] <= TARGETS["sweep_vs_best"])
            agree = max(r.get("agreement_best", 0.0) for r in rows)
            add("sweep agreement 1e-9", f"worst {agree:.1e}", agree <= TARGETS["agreement"])
        dense = [r for r in rows if r.get("resonant_flop_rate")]
        if dense:
            big = max(dense, key=lambda r: r["n"])
            frac = big["resonant_flop_rate"] / s["matmul_flop_rate"]
            add("dense sweep >= half the dense matmul FLOP rate",
                f"{frac:.2f} of matmul at n = {big['n']} "
                f"({big['resonant_flop_rate'] / 1e9:.1f} of {s['matmul_flop_rate'] / 1e9:.1f} "
                "GFLOP/s)", frac >= TARGETS["flop_fraction"])
        if not rows:
            add("sweep", "resonant.sweep not available", None)
    m = results.get("memory")
    if m:
        if "peak_mb" in m:
            add(f"peak RSS <= 500 MB at n = {m['n']:,}",
                f"{m['peak_mb']:.0f} MB (n_f = {m['n_f']}; {m['baseline_mb']:.0f} MB without "
                "the sweep)", m["peak_mb"] <= TARGETS["memory_mb"])
        else:
            add("peak RSS <= 500 MB", m["error"], None)
    r = results.get("reduced")
    if r:
        import bench_reduced

        met = bench_reduced.target(r["rows"])
        if met:
            add(f"reduced-order sweep of 10,000 DOF at 1,000 frequencies (auto) <= "
                f"{TARGETS['reduced_time']:g} s with error <= {TARGETS['reduced_error']:g}",
                met[0], met[1])
    e = results.get("end_to_end")
    if e:
        add("`resonant solve` within 1.3x of the import floor",
            f"{e['ratio']:.2f}x ({e['solve']:.2f} s vs {e['floor']:.2f} s, medians of "
            f"{e['runs']})", e["ratio"] <= TARGETS["e2e_ratio"])
    return lines


def end_to_end_section(e: dict[str, Any]) -> list[str]:
    lines = [f"Median of {e['runs']} alternating runs: `python -m resonant solve "
             f"examples/cart_pendulum.toml` **{e['solve']:.3f} s**, floor `python -c "
             f"\"import sympy, numpy, scipy.linalg\"` **{e['floor']:.3f} s**, ratio "
             f"**{e['ratio']:.2f}x**.", "",
             "Largest cumulative import times (`python -X importtime -m resonant solve ...`):",
             "", "| module | cumulative ms | self ms |", "|:---|---:|---:|"]
    for r in e["imports"][:12]:
        lines.append(f"| {'&nbsp;' * 2 * r['depth']}{r['module']} | {r['cumulative_ms']:.0f} | "
                     f"{r['self_ms']:.1f} |")
    lines += ["", "Largest cumulative times after the imports (cProfile of "
              "`resonant.cli.main(['solve', ...])`, import frames left out):", "",
              "| function | calls | cumulative s | own s |", "|:---|---:|---:|---:|"]
    for r in e["profile"][:12]:
        fn = r["function"].replace(str(ROOT) + "/", "")
        lines.append(f"| `{fn}` | {r['calls']} | {r['cumtime']:.3f} | {r['tottime']:.3f} |")
    return lines


def plot(results: dict[str, Any], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2))
    d = results.get("derivation")
    ax = axes[0]
    if d:
        styles = {"resonant": ("C0", "o"), "lagrange": ("C3", "s"), "kane": ("C1", "^")}
        labels = {"resonant": "resonant load + linearize",
                  "lagrange": "sympy LagrangesMethod + linearize",
                  "kane": "sympy KanesMethod + linearize"}
        for side, points in d["results"].items():
            color, marker = styles[side]
            meas = sorted((int(n), p["time"]) for n, p in points.items()
                          if not p["extrapolated"] and p.get("time"))
            extr = sorted((int(n), p["time"]) for n, p in points.items()
                          if p["extrapolated"] and p.get("time"))
            fit = d["fits"].get(side)
            local = local_exponent(points)
            label = labels[side] + (f"  (t ~ N^{fit[0]:.2f}; largest sizes N^{local:.2f})"
                                    if fit and local is not None else "")
            if meas:
                ax.loglog(*zip(*meas), marker=marker, color=color, label=label)
            if extr:
                xs = [meas[-1][0]] + [p[0] for p in extr] if meas else [p[0] for p in extr]
                ys = [meas[-1][1]] + [p[1] for p in extr] if meas else [p[1] for p in extr]
                ax.loglog(xs, ys, linestyle=":", color=color)
                ax.loglog(*zip(*extr), marker=marker, color=color, linestyle="none",
                          markerfacecolor="none")
        ax.set_xlabel("links N of the pendulum chain")
        ax.set_ylabel("derivation time [s]")
        ax.set_title("Derivation: symbolic M, K of the N-link pendulum\n"
                     "(hollow, dotted = extrapolated)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    s = results.get("sweep")
    ax = axes[1]
    if s:
        series = {}
        for r in s["rows"]:
            per = lambda t: t / r["n_f"]  # noqa: E731
            if r.get("resonant"):
                series.setdefault((f"resonant, {r['variant']}", False), []).append(
                    (r["n"], per(r["resonant"])))
            name = "solve_banded" if r["variant"] != "dense" else "numpy zgesv loop"
            series.setdefault((f"{name}, {r['variant']}", False), []).append(
                (r["n"], per(r["best"])))
            if r["variant"] == "chain" and r.get("loop"):
                series.setdefault(("numpy dense loop, chain", r["loop_subset"] == 0), []).append(
                    (r["n"], per(r["loop"])))
        colors = {"resonant": "C0", "solve_banded": "C2", "numpy zgesv loop": "C3",
                  "numpy dense loop": "C3"}
        markers = {"chain": "o", "nonprop": "s", "dense": "^"}
        merged: dict[str, list] = {}
        for (label, extr), pts in series.items():
            merged.setdefault(label, []).extend((n, t, extr) for n, t in pts)
        for label, pts in merged.items():
            pts.sort()
            side, variant = label.split(", ")
            xs, ys = [p[0] for p in pts], [p[1] for p in pts]
            fit = fit_power_law(xs, ys) if len(set(xs)) >= 2 else None
            ax.loglog(xs, ys, marker=markers[variant], color=colors[side],
                      linestyle="-" if side == "resonant" else "--",
                      label=label + (f"  (t ~ n^{fit[0]:.2f})" if fit else ""))
            for x, y, e in pts:
                if e:
                    ax.loglog([x], [y], marker="o", color="white", markersize=4)
        ax.set_xlabel("degrees of freedom n")
        ax.set_ylabel("time per frequency [s]")
        ax.set_title("Frequency sweep (median time / n_f)\n"
                     "(white dot = extrapolated with the n^p fit)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_report(results: dict[str, Any], out: Path, command: str) -> None:
    """The markdown report: into an existing report with :data:`HEAD_MARKER` only the
    sections between the markers, else a whole report with its own table of targets."""
    meta = results["meta"]
    head = _hand_written_head(out)
    lines = [head] if head else ["# Performance", "",
             "Benchmarks of resonant side by side with the alternatives; every number below is "
             "from one run of", "", f"    {command}", "",
             f"on {meta['machine']} ({meta['cpus']} cores, shared with other jobs: load average "
             f"{meta['load_before']} at the start, {meta['load_after']} at the end), "
             f"Python {meta['python']}, sympy {meta['sympy']}, numpy {meta['numpy']}, scipy "
             f"{meta['scipy']}, BLAS threads: {meta['threads'] or 'library default'} for every "
             f"side; {meta['date']}, {meta['seconds']:.0f} s in total. The machine "
             "is noisy: read the ratios (both sides of a ratio ran in the same run, "
             "interleaved or back to back), not the absolute times. How the benchmarks work: "
             "`benchmarks/README.md` in the repository.", "",
             "## Targets", ""] + target_rows(results)
    if not head:
        lines += ["", f"![time against size]({out.with_suffix('.png').name})", ""]
    if "derivation" in results:
        lines += ["## Derivation: N-link pendulum chain", ""] + \
            _rerun_note(meta, "derivation") + \
            derivation_section(results["derivation"]) + [""]
    if "sweep" in results:
        lines += ["## Frequency sweep", ""] + _rerun_note(meta, "sweep") + [
                  "Fixed-free spring-mass chain (masses 1, springs 1e4, C = 0.1 M + 1e-4 K, "
                  "unit force at the free end), `nonprop` = the same plus a damper c = 10 between "
                  "DOF 1 and 2, `dense` = fully coupled random M and K with the same "
                  "non-proportional damping; n_f frequencies log-spaced from 0.1 x the first to "
                  "1.5 x the highest natural frequency. resonant: `resonant.analyses.sweep.sweep(model, "
                  "'w', omegas)` on a `[matrices]` model file (`.mtx` / `.npy` files in a "
                  "temporary directory, harmonic `omega = \"w\"`), model loading not timed.",
                  ""] + sweep_section(results["sweep"]) + [""]
    if "end_to_end" in results:
        lines += ["## End to end", ""] + _rerun_note(meta, "end_to_end") + \
            end_to_end_section(results["end_to_end"]) + [""]
    if "memory" in results:
        m = results["memory"]
        lines += ["## Memory", ""]
        if "peak_mb" in m:
            lines += [f"Peak resident set size of a fresh process that builds the n = {m['n']:,} "
                      f"chain, writes and loads its model file and sweeps {m['n_f']} frequencies "
                      f"(method `{m['method']}`, amplitudes and phases of all {m['reported']:,} "
                      f"DOF): **{m['peak_mb']:.0f} MB**; the same process without the sweep: "
                      f"{m['baseline_mb']:.0f} MB. Measured as `getrusage(RUSAGE_CHILDREN)."
                      "ru_maxrss` in a minimal launcher process whose only child is the "
                      "benchmark (the child's own `RUSAGE_SELF` agrees: "
                      f"{m['self_maxrss_mb']:.0f} MB).", ""]
        else:
            lines += [f"Not measured: {m['error']}", ""]
    if "reduced" in results:
        import bench_reduced

        lines += ["## Reduced-order frequency response", ""] + \
            _rerun_note(meta, "reduced") + [bench_reduced.DESCRIPTION, ""] + \
            bench_reduced.table(results["reduced"]["rows"]) + [""]
    out.write_text("\n".join(lines) + _kept_sections(out), encoding="utf-8")


def _rerun_note(meta: dict[str, Any], name: str) -> list[str]:
    """A line saying that section ``name`` comes from a later partial run, if it does."""
    reruns = [r for r in meta.get("partial_reruns", []) if r["benchmark"] == name]
    if not reruns:
        return []
    last = reruns[-1]
    return [f"Re-measured alone on {last['date']} (load average {last['load_before']}) with "
            f"`python benchmarks/run.py --only {name} --out /tmp/x.md`, merged into "
            "`benchmarks/results/full.json`; the other sections are from the full run.", ""]


#: sections of the report below this line come from other benchmark scripts (nonlinear,
#: reduced-order, units, ...) with their own commands; a re-run keeps them as they are
KEEP_MARKER = "<!-- sections below are written by other benchmark scripts and kept by run.py -->"
#: the report above this line (its introduction and the table of every target, kept by hand
#: from all the sections) is kept as it is; run.py writes what lies between the two markers
HEAD_MARKER = "<!-- sections below, up to the next such line, are written by benchmarks/run.py -->"


def _hand_written_head(out: Path) -> str:
    """The part of an existing report up to and including :data:`HEAD_MARKER` ("" if none)."""
    try:
        old = out.read_text(encoding="utf-8")
    except OSError:
        return ""
    at = old.find(HEAD_MARKER)
    return old[:at + len(HEAD_MARKER)] + "\n" if at >= 0 else ""


def _kept_sections(out: Path) -> str:
    """The part of an existing report from :data:`KEEP_MARKER` on ("" if none)."""
    try:
        old = out.read_text(encoding="utf-8")
    except OSError:
        return ""
    at = old.find(KEEP_MARKER)
    return "\n" + old[at:] if at >= 0 else ""


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="tiny sizes, < 1 minute")
    parser.add_argument("--out", type=Path, default=None,
                        help="markdown report to write (default: docs/performance.md, or "
                             "benchmarks/results/quick.md with --quick)")
    parser.add_argument("--only", nargs="+", choices=BENCHMARKS, default=list(BENCHMARKS))
    parser.add_argument("--threads", type=int, default=1,
                        help="BLAS threads for every side (default 1; 0 = the library's "
                             "default). On a shared machine OpenBLAS's spinning threads made "
                             "small solves up to 100x slower and the ratios irreproducible.")
    parser.add_argument("--report-only", action="store_true",
                        help="re-render the report and plot from the last run's JSON "
                             "(benchmarks/results/<mode>.json) without running anything")
    args = parser.parse_args(argv)
    if args.report_only:
        return rerender("quick" if args.quick else "full", args.out)
    if args.threads > 0:
        # Before numpy is first imported here; child processes inherit the setting.
        for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
            os.environ[var] = str(args.threads)
    mode = "quick" if args.quick else "full"
    cfg = CONFIG[mode]
    out = args.out or (ROOT / "docs" / "performance.md" if mode == "full"
                       else HERE / "results" / "quick.md")
    out.parent.mkdir(parents=True, exist_ok=True)
    import numpy
    import scipy
    import sympy

    start = time.perf_counter()
    results: dict[str, Any] = {"meta": {
        "machine": f"{platform.machine()} {platform.system()}", "cpus": os.cpu_count(),
        "python": platform.python_version(), "sympy": sympy.__version__,
        "numpy": numpy.__version__, "scipy": scipy.__version__,
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "load_before": ", ".join(f"{v:.1f}" for v in os.getloadavg()),
        "threads": args.threads}}
    runners = {"derivation": run_derivation, "sweep": run_sweep,
               "end_to_end": run_end_to_end, "memory": run_memory, "reduced": run_reduced}
    for name in BENCHMARKS:
        if name in args.only:
            log(f"{name} ...")
            t0 = time.perf_counter()
            results[name] = runners[name](cfg)
            log(f"{name}: {time.perf_counter() - t0:.0f} s")
    results["meta"]["seconds"] = time.perf_counter() - start
    results["meta"]["load_after"] = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    command = "python benchmarks/run.py" + (" --quick" if args.quick else "") + \
        (f" --threads {args.threads}" if args.threads != 1 else "") + \
        (f" --out {args.out}" if args.out else "") + \
        (f" --only {' '.join(args.only)}" if set(args.only) != set(BENCHMARKS) else "")
    results["meta"]["command"] = command
    results["meta"]["out"] = os.path.relpath(out, ROOT)
    raw = HERE / "results" / f"{mode}.json"
    raw.parent.mkdir(exist_ok=True)
    raw.write_text(json.dumps(results, indent=1, default=_jsonable), encoding="utf-8")
    plot(results, out.with_suffix(".png"))
    write_report(results, out, command)
    log(f"wrote {out}, {out.with_suffix('.png')} and {raw} in {results['meta']['seconds']:.0f} s")
    return 0


def rerender(mode: str, out: Path | None) -> int:
    """Write the report and plot again from ``benchmarks/results/<mode>.json``."""
    raw = HERE / "results" / f"{mode}.json"
    results = json.loads(raw.read_text(encoding="utf-8"))
    derivation = results.get("derivation")
    if derivation:  # JSON turned the integer sizes into strings
        derivation["results"] = {side: {int(n): v for n, v in points.items()}
                                 for side, points in derivation["results"].items()}
    out = out or ROOT / results["meta"]["out"]
    plot(results, out.with_suffix(".png"))
    write_report(results, out, results["meta"]["command"])
    log(f"re-rendered {out} from {raw}")
    return 0


def _jsonable(value: Any) -> Any:
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return str(value)


if __name__ == "__main__":
    sys.exit(main())
