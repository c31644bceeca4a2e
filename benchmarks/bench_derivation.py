"""Benchmark 1: derivation scaling of the N-link pendulum chain.

resonant (``resonant.load(path).linearize()`` -> ``.M``, ``.K``) against
sympy.physics.mechanics ``LagrangesMethod`` + ``linearize`` and
``KanesMethod`` + ``linearize`` on the same system (see
:mod:`sympy_chain`).  Every measurement runs in a fresh process (sympy's
global cache would otherwise let a later run profit from an earlier one) and
the time covers the derivation only, not the interpreter's start or the
imports.  The child also returns M and K evaluated at random parameter values
(and, for small N, the symbolic matrices), so the parent can assert that both
sides agree.

Examples
--------
>>> values = parameter_point(2)
>>> sorted(values)
['g', 'l1', 'l2', 'm1', 'm2']
"""

from __future__ import annotations

import argparse
import json
import random
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import extrapolate, fit_power_law, run_child  # noqa: E402

SIDES = ("resonant", "lagrange", "kane")
#: sizes up to which the symbolic matrices are compared exactly (expand(difference) == 0)
SYMBOLIC_CHECK_UP_TO = 5
#: numeric agreement required at random parameter values (relative to max |entry|)
NUMERIC_TOLERANCE = 1e-12


def parameter_point(n: int, seed: int = 2024) -> dict[str, float]:
    """Random but reproducible values of g, m1..mN, l1..lN."""
    rng = random.Random(seed + n)
    values = {"g": rng.uniform(5.0, 15.0)}
    for i in range(1, n + 1):
        values[f"m{i}"] = rng.uniform(0.5, 2.0)
        values[f"l{i}"] = rng.uniform(0.3, 1.5)
    return values


def derive(side: str, n: int, warm_up: bool = True) -> tuple[float, Any, Any]:
    """(seconds, M, K) of one side; the time covers the derivation only.

    With ``warm_up``, the 1-link chain is derived first (untimed), so that the
    modules either side imports lazily on first use are loaded before the
    clock starts: the benchmark compares derivations, not imports.
    """
    if warm_up:
        derive(side, 1, warm_up=False)
    if side == "resonant":
        import tempfile

        import resonant
        from pendulum_chain import write_pendulum_chain

        with tempfile.TemporaryDirectory() as tmp:
            path = write_pendulum_chain(n, tmp)
            start = time.perf_counter()
            eom = resonant.load(path).linearize()
            M, K = eom.M, eom.K
            elapsed = time.perf_counter() - start
        return elapsed, M, K
    from sympy_chain import sympy_chain_matrices

    start = time.perf_counter()
    M, K = sympy_chain_matrices(n, side)
    return time.perf_counter() - start, M, K


def child(side: str, n: int) -> dict[str, Any]:
    """Run in a fresh process: derive, then evaluate at the parameter point."""
    import sympy

    elapsed, M, K = derive(side, n)
    # Compare by symbol *name*: the two sides may attach different assumptions.
    plain = {s: sympy.Symbol(s.name) for s in (M.free_symbols | K.free_symbols)}
    M, K = sympy.ImmutableMatrix(M).xreplace(plain), sympy.ImmutableMatrix(K).xreplace(plain)
    subs = {sympy.Symbol(k): sympy.Float(v, 30) for k, v in parameter_point(n).items()}

    def numeric(matrix: Any) -> list[list[float]]:
        return [[float(matrix[i, j].xreplace(subs)) for j in range(n)] for i in range(n)]

    out = {"side": side, "n": n, "time": elapsed, "M": numeric(M), "K": numeric(K)}
    if n <= SYMBOLIC_CHECK_UP_TO:
        out["M_srepr"], out["K_srepr"] = sympy.srepr(M), sympy.srepr(K)
    return out


def numeric_difference(a: list[list[float]], b: list[list[float]]) -> float:
    """max |a - b| / max |b| over all entries."""
    scale = max(abs(v) for row in b for v in row)
    return max(abs(x - y) for ra, rb in zip(a, b) for x, y in zip(ra, rb)) / scale


def symbolic_equal(a: str, b: str) -> bool:
    """Exact equality of two matrices given as srepr text (our own children's output)."""
    import sympy

    difference = sympy.sympify(a) - sympy.sympify(b)
    return all(sympy.expand(e) == 0 or sympy.simplify(e) == 0 for e in difference)


