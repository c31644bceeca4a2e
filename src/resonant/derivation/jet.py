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

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, TypeAlias

import numpy as np
import sympy
from sympy.core.add import _addsort
from sympy.core.mul import _mulsort

from ..expressions.functions import MATH
from ..expressions.functions import SYMPY as SYMPY_CONSTRUCTORS

if TYPE_CHECKING:
    from types import ModuleType

    import symengine

Var = tuple[str, int]
#: a jet's coefficient: a sympy or symengine expression, or a number (the float backend;
#: the numeric residual's are :class:`~resonant.derivation.residual.Sized` numbers, which
#: mypy lets pass where sympy's untyped classes are expected)
Coefficient: TypeAlias = "sympy.Basic | symengine.Basic | float"

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

    def slopes(self, func: str, value: Coefficient, second: bool) -> tuple[Any, Any]:
        """(f'(value), f''(value)) of a one-argument function (f'' only if ``second``)."""
        u, d1, d2 = self.derivatives(func)
        return d1.subs({u: value}), (d2.subs({u: value}) if second else 0)

    def is_bad(self, value: object) -> bool:
        """True for infinities and NaN (a function evaluated at a singularity)."""
        m = self.module
        return isinstance(value, self.basic) and any(
            value.has(x) for x in (m.zoo, m.nan, m.oo))

    def to_sympy(self, value: Coefficient, cache: dict | None = None) -> sympy.Expr:
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


class FloatBackend(Backend):
    """Coefficients as Python numbers: the jets of a model at one parameter point.

    The numeric path of large models (see
    :func:`resonant.derivation.lagrange.linearize_numeric`): a coefficient is a
    float (or an exact ``int``), a function's slopes are evaluated with
    :mod:`math` from its symbolic derivatives, and a sum of many jets is added up
    key by key with numpy (:func:`_float_sum`; a cancellation to rounding noise is
    zero).  Anything that is not a finite real number is "bad" (the caller then
    falls back to the symbolic derivation).
    """

    def symbol(self, name: str) -> Any:
        raise TypeError("the float backend has no symbols: give every name its value")

    def rational(self, numerator: int, denominator: int) -> Any:
        return numerator if denominator == 1 else numerator / denominator

    @property
    def pi(self) -> Any:
        return math.pi

    def slopes(self, func: str, value: Coefficient, second: bool) -> tuple[Any, Any]:
        if func not in self._derivatives:
            u = sympy.Symbol("_jet_u")
            d1 = sympy.diff(SYMPY_FUNCTIONS[func](u), u)
            self._derivatives[func] = (sympy.lambdify([u], d1, "math"),
                                       sympy.lambdify([u], sympy.diff(d1, u), "math"))
        first, other = self._derivatives[func]
        return first(value), (other(value) if second else 0)

    def is_bad(self, value: object) -> bool:
        return not isinstance(value, (int, float)) or not math.isfinite(value)

    def to_sympy(self, value: Coefficient, cache: dict | None = None) -> sympy.Expr:
        return sympy.sympify(value)

    def add(self, terms: list[Any]) -> Any:
        return terms[0] if len(terms) == 1 else math.fsum(terms)

    def from_sympy(self, value: sympy.Expr) -> Any:
        return float(value)


#: the numeric backend (coefficients are numbers at one parameter point)
FLOAT = FloatBackend("float", math, MATH, float)
_BACKENDS: dict[str, Backend] = {"sympy": SYMPY}


def backend(name: str) -> Backend:
    """The backend called ``"sympy"`` or ``"symengine"`` (imported on first use)."""
    if name not in _BACKENDS:
        import symengine

        # symengine spells |x| as sympy does (Abs); the other names are the model's own
        constructors = {n: getattr(symengine, "Abs" if n == "abs" else n)
                        for n in SYMPY_CONSTRUCTORS}
        _BACKENDS[name] = Backend("symengine", symengine, constructors, symengine.Basic)
    return _BACKENDS[name]


def _key(a: Var, b: Var) -> tuple[Var, Var]:
    return (a, b) if a <= b else (b, a)


def _nonzero(c: Coefficient) -> bool:
    # an expression that is not a number is never structurally zero (sympy and symengine
    # keep sums and products canonical): only numbers need the comparison
    if getattr(c, "is_Number", True):
        return not (c == 0)
    return True


class NotDifferentiable(ValueError):
    """The expression has no Taylor expansion at the reference state."""


