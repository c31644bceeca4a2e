"""Safe parsing of the math expressions found in (untrusted) model files.

A hand-written tokenizer and recursive-descent parser turn a string such as
``"m*x'^2/2 + k*(x - r)^2/2"`` into a small immutable syntax tree.  Nothing
is ever evaluated by Python or parsed by sympy: :meth:`Expression.fold`
walks the tree and :meth:`Expression.to_sympy` builds the sympy expression
from it, refusing anything that would compute a huge number.

Grammar (``^`` and ``**`` are the same, right-associative operator)::

    expr    := unary (('+' | '-' | '*' | '/') unary)*     (usual precedence)
    unary   := ('+' | '-')* power
    power   := primary ('^' unary)?
    primary := NUMBER | NAME "'"* | FUNC '(' expr (',' expr)* ')' | '(' expr ')'
"""

from __future__ import annotations

import math
import operator
import re
from collections.abc import Callable, Collection
from dataclasses import dataclass, field
from typing import Protocol, TypeVar

import sympy

from ..errors import ModelError, Problem
from .functions import ARITY, MATH, SYMPY

#: name -> number of arguments of the language's functions
FUNCTIONS: dict[str, int] = ARITY
RESERVED: frozenset[str] = frozenset(FUNCTIONS) | {"pi", "t"}
MAX_LENGTH = 20_000
MAX_DEPTH = 100
MAX_NODES = 20_000
MAX_EXPONENT = 1000
MAX_NAME_LENGTH = 64
#: the largest magnitude of a number in a model, and the smallest nonzero one
MAX_NUMBER = 1e300
MIN_NUMBER = 1e-300
_MAX_BITS = 1100  # ~330 decimal digits: the largest exact number we let sympy build
_FLOAT_DIGITS = 30  # the precision an exact number continues with beyond _MAX_BITS
_TIME_HINT = ("time 't' may only appear in [signals]; "
              "declare a signal for anything that moves with time")

_TOKEN = re.compile(
    r"(?P<ws>[ \t\r\n]+)"
    r"|(?P<num>(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)(?P<primes>'*)"
    r"|(?P<op>\*\*|[-+*/^(),])",
    re.ASCII,
)
_NUMBER = re.compile(r"([0-9]*)\.?([0-9]*)(?:[eE]([+-]?)0*([0-9]*))?", re.ASCII)
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*", re.ASCII)


class ExpressionError(ModelError):
    """An expression in a model file is invalid.

    ``str(err)`` shows the location, the reason and, when the position is known, the
    expression with a caret under the culprit.

    Parameters
    ----------
    reason : str
        What is wrong.
    text : str
        The expression.
    position : int or None
        0-based offset of the culprit in ``text``.
    file, section, key : str
        Where the expression is.

    Examples
    --------
    >>> err = ExpressionError("unknown name 'q'", "m*q'^2/2", 2, "model.toml", "energy", "T")
    >>> print(err)
    model.toml: [energy] T: unknown name 'q'
        m*q'^2/2
          ^
    """

    def __init__(self, reason: str, text: str = "", position: int | None = None,
                 file: str = "", section: str = "", key: str = "") -> None:
        self.text, self.position, self.reason = text, position, reason
        message = reason if position is None else f"{reason}\n{_caret(text, position)}"
        super().__init__(Problem(message, file, section, key))


def _caret(text: str, pos: int) -> str:
    """The line of ``text`` holding ``pos`` (a window of it if long) and a caret line."""
    start = text.rfind("\n", 0, pos) + 1
    end = text.find("\n", pos)
    line, col = text[start:len(text) if end < 0 else end], pos - start
    if len(line) > 70:
        lo = max(0, min(col - 30, len(line) - 60))
        head, tail = ("..." if lo else ""), ("..." if lo + 60 < len(line) else "")
        line, col = head + line[lo:lo + 60] + tail, col - lo + len(head)
    line = "".join(c if c.isprintable() else " " for c in line)
    return f"    {line}\n    {' ' * col}^"


