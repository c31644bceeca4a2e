"""Second-order Taylor jets: the arithmetic behind the linearization.

A :class:`Jet` is a polynomial of degree at most two in the *small
quantities* of a model (coordinate deviations, their rates, signals and their
rates), with symbolic coefficients (expressions of the parameters, in sympy or, for
large models, symengine — see :class:`Backend`)::

    c + sum_a lin[a] z_a + sum_{a <= b} quad[a, b] z_a z_b

Evaluating T, U, D and the forces as jets gives their second-order expansion
directly, without ever forming the full nonlinear expressions. Lagrange's
operator applied to a jet of degree two is exact to first order, which is
all the linearized equation of motion needs.

A small quantity is named by a pair ``(name, order)``: ``("x1", 0)`` is the
deviation of coordinate ``x1``, ``("x1", 1)`` its rate, ``("r", 2)`` the
second derivative of signal ``r``.

Examples
--------
>>> x = Jet.variable(("x", 0))
>>> j = (x * x + x * 3).apply("cos")
>>> j.const, j.lin, j.quad
(1, {}, {(('x', 0), ('x', 0)): -9/2})
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import sympy
from sympy.core.add import _addsort
from sympy.core.mul import _mulsort

from ..expressions.functions import SYMPY as SYMPY_CONSTRUCTORS

Var = tuple[str, int]
Coefficient = Any  # a sympy or symengine expression (or a Python int)

#: sympy constructors of the model language's functions
SYMPY_FUNCTIONS: Mapping[str, Callable[..., Any]] = SYMPY_CONSTRUCTORS


@dataclass(frozen=True)
class Backend:
    """The computer algebra system that does a jet's coefficient arithmetic.

    sympy for small models (nothing more to import), symengine for large
    ones (its arithmetic is an order of magnitude faster); the results are
    sympy either way.
    """

    name: str
    module: Any
    functions: Mapping[str, Callable[..., Any]]
    basic: type[Any]
    _derivatives: dict = field(default_factory=dict, compare=False, repr=False)

    def symbol(self, name: str) -> Any:
        return self.module.Symbol(name)

    def rational(self, numerator: int, denominator: int) -> Any:
        return self.module.Rational(numerator, denominator)

    @property
    def pi(self) -> Any:
        return self.module.pi

    def derivatives(self, func: str) -> tuple[Any, Any, Any]:
        """(u, f'(u), f''(u)) for a one-argument function, computed once."""
        if func not in self._derivatives:
            u = self.module.Symbol("_jet_u")
            d1 = self.module.diff(self.functions[func](u), u)
            self._derivatives[func] = (u, d1, self.module.diff(d1, u))
        return self._derivatives[func]

    def is_bad(self, value: Any) -> bool:
        """True for infinities and NaN (a function evaluated at a singularity)."""
        m = self.module
        return isinstance(value, self.basic) and any(
            value.has(x) for x in (m.zoo, m.nan, m.oo))

    def to_sympy(self, value: Any, cache: dict | None = None) -> sympy.Expr:
        if self.name == "sympy":
            return sympy.sympify(value)
        return to_sympy(value, cache)

    def add(self, terms: list[Any]) -> Any:
        """The sum of many terms, built at once (pairwise sums cost O(size) each)."""
        return terms[0] if len(terms) == 1 else self.module.Add(*terms)

    def from_sympy(self, value: sympy.Expr) -> Any:
        """Convert a sympy expression built by resonant (never user text)."""
        return value if self.name == "sympy" else self.module.sympify(value)


SYMPY = Backend("sympy", sympy, SYMPY_FUNCTIONS, sympy.Basic)
_BACKENDS: dict[str, Backend] = {"sympy": SYMPY}


def backend(name: str) -> Backend:
    """The backend called ``"sympy"`` or ``"symengine"`` (imported on first use)."""
    if name not in _BACKENDS:
        import symengine

        constructors = {n: getattr(symengine, n) for n in SYMPY_CONSTRUCTORS}
        _BACKENDS[name] = Backend("symengine", symengine, constructors, symengine.Basic)
    return _BACKENDS[name]


def _key(a: Var, b: Var) -> tuple[Var, Var]:
    return (a, b) if a <= b else (b, a)


def _nonzero(c: Coefficient) -> bool:
    return not (c == 0)


class NotDifferentiable(ValueError):
    """The expression has no Taylor expansion at the reference state."""


class Jet:
    """A polynomial of degree <= 2 in small quantities, truncated on multiplication."""

    __slots__ = ("const", "lin", "quad")

    def __init__(self, const: Coefficient = 0,
                 lin: Mapping[Var, Coefficient] | None = None,
                 quad: Mapping[tuple[Var, Var], Coefficient] | None = None) -> None:
        self.const = const
        self.lin: dict[Var, Coefficient] = dict(lin) if lin else {}
        self.quad: dict[tuple[Var, Var], Coefficient] = dict(quad) if quad else {}

    # -- construction -------------------------------------------------------
    @classmethod
    def constant(cls, value: Coefficient) -> Jet:
        return cls(value)

    @classmethod
    def variable(cls, var: Var, offset: Coefficient = 0) -> Jet:
        return cls(offset, {var: 1})

    def is_constant(self) -> bool:
        return not self.lin and not self.quad

    def degree(self) -> int:
        return 2 if self.quad else (1 if self.lin else 0)

    def variables(self) -> set[Var]:
        out = set(self.lin)
        for a, b in self.quad:
            out.add(a)
            out.add(b)
        return out

    def __repr__(self) -> str:
        return f"Jet({self.const!r}, {self.lin!r}, {self.quad!r})"

    # -- linear operations --------------------------------------------------
    @staticmethod
    def _merge(x: dict, y: Mapping, sign: int = 1) -> dict:
        out = dict(x)
        for k, v in y.items():
            v = v if sign > 0 else -v
            out[k] = out[k] + v if k in out else v
        return {k: v for k, v in out.items() if _nonzero(v)}

    def __add__(self, other: Jet) -> Jet:
        return Jet(self.const + other.const, self._merge(self.lin, other.lin),
                   self._merge(self.quad, other.quad))

    def __sub__(self, other: Jet) -> Jet:
        return Jet(self.const - other.const, self._merge(self.lin, other.lin, -1),
                   self._merge(self.quad, other.quad, -1))

    def __neg__(self) -> Jet:
        return Jet(-self.const, {k: -v for k, v in self.lin.items()},
                   {k: -v for k, v in self.quad.items()})

    @staticmethod
    def sum(jets: list[Jet], backend: Backend = SYMPY) -> Jet:
        """The sum of many jets, each coefficient built once from all its terms."""
        if len(jets) == 1:
            return jets[0]
        lin: dict[Var, list] = {}
        quad: dict[tuple[Var, Var], list] = {}
        for jet in jets:
            for k, v in jet.lin.items():
                lin.setdefault(k, []).append(v)
            for kq, v in jet.quad.items():
                quad.setdefault(kq, []).append(v)
        add = backend.add
        consts = [j.const for j in jets if _nonzero(j.const)]
        return Jet(add(consts) if consts else 0,
                   {k: c for k, v in lin.items() if _nonzero(c := add(v))},
                   {k: c for k, v in quad.items() if _nonzero(c := add(v))})

    def scale(self, factor: Coefficient) -> Jet:
        if factor == 0:
            return Jet()
        return Jet(self.const * factor, {k: v * factor for k, v in self.lin.items()},
                   {k: v * factor for k, v in self.quad.items()})

    # -- products and functions ---------------------------------------------
    def __mul__(self, other: Jet | Coefficient) -> Jet:
        if not isinstance(other, Jet):
            return self.scale(other)
        if other.is_constant():
            return self.scale(other.const)
        if self.is_constant():
            return other.scale(self.const)
        c1, c2 = self.const, other.const
        lin: dict[Var, Coefficient] = {}
        if _nonzero(c2):
            lin = {k: v * c2 for k, v in self.lin.items()}
        if _nonzero(c1):
            for k, v in other.lin.items():
                lin[k] = lin[k] + c1 * v if k in lin else c1 * v
        quad: dict[tuple[Var, Var], Coefficient] = {}
        if _nonzero(c2):
            quad = {k: v * c2 for k, v in self.quad.items()}
        if _nonzero(c1):
            for kq, v in other.quad.items():
                quad[kq] = quad[kq] + c1 * v if kq in quad else c1 * v
        for a, va in self.lin.items():
            for b, vb in other.lin.items():
                kq = _key(a, b)
                quad[kq] = quad[kq] + va * vb if kq in quad else va * vb
        return Jet(c1 * c2, {k: v for k, v in lin.items() if _nonzero(v)},
                   {k: v for k, v in quad.items() if _nonzero(v)})

    __rmul__ = __mul__

    def _compose(self, f0: Coefficient, f1: Coefficient, f2: Coefficient) -> Jet:
        """f(c + d) ~ f0 + f1 d + f2/2 d^2 with d = self - c."""
        delta = Jet(0, self.lin, self.quad)
        out = delta.scale(f1)
        if self.lin and _nonzero(f2):
            sq = Jet(0, self.lin) * Jet(0, self.lin)
            out = out + sq.scale(f2 / 2)
        return Jet(f0) + out

    def apply(self, func: str, backend: Backend = SYMPY) -> Jet:
        """The jet of ``func(self)`` for a one-argument function of the model language."""
        f0 = backend.functions[func](self.const)
        if self.is_constant():
            return Jet(f0)
        u, d1, d2 = backend.derivatives(func)
        f1 = d1.subs({u: self.const})
        f2 = d2.subs({u: self.const}) if self.lin else 0
        if any(backend.is_bad(v) for v in (f0, f1, f2)):
            raise NotDifferentiable(f"{func}() is not differentiable at the reference state")
        return self._compose(f0, f1, f2)

    def atan2(self, x: Jet, backend: Backend = SYMPY) -> Jet:
        """The jet of ``atan2(self, x)`` (self is the y argument)."""
        y0, x0 = self.const, x.const
        f0 = backend.functions["atan2"](y0, x0)
        if self.is_constant() and x.is_constant():
            return Jet(f0)
        r2 = x0**2 + y0**2
        if r2 == 0:
            raise NotDifferentiable("atan2(0, 0) has no expansion at the reference state")
        dy, dx = Jet(0, self.lin, self.quad), Jet(0, x.lin, x.quad)
        first = dy.scale(x0 / r2) - dx.scale(y0 / r2)
        ly, lx = Jet(0, self.lin), Jet(0, x.lin)
        # Hessian of atan2(y, x): f_yy = -2xy/r^4, f_xx = 2xy/r^4, f_xy = (y^2-x^2)/r^4
        r4 = r2**2
        second = ((ly * ly).scale(-x0 * y0 / r4) + (lx * lx).scale(x0 * y0 / r4)
                  + (ly * lx).scale((y0**2 - x0**2) / r4))
        return Jet(f0) + first + second

    def reciprocal(self) -> Jet:
        c = self.const
        if c == 0:
            raise NotDifferentiable("division by a quantity that is zero at the reference state")
        if self.is_constant():
            return Jet(1 / c)
        return self._compose(1 / c, -1 / c**2, 2 / c**3)

    def __truediv__(self, other: Jet) -> Jet:
        if other.is_constant():
            if other.const == 0:
                raise NotDifferentiable("division by zero")
            return self.scale(1 / other.const)
        return self * other.reciprocal()

    def __pow__(self, exponent: Jet) -> Jet:
        if not exponent.is_constant():
            raise NotDifferentiable("a power whose exponent varies with the motion; write it "
                                    "as exp(b*log(a))")
        b = exponent.const
        if self.is_constant():
            return Jet(self.const**b)
        if isinstance(b, int) or getattr(b, "is_Integer", False):
            n = int(b)
            if n == 0:
                return Jet(1)
            base = self if n > 0 else self.reciprocal()
            return _integer_power(base, abs(n))
        c = self.const
        if c == 0:
            raise NotDifferentiable(
                f"a power with exponent {b} of a quantity that is zero at the reference state")
        return self._compose(c**b, b * c**(b - 1), b * (b - 1) * c**(b - 2))

    # -- calculus -------------------------------------------------------------
    def diff(self, var: Var) -> Jet:
        """Partial derivative with respect to a small quantity (degree drops by one)."""
        const = self.lin.get(var, 0)
        lin: dict[Var, Coefficient] = {}
        for (a, b), v in self.quad.items():
            if a == var and b == var:
                lin[a] = lin.get(a, 0) + 2 * v
            elif a == var:
                lin[b] = lin.get(b, 0) + v
            elif b == var:
                lin[a] = lin.get(a, 0) + v
        return Jet(const, {k: v for k, v in lin.items() if _nonzero(v)})

    def dt(self) -> Jet:
        """Total time derivative: each small quantity (name, k) becomes (name, k+1).

        Exact to degree two because the coefficients do not depend on time
        (everything that moves is a declared signal).
        """
        lin = {(n, k + 1): v for (n, k), v in self.lin.items()}
        quad: dict[tuple[Var, Var], Coefficient] = {}
        for (a, b), v in self.quad.items():
            for key in (_key((a[0], a[1] + 1), b), _key(a, (b[0], b[1] + 1))):
                quad[key] = quad[key] + v if key in quad else v
        return Jet(0, lin, {k: v for k, v in quad.items() if _nonzero(v)})

    def truncate(self, degree: int) -> Jet:
        if degree >= 2:
            return self
        if degree == 1:
            return Jet(self.const, self.lin)
        return Jet(self.const)


def _integer_power(base: Jet, n: int) -> Jet:
    result = Jet(1)
    square = base
    while n:
        if n & 1:
            result = result * square
        n >>= 1
        if n:
            square = square * square
    return result


CANONICAL_SORT_LIMIT = 12


def to_sympy(value: Coefficient, cache: dict | None = None) -> sympy.Expr:
    """Convert a symengine coefficient to sympy (model symbols carry no assumptions).

    symengine's result is already canonical (like terms combined), so sums
    and products are rebuilt without sympy's costly re-flattening; this is
    what keeps a 100-coordinate derivation within seconds.

    Examples
    --------
    >>> se = backend("symengine")
    >>> a = se.symbol("a")
    >>> to_sympy(se.rational(1, 2) * a + 3 * a**2)
    3*a**2 + a/2
    """
    import symengine as se

    if not isinstance(value, se.Basic):
        return sympy.sympify(value)
    return _convert(value, {} if cache is None else cache, se)


def _convert(e: Any, cache: dict, se: Any) -> sympy.Expr:
    if e in cache:
        return cache[e]
    if isinstance(e, se.Symbol):
        out = sympy.Symbol(e.name)
    elif isinstance(e, (se.Add, se.Mul)):
        args = [_convert(a, cache, se) for a in e.args]
        # sympy's canonical order for ordinary sizes; for long sums (large
        # systems) only the numeric coefficient goes first, which is all sympy's
        # algorithms rely on -- the full sort would cost more than the derivation
        if len(args) <= CANONICAL_SORT_LIMIT:
            (_addsort if isinstance(e, se.Add) else _mulsort)(args)
        else:
            args.sort(key=lambda a: not a.is_Number)
        cls = sympy.Add if isinstance(e, se.Add) else sympy.Mul
        out = cls._from_args(args, is_commutative=True)
    elif isinstance(e, se.Pow):
        base, exponent = (_convert(a, cache, se) for a in e.args)
        out = sympy.Pow(base, exponent)
    elif e.args and isinstance(e, se.Function) and type(e).__name__.lower() in SYMPY_FUNCTIONS:
        out = SYMPY_FUNCTIONS[type(e).__name__.lower()](*(_convert(a, cache, se) for a in e.args))
    else:
        out = e._sympy_()
    cache[e] = out
    return out


__all__ = ["Jet", "Var", "NotDifferentiable", "Backend", "backend", "SYMPY", "SYMPY_FUNCTIONS",
           "to_sympy"]