class Jet:
    """A polynomial of degree <= 2 in small quantities, truncated on multiplication.

    Parameters
    ----------
    const : coefficient
        The value at the reference state.
    lin : mapping, optional
        small quantity -> first-order coefficient.
    quad : mapping, optional
        (quantity, quantity) -> second-order coefficient.

    Examples
    --------
    >>> x = Jet(0, {("x", 0): 1})
    >>> (x * x).quad, (x * x * x).quad
    ({(('x', 0), ('x', 0)): 1}, {})
    """

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
        if isinstance(backend, FloatBackend):
            return Jet(math.fsum(j.const for j in jets), _float_sum([j.lin for j in jets]),
                       _float_sum([j.quad for j in jets]))
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
        if other is self and self.lin and not isinstance(next(iter(self.lin.values())),
                                                          sympy.Basic):
            _square_terms(self.lin, quad)
        else:
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
        f1, f2 = backend.slopes(func, self.const, bool(self.lin))
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

    def partials(self, variables: set[Var]) -> dict[Var, Jet]:
        """:meth:`diff` with respect to each of ``variables``, in one pass over the terms.

        Examples
        --------
        >>> x, y = Jet.variable(("x", 0)), Jet.variable(("y", 0))
        >>> d = (x * x + x * y * 3).partials({("x", 0), ("y", 0)})
        >>> d[("x", 0)].lin == {("x", 0): 2, ("y", 0): 3}, d[("y", 0)].lin
        (True, {('x', 0): 3})
        """
        lin: dict[Var, dict[Var, Coefficient]] = {var: {} for var in variables}
        for (a, b), v in self.quad.items():
            if a == b:
                if a in lin:
                    out = lin[a]
                    out[a] = out.get(a, 0) + 2 * v
                continue
            if a in lin:
                out = lin[a]
                out[b] = out.get(b, 0) + v
            if b in lin:
                out = lin[b]
                out[a] = out.get(a, 0) + v
        return {var: Jet(self.lin.get(var, 0), {k: v for k, v in lin[var].items() if _nonzero(v)})
                for var in variables}

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


def _square_terms(lin: Mapping[Var, Coefficient], quad: dict) -> None:
    """Add the products of ``lin`` with itself to ``quad``: each pair once (x y + y x = 2 x y).

    For symengine and float coefficients (sympy's are left to the general loop, so that
    the textbook models' expressions keep their exact form).
    """
    items = sorted(lin.items())  # then a < b for every later b: the key needs no sorting
    for i, (a, va) in enumerate(items):
        kq = (a, a)
        term = va * va
        quad[kq] = quad[kq] + term if kq in quad else term
        twice = 2 * va
        for b, vb in items[i + 1:]:
            kq = (a, b)
            term = twice * vb
            quad[kq] = quad[kq] + term if kq in quad else term


#: a float sum smaller than this times the sum of its terms' sizes is rounding noise of
#: an exact cancellation: it is zero (as the symbolic sum would be)
CANCELLED = 1e-14


def _float_sum(parts: list[Mapping[Any, Any]]) -> dict[Any, float]:
    """Add up the coefficients of many float jets key by key, at C speed.

    Sums that cancel to rounding noise (:data:`CANCELLED`) become exactly zero and
    are dropped, like a cancelling symbolic sum.
    """
    keys: list[Any] = []
    values: list[Any] = []
    for part in parts:
        keys.extend(part)
        values.extend(part.values())
    if not keys:
        return {}
    index: dict[Any, int] = {}
    where = np.fromiter((index.setdefault(k, len(index)) for k in keys), dtype=np.intp,
                        count=len(keys))
    terms = np.array(values, dtype=float)
    total = np.bincount(where, weights=terms, minlength=len(index))
    size = np.bincount(where, weights=np.abs(terms), minlength=len(index))
    total[np.abs(total) <= CANCELLED * size] = 0.0
    return {k: t for k, t in zip(index, total.tolist()) if t != 0.0}


def _integer_power(base: Jet, n: int) -> Jet:
    result: Jet | None = None
    square = base
    while n:
        if n & 1:
            result = square if result is None else result * square
        n >>= 1
        if n:
            square = square * square
    return Jet(1) if result is None else result


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


def _factor_key(factor: sympy.Expr) -> tuple[int, str, int] | None:
    """sympy's canonical order (``Basic.compare``) of a symbol or an integer power of one;
    None for anything else."""
    if factor.is_Symbol:
        return (0, factor.name, 0)  # Symbol before Pow; symbols by name
    if factor.is_Pow and factor.base.is_Symbol and factor.exp.is_Integer:
        return (1, factor.base.name, int(factor.exp))  # powers by base, then exponent
    return None


def _sorted_factors(args: list[sympy.Expr]) -> list[sympy.Expr]:
    """The factors of a product in sympy's canonical order (as ``_mulsort`` sorts them).

    The common products of symbols and their integer powers (with at most one number,
    which goes first) are sorted by a plain key; anything else by sympy's comparison.
    """
    numbers = [a for a in args if a.is_Number]
    rest = [a for a in args if not a.is_Number]
    keyed = [(_factor_key(a), a) for a in rest]
    if len(numbers) > 1 or any(k is None for k, _ in keyed):
        _mulsort(args)
        return args
    keyed.sort(key=lambda pair: pair[0])  # type: ignore[arg-type, return-value]
    return numbers + [a for _, a in keyed]


def _convert(e: symengine.Basic, cache: dict, se: ModuleType) -> sympy.Expr:
    if e in cache:
        return cache[e]
    if isinstance(e, se.Symbol):
        out = sympy.Symbol(e.name)
    elif isinstance(e, (se.Add, se.Mul)):
        args = [_convert(a, cache, se) for a in e.args]
        # sympy's canonical order for ordinary sizes; for long sums (large
        # systems) only the numeric coefficient goes first, which is all sympy's
        # algorithms rely on -- the full sort would cost more than the derivation
        if isinstance(e, se.Mul):
            args = _sorted_factors(args)
        elif len(args) <= CANONICAL_SORT_LIMIT:
            _addsort(args)
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


__all__ = ["Jet", "Var", "NotDifferentiable", "Backend", "FloatBackend", "backend", "SYMPY",
           "FLOAT", "SYMPY_FUNCTIONS", "to_sympy"]