@dataclass(frozen=True)
class Num:
    """A numeric literal, kept as its text (e.g. ``"0.5"``, ``"1e-3"``).

    Parameters
    ----------
    value : str
        The literal as written.

    Examples
    --------
    >>> parse("1e-3").root
    Num(value='1e-3')
    """

    value: str


@dataclass(frozen=True)
class Name:
    """A name with ``primes`` time derivatives; ``position`` is its offset in the text.

    Parameters
    ----------
    name : str
        The name.
    primes : int
        How many time derivatives (``x''``: 2).
    position : int
        Its offset in the expression's text.

    Examples
    --------
    >>> parse("2*x''").root.right
    Name(name='x', primes=2, position=2)
    """

    name: str
    primes: int = 0
    position: int = field(default=0, compare=False)


@dataclass(frozen=True)
class Call:
    """A call of one of :data:`FUNCTIONS`.

    Parameters
    ----------
    func : str
        The function's name.
    args : tuple of Node
        Its arguments.

    Examples
    --------
    >>> parse("sin(x)").root.func
    'sin'
    """

    func: str
    args: tuple[Node, ...]


@dataclass(frozen=True)
class BinOp:
    """A binary operation; ``op`` is one of ``+ - * / ^``.

    Parameters
    ----------
    op : str
        The operator.
    left, right : Node
        The operands.

    Examples
    --------
    >>> parse("a^2").root.op
    '^'
    """

    op: str
    left: Node
    right: Node


@dataclass(frozen=True)
class Neg:
    """Unary minus.

    Parameters
    ----------
    operand : Node
        What is negated.

    Examples
    --------
    >>> parse("-a").root
    Neg(operand=Name(name='a', primes=0, position=1))
    """

    operand: Node


Node = Num | Name | Call | BinOp | Neg
_OPS = {"+": "add", "-": "sub", "*": "mul", "/": "div", "^": "pow"}

_T = TypeVar("_T")
_N = TypeVar("_N", bound=Node)


class FoldOps(Protocol[_T]):
    """The operations :meth:`Expression.fold` evaluates a tree with; ``_T`` is their value."""

    def num(self, text: str) -> _T: ...
    def name(self, name: str, primes: int) -> _T: ...
    def pi(self) -> _T: ...
    def add(self, a: _T, b: _T) -> _T: ...
    def sub(self, a: _T, b: _T) -> _T: ...
    def mul(self, a: _T, b: _T) -> _T: ...
    def div(self, a: _T, b: _T) -> _T: ...
    def pow(self, a: _T, b: _T) -> _T: ...
    def neg(self, a: _T) -> _T: ...
    def call(self, func: str, args: list[_T]) -> _T: ...


def _children(node: Node) -> tuple[Node, ...]:
    if isinstance(node, BinOp):
        return (node.left, node.right)
    if isinstance(node, Neg):
        return (node.operand,)
    return node.args if isinstance(node, Call) else ()