def run(sizes: list[int], *, skip_after: float = 60.0, timeout: float = 240.0,
        sides: tuple[str, ...] = SIDES, repeat_below: float = 2.0, repeats: int = 3,
        log: Any = print) -> dict[str, Any]:
    """Time every side at every size (within budget), check agreement, fit exponents.

    A side stops growing after a size that took longer than ``skip_after``
    seconds, or when its power law (fitted so far) predicts more than
    ``skip_after`` for the next size; the remaining sizes are extrapolated
    and marked so.  A derivation faster than ``repeat_below`` seconds is run
    ``repeats`` times (fresh processes) and the median kept.
    """
    results: dict[str, dict[int, dict[str, Any]]] = {s: {} for s in sides}
    reference: dict[int, dict[str, Any]] = {}
    for side in sides:
        stopped = False
        for n in sizes:
            measured = {k: v for k, v in results[side].items() if not v["extrapolated"]}
            if not stopped and len(measured) >= 3:
                fit = _fit(measured)
                if extrapolate(fit, n) > skip_after:
                    stopped = True
            if stopped:
                fit = _fit(measured)
                results[side][n] = {"time": extrapolate(fit, n), "extrapolated": True}
                continue
            data = run_child([__file__, "--child", side, str(n)], timeout)
            if data is None:
                log(f"  {side} N={n}: timed out after {timeout:.0f} s")
                stopped = True
                fit = _fit(measured) if len(measured) >= 2 else None
                results[side][n] = {"time": extrapolate(fit, n) if fit else None,
                                    "extrapolated": True, "timed_out": timeout}
                continue
            times = [data["time"]]
            while times[-1] < repeat_below and len(times) < repeats:
                times.append(run_child([__file__, "--child", side, str(n)], timeout)["time"])
            entry = {"time": sorted(times)[len(times) // 2], "times": times,
                     "extrapolated": False}
            if side == sides[0]:
                reference[n] = data
            else:
                ref = reference.get(n)
                if ref is not None:
                    entry["dM"] = numeric_difference(data["M"], ref["M"])
                    entry["dK"] = numeric_difference(data["K"], ref["K"])
                    if "M_srepr" in data and "M_srepr" in ref:
                        entry["symbolic_equal"] = (
                            symbolic_equal(data["M_srepr"], ref["M_srepr"])
                            and symbolic_equal(data["K_srepr"], ref["K_srepr"]))
                    if max(entry["dM"], entry["dK"]) > NUMERIC_TOLERANCE or \
                            entry.get("symbolic_equal") is False:
                        raise AssertionError(
                            f"{side} and {sides[0]} disagree at N = {n}: "
                            f"dM = {entry['dM']:.3g}, dK = {entry['dK']:.3g}, "
                            f"symbolic equal: {entry.get('symbolic_equal')}")
            results[side][n] = entry
            log(f"  {side} N={n}: {entry['time']:.3g} s"
                + (f" (agree: dM={entry['dM']:.1e} dK={entry['dK']:.1e}"
                   f"{', symbolic ok' if entry.get('symbolic_equal') else ''})"
                   if "dM" in entry else ""))
            if entry["time"] > skip_after:
                stopped = True
    fits = {}
    for side in sides:
        measured = {k: v for k, v in results[side].items() if not v["extrapolated"]}
        if len(measured) >= 2:
            fits[side] = _fit(measured)
    return {"sizes": sizes, "results": results, "fits": fits}


def _fit(measured: dict[int, dict[str, Any]]) -> tuple[float, float]:
    """Power law through the measured points; the smallest sizes (start-up bound) are left
    out when enough larger ones exist, so the exponent describes the growth."""
    sizes = sorted(measured)
    use = [n for n in sizes if n >= 5] if len([n for n in sizes if n >= 5]) >= 2 else sizes
    return fit_power_law(use, [measured[n]["time"] for n in use])


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--child", nargs=2, metavar=("SIDE", "N"))
    parser.add_argument("--sizes", default="2,3,5")
    args = parser.parse_args()
    if args.child:
        side, n = args.child
        print(json.dumps(child(side, int(n))))
    else:
        summary = run([int(s) for s in args.sizes.split(",")])
        print(json.dumps({k: v for k, v in summary.items()}, default=str, indent=1))
