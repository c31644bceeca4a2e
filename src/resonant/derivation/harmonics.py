"""Harmonic decomposition of the signals: s(t) = sum_i S_i sin(w_i t) + C_i cos(w_i t).

Phases are expanded (``sin(w t + eps) = cos(eps) sin(w t) + sin(eps) cos(w t)``),
products and powers of sines and cosines are turned into sums, and a constant
part is kept as the frequency 0 (a static load).  A signal that is not a
finite sum of harmonics (``exp(-t)``, ``t*sin(t)``) has no decomposition.

Examples
--------
>>> import sympy
>>> from resonant.model import TIME as t
>>> w, eps = sympy.symbols("w eps")
>>> decompose(3*sympy.sin(w*t + eps) + 1)
{0: (0, 1), w: (3*cos(eps), 3*sin(eps))}
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy
from sympy.simplify.fu import TR8

from ..model import TIME
from .jet import Var

ZERO = sympy.Integer(0)


class NotHarmonic(ValueError):
    """The expression is not a finite sum of harmonics of t."""


def _single(factor: sympy.Expr) -> tuple[sympy.Expr, sympy.Expr, sympy.Expr] | None:
    """(w, S, C) for sin(a t + b) or cos(a t + b); None for anything else."""
    if not isinstance(factor, (sympy.sin, sympy.cos)):
        return None
    arg = factor.args[0]
    a = sympy.diff(arg, TIME)
    if a.has(TIME):
        return None
    b = sympy.expand(arg - a * TIME)
    if b.has(TIME):
        return None
    sign = 1
    if a.could_extract_minus_sign():
        a, b = -a, -b
        sign = -1 if isinstance(factor, sympy.sin) else 1
    if isinstance(factor, sympy.sin):
        return a, sign * sympy.cos(b), sign * sympy.sin(b)
    return a, -sympy.sin(b), sympy.cos(b)


#: highest power of a sine or cosine that is split into harmonics (sin^n has n/2 + 1 terms;
#: beyond this the split is slow and the signal is treated as not harmonic)
MAX_HARMONIC_POWER = 64


def _finite_harmonic_form(expr: sympy.Expr) -> bool:
    """Whether ``expr`` is built from sin/cos of arguments linear in t by sums, products and
    integer powers up to :data:`MAX_HARMONIC_POWER` (decided without expanding anything).

    Anything else that depends on t (sin of a sine, a root of a sine, exp(t), t itself
    outside a linear argument) is not a finite sum of harmonics: saying so at once avoids
    handing sympy an expansion that never ends (``sin((F0*sin(w*t))^999)``).
    """
    if not expr.has(TIME):
        return True
    if isinstance(expr, (sympy.sin, sympy.cos)):
        argument = expr.args[0]
        return not sympy.diff(argument, TIME).has(TIME)
    if isinstance(expr, (sympy.Add, sympy.Mul)):
        return all(_finite_harmonic_form(a) for a in expr.args)
    if isinstance(expr, sympy.Pow):
        base, exponent = expr.args
        return (exponent.is_Integer and 0 < int(exponent) <= MAX_HARMONIC_POWER
                and _finite_harmonic_form(base))
    return False


def decompose(expr: sympy.Expr, _depth: int = 0) -> dict[sympy.Expr, tuple[sympy.Expr, sympy.Expr]]:
    """Split a function of t into ``{w: (S, C)}``; ``w = 0`` is the constant part.

    Parameters
    ----------
    expr : sympy.Expr
        A function of :data:`resonant.model.TIME`.
    _depth : int
        Internal recursion depth.

    Returns
    -------
    dict
        w -> (S, C) with expr = sum of S sin(w t) + C cos(w t).

    Raises
    ------
    NotHarmonic
        If a term is not a constant times sin/cos of an argument linear in t.

    Examples
    --------
    >>> import sympy
    >>> from resonant.model import TIME
    >>> w = sympy.Symbol("w")
    >>> decompose(3 + 2*sympy.sin(w*TIME))
    {0: (0, 3), w: (2, 0)}
    >>> decompose(sympy.diff(sympy.Symbol("y0"), TIME))
    {}
    """
    out: dict[sympy.Expr, list[sympy.Expr]] = {}

    def add(w: sympy.Expr, s: sympy.Expr, c: sympy.Expr) -> None:
        entry = out.setdefault(w, [ZERO, ZERO])
        entry[0] += s
        entry[1] += c

    for term in sympy.Add.make_args(sympy.expand(expr)):
        if term == 0:  # the derivative of a constant signal: no harmonic at all
            continue
        coeff, dependent = term.as_independent(TIME, as_Add=False)
        if dependent == 1:
            add(ZERO, ZERO, coeff)
            continue
        single = _single(dependent)
        if single is not None:
            w, s, c = single
            if w == 0:
                add(ZERO, ZERO, coeff * c)
            else:
                add(w, coeff * s, coeff * c)
            continue
        if not _finite_harmonic_form(dependent):
            raise NotHarmonic(str(term))
        rewritten = TR8(dependent) if _depth < 3 else dependent
        if rewritten == dependent:
            raise NotHarmonic(str(term))
        for w, (s, c) in decompose(coeff * rewritten, _depth + 1).items():
            add(w, s, c)
    return {w: (s, c) for w, (s, c) in out.items() if s != 0 or c != 0}


@dataclass(frozen=True)
class SignalHarmonics:
    """The decomposition of every signal derivative that enters the model.

    Parameters
    ----------
    parts : mapping
        ``parts[(signal, order)][w] = (S, C)``.

    Examples
    --------
    >>> import sympy
    >>> w = sympy.Symbol("w")
    >>> SignalHarmonics({("r", 0): {w: (sympy.Integer(1), sympy.Integer(0))}}).frequencies
    (w,)
    """

    parts: Mapping[Var, Mapping[sympy.Expr, tuple[sympy.Expr, sympy.Expr]]]

    @property
    def frequencies(self) -> tuple[sympy.Expr, ...]:
        seen: dict[sympy.Expr, None] = {}
        for per_w in self.parts.values():
            for w in per_w:
                seen.setdefault(w, None)
        return tuple(sorted(seen, key=sympy.default_sort_key))

    def forcing(self, columns: Mapping[Var, sympy.MatrixBase], w: sympy.Expr
                ) -> tuple[sympy.Matrix, sympy.Matrix]:
        """F_S, F_C at frequency w for Q = sum of column * signal derivative."""
        n = next(iter(columns.values())).rows if columns else 0
        f_s, f_c = sympy.zeros(n, 1), sympy.zeros(n, 1)
        for var, column in columns.items():
            s, c = self.parts.get(var, {}).get(w, (ZERO, ZERO))
            if s != 0:
                f_s += column * s
            if c != 0:
                f_c += column * c
        return f_s, f_c


def decompose_signals(functions: Mapping[Var, sympy.Expr]) -> SignalHarmonics | None:
    """Decompose each signal derivative; None when one of them is not harmonic.

    Parameters
    ----------
    functions : mapping
        ``(signal, order)`` -> its function of t.

    Returns
    -------
    SignalHarmonics or None
        The decompositions, or None if one is not a sum of harmonics.

    Examples
    --------
    >>> import sympy
    >>> from resonant.model import TIME
    >>> decompose_signals({("r", 0): sympy.exp(-TIME)}) is None
    True
    """
    parts = {}
    try:
        for var, expr in functions.items():
            parts[var] = decompose(expr)
    except NotHarmonic:
        return None
    return SignalHarmonics(parts)


__all__ = ["decompose", "decompose_signals", "SignalHarmonics", "NotHarmonic"]