@dataclass(frozen=True)
class Expression:
    """A parsed expression: its source ``text`` and syntax tree ``root``.

    Equality and hashing use the text only.

    Parameters
    ----------
    text : str
        The source text.
    root : Node
        The syntax tree.
    origin : tuple of str
        The ``(file, section, key)`` it came from, used in error messages.

    Examples
    --------
    >>> e = parse("m*x'^2/2 + k*x^2/2")
    >>> sorted(e.names())
    [('k', 0), ('m', 0), ('x', 0), ('x', 1)]
    >>> import sympy
    >>> e.to_sympy(lambda name, primes: sympy.Symbol(name + "_d" * primes))
    k*x**2/2 + m*x_d**2/2
    """

    text: str
    root: Node = field(compare=False, repr=False)
    origin: tuple[str, str, str] = field(default=("", "", ""), compare=False, repr=False)

    def names(self) -> frozenset[tuple[str, int]]:
        """Every ``(name, primes)`` used, excluding the constant ``pi``."""
        found, stack = set(), [self.root]
        while stack:
            node = stack.pop()
            if isinstance(node, Name) and node.name != "pi":
                found.add((node.name, node.primes))
            stack.extend(_children(node))
        return frozenset(found)

    def fold(self, ops: FoldOps[_T]) -> _T:
        """Evaluate the tree bottom-up with the methods of ``ops``.

        ``ops`` provides ``num(text)``, ``name(name, primes)``, ``pi()``,
        ``add/sub/mul/div/pow(a, b)``, ``neg(a)`` and ``call(func, args)``.

        Examples
        --------
        >>> import math, operator as op
        >>> from types import SimpleNamespace
        >>> floats = SimpleNamespace(
        ...     num=float, name=lambda name, primes: 2.0, pi=lambda: math.pi, add=op.add,
        ...     sub=op.sub, mul=op.mul, div=op.truediv, pow=op.pow, neg=op.neg,
        ...     call=lambda func, args: getattr(math, func)(*args))
        >>> parse("-x^2 + 2^3^2 + cos(pi)").fold(floats)
        507.0
        """
        stack: list[tuple[Node, bool]] = [(self.root, False)]
        out: list[_T] = []
        while stack:
            node, expanded = stack.pop()
            if isinstance(node, Num):
                out.append(ops.num(node.value))
            elif isinstance(node, Name):
                out.append(ops.pi() if node.name == "pi" else ops.name(node.name, node.primes))
            elif not expanded:
                stack.append((node, True))
                stack.extend((child, False) for child in reversed(_children(node)))
            else:
                count = len(_children(node))
                args = out[len(out) - count:]
                del out[len(out) - count:]
                if isinstance(node, BinOp):
                    out.append(getattr(ops, _OPS[node.op])(*args))
                elif isinstance(node, Neg):
                    out.append(ops.neg(args[0]))
                else:
                    out.append(ops.call(node.func, args))
        return out[0]

    def to_sympy(self, resolve: Callable[[str, int], sympy.Expr | int | float]) -> sympy.Expr:
        """The exact sympy expression; ``resolve(name, primes)`` supplies the names.

        Raises :class:`ExpressionError` instead of building a huge number.

        Examples
        --------
        >>> parse("0.5*x + 1e-3").to_sympy(lambda name, primes: sympy.Symbol(name))
        x/2 + 1/1000
        """
        ops = _SympyOps(resolve, self)
        return ops.done(self.fold(ops))


def _decimal(text: str) -> tuple[str, int]:
    """Significant digits and scale of a literal: ``"0.0250"`` -> ``("25", -3)``.

    Works on the text alone, so an absurd exponent like ``1e-99999999999`` costs nothing.
    """
    whole, frac, sign, exp = _NUMBER.fullmatch(text).groups()  # type: ignore[union-attr]
    digits = (whole + frac).lstrip("0")
    stripped = digits.rstrip("0")
    if not stripped:
        return "", 0
    power = 0 if not exp else int(exp) if len(exp) <= 9 else 10**9
    return stripped, len(digits) - len(stripped) - len(frac) + (-power if sign == "-" else power)


def _number_problem(text: str) -> str | None:
    digits, scale = _decimal(text)
    if len(digits) > 300:
        return "number has too many digits (at most 300)"
    if float(text) > MAX_NUMBER or len(digits) + scale > 301:
        return "number too large (at most 1e300)"
    if digits and len(digits) + scale < -299:
        return "number too small (at least 1e-300 unless zero)"
    return None


_FLOAT_OPS: dict[str, Callable[..., float]] = dict(MATH) | {
    "+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv,
    "^": math.pow, "neg": operator.neg}


def _const(op: str, *values: float | None) -> float | None:
    """Float value of a constant subexpression (None: not constant or undefined)."""
    if any(v is None for v in values):
        return None
    try:
        result = _FLOAT_OPS[op](*values)
    except OverflowError:
        return math.inf
    except (ValueError, ZeroDivisionError):
        return None
    return None if result != result else result  # nan


class _Parser:
    def __init__(self, text: str, allowed: Collection[str] | None, where: tuple[str, str, str]):
        self.text, self.allowed, self.where = text, allowed, where
        self.nodes = 0
        self.tokens = self._tokenize()
        self.i = 0

    def error(self, reason: str, position: int | None) -> ExpressionError:
        return ExpressionError(reason, self.text, position, *self.where)

    def _tokenize(self) -> list[tuple[str, str, int, int]]:
        """Tokens ``(kind, text, position, primes)``, ending with an ``end`` token."""
        text, pos, tokens = self.text, 0, []
        while pos < len(text):
            m = _TOKEN.match(text, pos)
            if m is None:
                ch = text[pos]
                if ch == "'":
                    raise self.error("a prime (') may only directly follow a name, as in x'", pos)
                code = "" if ch.isascii() else f" (U+{ord(ch):04X})"
                raise self.error(f"unexpected character {ch!r}{code}", pos)
            if m.group("num"):
                if text[m.end():m.end() + 1] == ".":
                    raise self.error(f"malformed number {text[pos:m.end() + 1]!r}", pos)
                if (problem := _number_problem(m.group())) is not None:
                    raise self.error(problem, pos)
                tokens.append(("num", m.group(), pos, 0))
            elif m.group("name"):
                tokens.append(("name", m.group("name"), pos, len(m.group("primes"))))
            elif m.group("op"):
                tokens.append(("op", "^" if m.group() == "**" else m.group(), pos, 0))
            pos = m.end()
        tokens.append(("end", "", len(text), 0))
        return tokens

    def peek(self) -> tuple[str, str, int, int]:
        return self.tokens[self.i]

    def node(self, cls: Callable[..., _N], *args: object) -> _N:
        self.nodes += 1
        if self.nodes > MAX_NODES:
            raise self.error(f"expression too large (more than {MAX_NODES} nodes)", None)
        return cls(*args)

    def descend(self, depth: int, pos: int) -> int:
        if depth >= MAX_DEPTH:
            raise self.error(f"expression nested too deeply (more than {MAX_DEPTH} levels)", pos)
        return depth + 1

    def parse(self) -> Node:
        if self.peek()[0] == "end":
            raise self.error("empty expression", None)
        root, _ = self.expr(0)
        self.expect("")
        return root

    def expect(self, closing: str, opening: int = 0) -> None:
        """Consume ``closing`` (``")"``, or ``""`` for the end), else explain what is wrong."""
        kind, tok, pos, _ = self.peek()
        if kind == "end" and closing == ")":
            raise self.error("unclosed '('", opening)
        if kind in ("num", "name") or tok == "(":
            prev_kind, prev, _, prev_primes = self.tokens[self.i - 1]
            prev += "'" * prev_primes
            hint = (f"write {prev}*{tok}"
                    if prev_kind in ("num", "name") and kind in ("num", "name")
                    else "insert '*' where you mean a product")
            raise self.error(
                f"missing operator (implicit multiplication is not supported: {hint})", pos)
        if tok != closing:
            raise self.error("unmatched ')'" if tok == ")" else f"unexpected {tok!r}", pos)
        self.i += 1

    def expr(self, depth: int) -> tuple[Node, float | None]:
        """Sums of products, iteratively (``a-b-c`` and ``a/b/c`` associate left)."""
        total: tuple[Node, float | None] | None = None
        add_op = "+"
        term = self.unary(depth)
        while (tok := self.peek()[1]) in ("+", "-", "*", "/"):
            self.i += 1
            right = self.unary(depth)
            if tok in "*/":
                term = self.node(BinOp, tok, term[0], right[0]), _const(tok, term[1], right[1])
            else:
                if total is not None:
                    term = (self.node(BinOp, add_op, total[0], term[0]),
                            _const(add_op, total[1], term[1]))
                total, add_op, term = term, tok, right
        if total is not None:
            term = self.node(BinOp, add_op, total[0], term[0]), _const(add_op, total[1], term[1])
        return term

    def unary(self, depth: int) -> tuple[Node, float | None]:
        signs = 0
        while (tok := self.peek())[1] in ("+", "-"):
            depth = self.descend(depth, tok[2])
            signs += tok[1] == "-"
            self.i += 1
        result = self.power(depth)
        for _ in range(signs):
            result = self.node(Neg, result[0]), _const("neg", result[1])
        return result

    def power(self, depth: int) -> tuple[Node, float | None]:
        base = self.primary(depth)
        tok, pos = self.peek()[1:3]
        if tok != "^":
            return base
        self.i += 1
        exponent = self.unary(self.descend(depth, pos))
        if exponent[1] is not None and abs(exponent[1]) > MAX_EXPONENT:
            raise self.error(f"exponent too large (at most {MAX_EXPONENT} in magnitude)", pos)
        return self.node(BinOp, "^", base[0], exponent[0]), _const("^", base[1], exponent[1])

    def primary(self, depth: int) -> tuple[Node, float | None]:
        kind, tok, pos, primes = self.peek()
        self.i += 1
        if kind == "num":
            return self.node(Num, tok), float(tok)
        if tok == "(":
            inner = self.expr(self.descend(depth, pos))
            self.expect(")", pos)
            return inner
        if kind == "name":
            return self.name(tok, pos, primes, depth)
        if kind == "end":
            raise self.error("unexpected end of expression", pos)
        raise self.error(f"expected a number, a name or '(' but found {tok!r}", pos)

    def name(self, name: str, pos: int, primes: int, depth: int) -> tuple[Node, float | None]:
        is_call = self.peek()[1] == "("
        if name.startswith("__"):
            raise self.error("names starting with '__' are not allowed", pos)
        if name in FUNCTIONS:
            if primes:
                raise self.error("a prime (') may only follow a name, not a function", pos)
            if not is_call:
                raise self.error(f"{name!r} is a function; call it as {name}(...)", pos)
            return self.call(name, pos, depth)
        if is_call:
            raise self.error(f"unknown function {name!r} (for a product write {name}*(...))", pos)
        if name == "pi":
            if primes:
                raise self.error("'pi' is a constant and has no time derivative", pos)
            return self.node(Name, name, 0, pos), math.pi
        if self.allowed is not None and name not in self.allowed:
            raise self.error(_TIME_HINT if name == "t" else f"unknown name {name!r}", pos)
        return self.node(Name, name, primes, pos), None

    def call(self, func: str, pos: int, depth: int) -> tuple[Node, float | None]:
        opening = self.peek()[2]
        depth = self.descend(depth, opening)
        self.i += 1
        args = [self.expr(depth)]
        while self.peek()[1] == ",":
            self.i += 1
            args.append(self.expr(depth))
        self.expect(")", opening)
        arity = FUNCTIONS[func]
        if len(args) != arity:
            plural = "s" if arity > 1 else ""
            raise self.error(f"{func}() takes {arity} argument{plural}, got {len(args)}", pos)
        node = self.node(Call, func, tuple(a[0] for a in args))
        return node, _const(func, *(a[1] for a in args))


def parse(text: str | int | float, *, allowed: Collection[str] | None = None,
          file: str = "", section: str = "", key: str = "") -> Expression:
    """Parse an expression from a model file.

    Parameters
    ----------
    text : str or int or float
        The expression; TOML numbers are accepted too.
    allowed : collection of str, optional
        If given, every name except ``pi`` must be in it.
    file, section, key : str
        Where the expression comes from, for error messages.

    Returns
    -------
    Expression

    Raises
    ------
    ExpressionError
        On any syntax error, unknown name or exceeded limit.

    Examples
    --------
    >>> parse("-x^2").root
    Neg(operand=BinOp(op='^', left=Name(name='x', primes=0, position=1), right=Num(value='2')))
    >>> parse(0.25).text
    '0.25'
    >>> try:
    ...     parse("m*q'", allowed={"m"}, file="model.toml", section="energy", key="T")
    ... except ExpressionError as err:
    ...     print(err)
    model.toml: [energy] T: unknown name 'q'
        m*q'
          ^
    """
    where = (file, section, key)
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise ExpressionError("expected a number or an expression string", "", None, *where)
    if isinstance(text, float) and not math.isfinite(text):
        raise ExpressionError(f"expected a finite number, got {text!r}", "", None, *where)
    if isinstance(text, int) and text.bit_length() > 1000:
        raise ExpressionError("number too large (at most 1e300)", "", None, *where)
    if not isinstance(text, str):
        text = repr(text)
    if len(text) > MAX_LENGTH:
        raise ExpressionError(
            f"expression too long ({len(text)} characters; at most {MAX_LENGTH})", "", None, *where)
    return Expression(text, _Parser(text, allowed, where).parse(), where)


def primed_names(expression: Expression) -> list[str]:
    """The time derivatives (``k'``) in an expression that may only use constants.

    Parameters
    ----------
    expression : Expression

    Returns
    -------
    list of str
        Each primed name with its primes, sorted.

    Examples
    --------
    >>> primed_names(parse("k' + 2*m''"))
    ["k'", "m''"]
    """
    return sorted(name + "'" * primes for name, primes in expression.names() if primes)


def validate_name(name: str) -> str | None:
    """Why ``name`` cannot be declared by a model, or None if it can.

    Parameters
    ----------
    name : str
        A name a model declares.

    Returns
    -------
    str or None
        The reason, or None for a valid name.

    Examples
    --------
    >>> validate_name("x1") is None
    True
    >>> validate_name("sin")
    "'sin' is reserved"
    """
    if not isinstance(name, str) or not _IDENT.fullmatch(name):
        return f"{name!r} is not a valid name (letters, digits and '_', not starting with a digit)"
    if name.startswith("__"):
        return "names starting with '__' are not allowed"
    if name in RESERVED:
        return f"{name!r} is reserved"
    if len(name) > MAX_NAME_LENGTH:
        return f"name too long ({len(name)} characters; at most {MAX_NAME_LENGTH})"
    return None




def _huge(n: sympy.Expr, limit: float) -> bool:
    return bool(n.is_Number and n is not sympy.nan and abs(n) > limit)


class _Pending:
    """A sum or product being collected, so a long chain costs one sympy call."""

    __slots__ = ("mul", "coeff", "items")

    def __init__(self, mul: bool) -> None:
        self.mul, self.coeff = mul, sympy.Integer(int(mul))
        self.items: list[sympy.Expr] = []


class _SympyOps:
    """Fold operations building an exact sympy expression, with size guards.

    Chains ``a + b - c ...`` and ``a * b / c ...`` are collected and built by
    a single ``Add``/``Mul`` (pairwise building is quadratic in sympy), their
    numeric coefficient accumulated eagerly so it can be bounded at each step.
    """

    def __init__(self, resolve: Callable[[str, int], sympy.Expr | int | float],
                 expression: Expression) -> None:
        self.resolve, self.expression = resolve, expression

    def fail(self, reason: str) -> ExpressionError:
        return ExpressionError(reason, self.expression.text, None, *self.expression.origin)

    def check(self, e: sympy.Expr) -> sympy.Expr:
        """Refuse results holding a huge number or a merged huge exponent; an exact
        rational whose digits outgrow the limit while its value does not (a chain of
        parameters like 0.01*1.01 + 0.0003 ...) continues as a float of 30 digits."""
        inexact: dict[sympy.Expr, sympy.Expr] = {}
        for part in (e, *e.args) if e.is_Add or e.is_Mul else (e,):
            if part.is_Mul:
                part = part.args[0]
            if part.is_Rational and max(abs(part.p).bit_length(), part.q.bit_length()) > _MAX_BITS:
                inexact[part] = self.rounded(part)
            if part.is_Pow and _huge(part.exp, MAX_EXPONENT):
                raise self.fail(f"exponent too large (at most {MAX_EXPONENT} in magnitude)")
        return e.xreplace(inexact) if inexact else e

    def rounded(self, value: sympy.Rational) -> sympy.Expr:
        """A rational of too many digits as a 30-digit float, if its value is not huge."""
        magnitude = abs(value.p).bit_length() - value.q.bit_length()
        if magnitude > _MAX_BITS:
            raise self.fail("number too large")
        if magnitude < -_MAX_BITS:
            raise self.fail("number too small (a value below 1e-300 is 0 in floating point)")
        return sympy.Float(value, _FLOAT_DIGITS)

    def done(self, x: sympy.Expr | _Pending) -> sympy.Expr:
        if isinstance(x, _Pending):
            x = self.check((sympy.Mul if x.mul else sympy.Add)(x.coeff, *x.items))
        return x

    def collect(self, a: sympy.Expr | _Pending, b: sympy.Expr, mul: bool) -> _Pending:
        if not (isinstance(a, _Pending) and a.mul == mul):
            a = self.collect(_Pending(mul), self.done(a), mul)
        coeff, rest = b.as_coeff_Mul() if mul else b.as_coeff_Add()
        if coeff.is_Rational:
            a.coeff = self.check(a.coeff * coeff if mul else a.coeff + coeff)
            b = rest
        if b != int(mul):
            a.items.append(b)
        return a

    def num(self, text: str) -> sympy.Expr:
        digits, scale = _decimal(text)  # bounded by the tokenizer's checks
        return sympy.Integer(int(digits or "0")) * sympy.Integer(10) ** scale

    def name(self, name: str, primes: int) -> sympy.Expr:
        value = self.resolve(name, primes)
        if isinstance(value, int) and not isinstance(value, bool):
            return sympy.Integer(value)
        if isinstance(value, float):
            return sympy.Float(value)
        if not isinstance(value, sympy.Basic):  # never sympify: a str would be parsed
            raise TypeError(
                f"resolve({name!r}, {primes}) must return a sympy expression or a number")
        return value

    def pi(self) -> sympy.Expr:
        return sympy.pi

    def add(self, a: sympy.Expr | _Pending, b: sympy.Expr | _Pending) -> _Pending:
        return self.collect(a, self.done(b), mul=False)

    def sub(self, a: sympy.Expr | _Pending, b: sympy.Expr | _Pending) -> _Pending:
        return self.collect(a, -self.done(b), mul=False)

    def mul(self, a: sympy.Expr | _Pending, b: sympy.Expr | _Pending) -> _Pending:
        return self.collect(a, self.done(b), mul=True)

    def div(self, a: sympy.Expr | _Pending, b: sympy.Expr | _Pending) -> _Pending:
        return self.collect(a, sympy.Pow(self.done(b), -1), mul=True)

    def neg(self, a: sympy.Expr | _Pending) -> sympy.Expr:
        return -self.done(a)

    def pow(self, a: sympy.Expr | _Pending, b: sympy.Expr | _Pending) -> sympy.Expr:
        a, b = self.done(a), self.done(b)
        if _huge(b, MAX_EXPONENT):
            raise self.fail(f"exponent too large (at most {MAX_EXPONENT} in magnitude)")
        if a.is_Rational and b.is_Rational and a not in (0, 1, -1):
            if abs(b) * max(math.log2(abs(a.p)), math.log2(a.q)) > _MAX_BITS:
                # too many digits to keep exact: huge in value, or else a float
                if abs(b) * abs(math.log2(abs(a.p)) - math.log2(a.q)) > _MAX_BITS:
                    huge = (math.log2(abs(a.p)) > math.log2(a.q)) == (b > 0)
                    raise self.fail("number too large" if huge else "number too small "
                                    "(a value below 1e-300 is 0 in floating point)")
                return self.check(sympy.Pow(sympy.Float(a, _FLOAT_DIGITS), b))
        return self.check(sympy.Pow(a, b))

    def call(self, func: str, args: list[sympy.Expr | _Pending]) -> sympy.Expr:
        values = [self.done(a) for a in args]
        # exp(c*log(b)) evaluates to b**c: bound c like any exponent.
        if func == "exp" and values[0].has(sympy.log) and any(
                _huge(n, MAX_EXPONENT) for n in values[0].atoms(sympy.Number)):
            raise self.fail(f"exponent too large (at most {MAX_EXPONENT} in magnitude)")
        return self.check(SYMPY[func](*values))
