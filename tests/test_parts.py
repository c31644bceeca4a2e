"""A planar mechanism described by its parts (the contract: docs/parts.md).

Every example in examples/parts/ is checked against the same system written as energies
(symbolic M, C, K and Q equal), two of them also against sympy.physics.mechanics'
Lagrangian route, and random chains of bodies and springs against their energies.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
import sympy
from conftest import EXAMPLES, run_cli
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import resonant
from resonant.derivation.residual import is_zero, magnitude
from resonant.errors import ModelError

PARTS = EXAMPLES / "parts"
S = sympy.Symbol


def _same(a: sympy.Expr, b: sympy.Expr) -> bool:
    """a == b symbolically (with positive symbols when sqrt(x^2) needs them)."""
    difference = sympy.simplify(sympy.sympify(a) - sympy.sympify(b))
    if difference == 0:
        return True
    positive, _ = sympy.posify(difference)
    return bool(sympy.simplify(positive) == 0)


def assert_same_system(parts: resonant.Model, energy: resonant.Model) -> None:
    a, b = parts.linearize(), energy.linearize()
    assert a.coordinates == b.coordinates
    for name in ("M", "C", "K", "Q"):
        ma, mb = getattr(a, name), getattr(b, name)
        assert ma.shape == mb.shape, name
        for x, y in zip(ma, mb):
            assert _same(x, y), (name, x, y)


def load_text(text: str) -> resonant.Model:
    return resonant.loads(text, source="test.toml")


def errors_of(text: str) -> str:
    with pytest.raises(ModelError) as info:
        load_text(text).linearize()
    return str(info.value)


# -- the equilibrium check (the bug this work hits at once) ----------------------------------

SPRING_EXACT = """
[parameters]
a = {a}
k = 100
m = 1
[coordinates]
x = ""
[energy]
T = "m*x'^2/2"
U = "k/2*(sqrt((a + x)^2) - a)^2"
"""


@pytest.mark.parametrize("a", ["0.5", "1", "3", "1e-3", "\"pi/7\""])
def test_spring_of_free_length_a_is_an_equilibrium(a: str) -> None:
    eom = load_text(SPRING_EXACT.format(a=a)).linearize()
    assert float(eom.numeric().K[0, 0]) == pytest.approx(100)


def test_a_real_residual_is_still_refused() -> None:
    text = SPRING_EXACT.format(a="0.5").replace("sqrt((a + x)^2) - a", "sqrt((a + x)^2) - 2*a")
    message = errors_of(text)
    assert "not an equilibrium" in message and "residual" in message


def test_residual_judged_against_every_term() -> None:
    a, k = S("a"), S("k")
    values = {a: sympy.Rational(1, 3), k: 100}
    cancelling = a * k * (-a + sympy.sqrt(a**2)) / sympy.sqrt(a**2)
    assert is_zero(cancelling, values)[0]
    assert is_zero(sympy.sin(sympy.sqrt(a**2) - a) * k, values)[0]
    assert not is_zero(k * (a - sympy.Rational(1, 4)), values)[0]
    # a small but real residual inside a product is not hidden by the big terms
    assert not is_zero(sympy.Rational(1, 10**12) * k * (a + 1), values)[0]
    value, size = magnitude(cancelling, values)
    assert abs(value) < 1e-25 * size and size > 1


# -- the reference exercise ------------------------------------------------------------------

def test_cart_pendulum_parts_equal_the_energy_form() -> None:
    parts = resonant.load(PARTS / "cart_pendulum.toml")
    energy = resonant.load(EXAMPLES / "cart_pendulum.toml")
    assert_same_system(parts, energy)
    a, b = parts.linearize(), energy.linearize()
    m1, m2, l, k, g = (S(n) for n in ("m1", "m2", "l", "k", "g"))
    assert _same(a.M[0, 0], m1 + m2) and _same(a.M[1, 1], m2 / 3) and _same(a.M[0, 1], m2 / 2)
    assert _same(a.K[0, 0], k) and _same(a.K[1, 1], m2 * g / (2 * l))
    sa, sb = a.stationary().to_dict(), b.stationary().to_dict()
    for key in ("harmonics", "amplitudes", "phases"):
        assert json.dumps(sa[key], sort_keys=True) == json.dumps(sb[key], sort_keys=True), key
    L = sa["harmonics"][0]["L"]
    assert L == pytest.approx([0.00217, -0.03856], abs=5e-5)


def test_cart_pendulum_derived_energies() -> None:
    model = resonant.load(PARTS / "cart_pendulum.toml")
    derived = model.parts
    assert derived is not None
    kinds = [(c.kind, c.name, c.energy) for c in derived.contributions]
    assert kinds == [("body", "cart", "T"), ("body", "rod", "T"), ("body", "rod", "U"),
                     ("spring", "k", "U")]
    assert derived.force_points == {"F at C": "rod.C"}
    assert derived.positions["rod.C"] == ("l*sin(phi) + x1", "-l*cos(phi)")
    assert derived.centres["rod"] == ("l*sin(phi)/2 + x1", "-l*cos(phi)/2")
    assert set(model.energy) == {"T", "U"} and not derived.written


def test_parts_mix_with_energy() -> None:
    base = (PARTS / "cart_pendulum.toml").read_text()
    mixed = base.replace('[definitions]', '[energy]\nU = "k2*x1^2/2"\n\n[definitions]')
    mixed = mixed.replace("[parameters]", "[parameters]\nk2 = 50")
    model = load_text(mixed)
    assert model.parts is not None and "U" in model.parts.written
    eom = model.linearize()
    assert _same(eom.K[0, 0], S("k") + S("k2"))


# -- every example against its energy form --------------------------------------------------

DOUBLE_PENDULUM_ENERGY = """
[parameters]
m1 = 1
m2 = 0.5
l1 = 0.6
l2 = 0.4
g = 9.81
M0 = 0.1
omega = 3
[coordinates]
phi1 = ""
phi2 = ""
[signals]
Mt = "M0*sin(omega*t)"
[energy]
T = "m1*l1^2/8*phi1'^2 + m1*l1^2/24*phi1'^2 + m2/2*(l1^2*phi1'^2 + l2^2/4*phi2'^2 + l1*l2*phi1'*phi2'*cos(phi1 - phi2)) + m2*l2^2/24*phi2'^2"
U = "-m1*g*l1/2*cos(phi1) - m2*g*(l1*cos(phi1) + l2/2*cos(phi2))"
[[force]]
generalized = { phi2 = "Mt" }
"""

QUARTER_CAR_ENERGY = """
[parameters]
ms = 300
mu = 40
ks = 20000
cs = 1500
kt = 180000
ct = 50
h = 0.02
omega = 15
[coordinates]
z_u = ""
z_s = ""
[signals]
y = "h*sin(omega*t)"
[energy]
T = "mu/2*z_u'^2 + ms/2*z_s'^2"
U = "kt/2*(z_u - y)^2 + ks/2*(z_s - z_u)^2"
D = "ct/2*(z_u' - y')^2 + cs/2*(z_s' - z_u')^2"
"""

ROLLING_DISC_ENERGY = """
[parameters]
m = 4
R = 0.1
k = 400
c = 8
a0 = 0.01
omega = 8
[coordinates]
x = ""
[signals]
a = "a0*cos(omega*t)"
[energy]
T = "m/2*x'^2 + m*R^2/4*(x'/R)^2"
U = "k/2*x^2"
D = "c/2*(a' - x')^2"
"""

TORSIONAL_ENERGY = """
[parameters]
J1 = 0.02
J2 = 0.05
kt1 = 300
kt2 = 200
ct = 0.1
M0 = 2
omega = 40
[coordinates]
phi1 = ""
phi2 = ""
[signals]
M = "M0*cos(omega*t)"
[energy]
T = "J1/2*phi1'^2 + J2/2*phi2'^2"
U = "kt1/2*phi1^2 + kt2/2*(phi2 - phi1)^2"
D = "ct/2*(phi2' - phi1')^2"
[[force]]
generalized = { phi2 = "M" }
"""

SLIDER_ENERGY = """
[parameters]
m = 1
k1 = 500
k2 = 100
h = 0.3
L0 = 0.2
a = 0.5
F0 = 1
omega = 10
[coordinates]
x = ""
[signals]
F = "F0*sin(omega*t)"
[energy]
T = "m/2*x'^2"
U = "k1/2*(sqrt(x^2 + h^2) - L0)^2 + k2/2*x^2"
[[force]]
generalized = { x = "F" }
"""

ELASTIC_PENDULUM_ENERGY = """
[parameters]
m = 0.5
k = 200
L0 = 0.4
g = 9.81
[coordinates]
r = ""
theta = ""
[equilibrium]
r = "m*g/k"
[energy]
T = "m/2*(r'^2 + (L0 + r)^2*theta'^2)"
U = "k/2*r^2 - m*g*(L0 + r)*cos(theta)"
"""


@pytest.mark.parametrize("name, energy", [
    ("pendulum", EXAMPLES / "pendulum.toml"),
    ("rotating_unbalance", EXAMPLES / "rotating_unbalance.toml"),
    ("double_pendulum", DOUBLE_PENDULUM_ENERGY),
    ("quarter_car", QUARTER_CAR_ENERGY),
    ("rolling_disc", ROLLING_DISC_ENERGY),
    ("torsional_chain", TORSIONAL_ENERGY),
    ("slider_spring", SLIDER_ENERGY),
    ("elastic_pendulum", ELASTIC_PENDULUM_ENERGY),
])
def test_example_equals_its_energy_form(name: str, energy: Path | str) -> None:
    parts = resonant.load(PARTS / f"{name}.toml")
    other = resonant.load(energy) if isinstance(energy, Path) else load_text(energy)
    assert_same_system(parts, other)


def test_independent_values() -> None:
    """Hand-derived stiffnesses of the exact-geometry and sagging examples."""
    slider = resonant.load(PARTS / "slider_spring.toml").linearize()
    assert _same(slider.K[0, 0], S("k1") * (1 - S("L0") / S("h")) + S("k2"))
    elastic = resonant.load(PARTS / "elastic_pendulum.toml").linearize().numeric()
    m, k, L0, g = 0.5, 200, 0.4, 9.81
    assert float(elastic.K[0, 0]) == pytest.approx(k)
    assert float(elastic.K[1, 1]) == pytest.approx(m * g * (L0 + m * g / k))
    assert float(elastic.M[1, 1]) == pytest.approx(m * (L0 + m * g / k) ** 2)
    disc = resonant.load(PARTS / "rolling_disc.toml").linearize()
    assert _same(disc.M[0, 0], sympy.Rational(3, 2) * S("m"))


# -- sympy.physics.mechanics' Lagrangian route -------------------------------------------------

def _mechanics_matrices(lagrangian: sympy.Expr, q: list, values: dict) -> tuple:
    qd = [sympy.diff(x, sympy.Symbol("t")) for x in q]
    speeds = [sympy.Dummy() for _ in q]
    coords = [sympy.Dummy() for _ in q]
    L = lagrangian.subs(dict(zip(qd, speeds))).subs(dict(zip(q, coords)))
    at_rest = {**{c: values.get(i, 0) for i, c in enumerate(coords)},
               **dict.fromkeys(speeds, 0)}
    M = sympy.hessian(L, speeds).subs(at_rest)
    K = -sympy.hessian(L, coords).subs(at_rest)
    return M, K


def test_double_pendulum_against_sympy_mechanics() -> None:
    me = pytest.importorskip("sympy.physics.mechanics")
    m1, m2, l1, l2, g = sympy.symbols("m1 m2 l1 l2 g")
    phi1, phi2 = me.dynamicsymbols("phi1 phi2")
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [phi1, N.z])
    B = N.orientnew("B", "Axis", [phi2, N.z])
    O = me.Point("O")
    O.set_vel(N, 0)
    S1 = O.locatenew("S1", -l1 / 2 * A.y)
    E = O.locatenew("E", -l1 * A.y)
    S2 = E.locatenew("S2", -l2 / 2 * B.y)
    S1.v2pt_theory(O, N, A)
    E.v2pt_theory(O, N, A)
    S2.v2pt_theory(E, N, B)
    rod1 = me.RigidBody("rod1", S1, A, m1, (me.inertia(A, 0, 0, m1 * l1**2 / 12), S1))
    rod2 = me.RigidBody("rod2", S2, B, m2, (me.inertia(B, 0, 0, m2 * l2**2 / 12), S2))
    rod1.potential_energy = m1 * g * S1.pos_from(O).dot(N.y)
    rod2.potential_energy = m2 * g * S2.pos_from(O).dot(N.y)
    M, K = _mechanics_matrices(me.Lagrangian(N, rod1, rod2), [phi1, phi2], {})
    eom = resonant.load(PARTS / "double_pendulum.toml").linearize()
    for x, y in zip(eom.M, M):
        assert _same(x, y)
    for x, y in zip(eom.K, K):
        assert _same(x, y)


def test_cart_pendulum_against_sympy_mechanics() -> None:
    me = pytest.importorskip("sympy.physics.mechanics")
    m1, m2, l, k, g = sympy.symbols("m1 m2 l k g")
    x1, x2 = me.dynamicsymbols("x1 x2")
    phi = x2 / l
    N = me.ReferenceFrame("N")
    R = N.orientnew("R", "Axis", [phi, N.z])
    O = me.Point("O")
    O.set_vel(N, 0)
    B = O.locatenew("B", x1 * N.x)
    B.set_vel(N, B.pos_from(O).dt(N))
    Sp = B.locatenew("S", -l / 2 * R.y)
    Sp.v2pt_theory(B, N, R)
    cart = me.Particle("cart", B, m1)
    rod = me.RigidBody("rod", Sp, R, m2, (me.inertia(R, 0, 0, m2 * l**2 / 12), Sp))
    cart.potential_energy = k * x1**2 / 2
    rod.potential_energy = m2 * g * Sp.pos_from(O).dot(N.y)
    M, K = _mechanics_matrices(me.Lagrangian(N, cart, rod), [x1, x2], {})
    eom = resonant.load(PARTS / "cart_pendulum.toml").linearize()
    for x, y in zip(eom.M, M):
        assert _same(x, y)
    for x, y in zip(eom.K, K):
        assert _same(x, y)


# -- random chains: parts == energies ---------------------------------------------------------

@st.composite
def chains(draw: st.DrawFn) -> tuple[str, str]:
    n = draw(st.integers(1, 3))
    values = st.integers(1, 9)
    params, coords, bodies, springs = [], [], [], []
    T, U, D = [], [], []
    params.append("g = 9.81")
    for i in range(1, n + 1):
        m, k = draw(values), draw(values)
        params += [f"m{i} = {m}", f"k{i} = {k}"]
        coords.append(f'x{i} = ""')
        bodies.append(f'[[body]]\nname = "b{i}"\nmass = "m{i}"\nposition = ["{2 * i} + x{i}", "0"]')
        previous = "ground" if i == 1 else f"b{i - 1}"
        prev_x = "0" if i == 1 else f"x{i - 1}"
        mode = draw(st.sampled_from(["along", "free", "length"]))
        key = {"along": 'along = ["1", "0"]', "free": "",
               "length": "length = 1"}[mode]
        springs.append(f'[[spring]]\nbetween = ["{previous}", "b{i}"]\nstiffness = "k{i}"\n{key}')
        T.append(f"m{i}/2*x{i}'^2")
        # free length 2 between neighbours 2 apart; `length = 1` preloads it (tension k)
        U.append(f"k{i}/2*(x{i} - {prev_x})^2" if mode != "length"
                 else f"k{i}/2*(2 + x{i} - {prev_x} - 1)^2")
        if draw(st.booleans()):
            c = draw(values)
            params.append(f"c{i} = {c}")
            springs.append(f'[[damper]]\nbetween = ["{previous}", "b{i}"]\ndamping = "c{i}"\n'
                           'along = ["1", "0"]')
            D.append(f"c{i}/2*(x{i}' - {prev_x}')^2".replace("0'", "0"))
        if draw(st.booleans()):  # a pendulum hanging from the body
            mp, lp = draw(values), draw(values)
            params += [f"p{i} = {mp}", f'l{i} = "{lp}/10"']
            coords.append(f'th{i} = ""')
            bodies.append(f'[[body]]\nname = "pendulum{i}"\nmass = "p{i}"\npin = "b{i}"\n'
                          f'angle = "th{i}"\ncentre = ["0", "-l{i}"]')
            T.append(f"p{i}/2*((x{i}' + l{i}*cos(th{i})*th{i}')^2 + (l{i}*sin(th{i})*th{i}')^2)")
            U.append(f"-p{i}*g*l{i}*cos(th{i})")
    # the preloaded springs pull the chain: a spring to the right end balances nothing, so
    # the energy form carries the same preloads and the check compares the same equilibrium
    head = "[parameters]\n" + "\n".join(params) + "\n[coordinates]\n" + "\n".join(coords)
    parts = (f'gravity = "g"\n{head}\n[[point]]\nname = "ground"\nposition = ["0", "0"]\n'
             + "\n".join(bodies) + "\n" + "\n".join(springs))
    energy = (f'{head}\n[energy]\nT = "{" + ".join(T)}"\nU = "{" + ".join(U)}"\n'
              + (f'D = "{" + ".join(D)}"\n' if D else ""))
    return parts, energy


def _balanced(text: str) -> bool:
    try:
        resonant.loads(text).linearize()
    except ModelError as exc:
        return "not an equilibrium" not in str(exc)
    return True


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(chains())
def test_random_chains_parts_equal_energies(chain: tuple[str, str]) -> None:
    parts_text, energy_text = chain
    if not _balanced(energy_text):  # preloaded springs that do not balance: both refuse
        with pytest.raises(ModelError, match="not an equilibrium"):
            load_text(parts_text).linearize()
        return
    assert_same_system(load_text(parts_text), load_text(energy_text))


# -- the derived text is the model language, parsed back exactly ----------------------------

def test_to_text_round_trip() -> None:
    from resonant.model.part_energies import to_text

    t = sympy.Symbol("t")
    x, phi = sympy.Function("x")(t), sympy.Function("phi")(t)
    a, b = sympy.symbols("a b")
    cases = [(a * sympy.diff(x, t) * sympy.cos(phi) / 2) ** 2, sympy.sqrt((a + x) ** 2) - a,
             (a - b) ** sympy.Rational(3, 2) / (a * x), -x ** 2 + sympy.exp(1) * sympy.pi,
             sympy.diff(x, t, 2) * sympy.atan2(x, a) - sympy.Float(0.25) * b]
    for expr in cases:
        text = to_text(expr)
        back = resonant.expressions.parse(text).to_sympy(
            lambda n, p: sympy.diff(sympy.Function(n)(t), t, p) if n in ("x", "phi")
            else sympy.Symbol(n))
        assert sympy.simplify(back - expr) == 0, (text, expr)


# -- errors name the part and the key ---------------------------------------------------------

BASE = """
[parameters]
m = 1
k = 10
l = 1
[coordinates]
x = ""
[[point]]
name = "wall"
position = ["0", "0"]
"""


@pytest.mark.parametrize("extra, expected", [
    ('[[body]]\nname = "b"\nmass = "m"\nposition = ["x", "0"]\n[[spring]]\nname = "s"\n'
     'between = ["wal", "b"]\nstiffness = "k"',
     ['[spring "s"] between[0]', "unknown point 'wal'", "did you mean 'wall'"]),
    ('[[body]]\nname = "b"\nmass = "-m"\nposition = ["x", "0"]',
     ['[body "b"] mass', "negative"]),
    ('[[body]]\nname = "b"\nmass = "m"\ninertia = "-1"\nposition = ["x", "0"]',
     ['[body "b"] inertia', "negative"]),
    ('[[body]]\nname = "b"\nmass = "m"\nposition = ["x", "0"]\n[[spring]]\n'
     'between = ["wall", "b"]\nstiffness = "k"\nlength = "l"\nalong = ["1", "0"]',
     ["[spring 1] along", "at most one of length, along and elongation"]),
    ('[[body]]\nname = "b"\nmass = "m"\nposition = ["x", "0"]\npin = "wall"',
     ['[body "b"] pin', "exactly one of position", "pin"]),
    ('[[body]]\nname = "b"\nmass = "m"', ['[body "b"] position', "position", "pin"]),
    ('[[body]]\nname = "b"\nmass = "m"\nposition = ["x", "0"]\n[[spring]]\n'
     'between = ["wall", "b"]\nstiffness = "k"',
     ["[spring 1] between", "zero length at the reference state", "along"]),
    ('[[body]]\nname = "b"\nmass = "m"\nposition = ["x + sin(t)", "0"]',
     ['[body "b"] position[0]', "time 't' may only appear in [signals]"]),
    ('[[body]]\nname = "b"\nmass = "m"\nposition = ["x\'", "0"]',
     ['[body "b"] position[0]', "may not depend on a rate"]),
    ('[[body]]\nname = "b"\nmass = "m*x"\nposition = ["x", "0"]',
     ['[body "b"] mass', "must be a constant"]),
    ('[[body]]\nname = "a"\nmass = "m"\npin = "c.P"\n[[body]]\nname = "c"\nmass = "m"\n'
     'pin = "a"\npoints = { P = ["1", "0"] }',
     ["pinned to each other in a cycle", "a -> c -> a"]),
    ('[[body]]\nname = "b"\nmass = "m"\nposition = ["x", "0"]\n[[force]]\nname = "F"\n'
     'point = "b.Q"\nvector = ["1", "0"]',
     ["[force 'F'] point", "unknown point 'b.Q'"]),
    ('[[body]]\nname = "b"\nmass = "m"\nposition = ["x", "0"]\nwidth = 3',
     ['[body "b"] width', "unknown key 'width'"]),
    ('[[torque]]\nbody = "nobody"\nmoment = "1"', ["[torque 1] body", "unknown body"]),
    ('[[body]]\nmass = "m"\nposition = ["x", "0"]', ["[body 1] name", "needs a name"]),
    ('[[point]]\nposition = ["1", "0"]', ["[point 2] name", "needs a name"]),
])
def test_errors_name_the_part_and_key(extra: str, expected: list[str]) -> None:
    message = errors_of(BASE + extra + '\n[energy]\nT = "m*x\'^2/2"\n')
    for text in expected:
        assert text in message, (text, message)


def test_all_problems_are_collected() -> None:
    message = errors_of(BASE + '[[body]]\nname = "b"\nmass = "m"\n[[spring]]\n'
                        'between = ["wall", "nowhere"]\nstiffness = "k"\n'
                        '[energy]\nT = "m*x\'^2/2"\n')
    assert "position" in message and "unknown point 'nowhere'" in message


def test_parts_alone_need_a_mass() -> None:
    message = errors_of(BASE.replace("[[point]]", "[[spring]]\nbetween = [\"wall\", \"wall\"]\n"
                                     "stiffness = \"k\"\nelongation = \"x\"\n[[point]]"))
    assert "no kinetic energy" in message


def test_parts_and_matrices_exclude_each_other() -> None:
    text = ('[parameters]\nm = 1\n[matrices]\nM = [[1]]\nK = [[1]]\n'
            '[[body]]\nname = "b"\nmass = "m"\nposition = ["0", "0"]\n')
    assert "parts ([[body]], [[spring]], ...) or [matrices]" in errors_of(text)


def test_too_many_parts_are_refused_before_parsing() -> None:
    from resonant.model import limits

    bodies = "".join(f'[[body]]\nname = "b{i}"\nmass = 1\nposition = ["x", "0"]\n'
                     for i in range(limits.MAX_PARTS + 1))
    message = errors_of(BASE + bodies)
    assert f"{limits.MAX_PARTS + 1} [[body]] entries" in message


def test_negative_mass_from_set_is_refused() -> None:
    status, _, err = run_cli(["check", PARTS / "cart_pendulum.toml", "--set", "m2=-1"])
    assert status == 2 and 'body "rod"' in err and "negative" in err


# -- resonant energies ------------------------------------------------------------------------

def test_cli_energies_json() -> None:
    status, out, err = run_cli(["energies", PARTS / "cart_pendulum.toml", "--json"])
    assert status == 0, err
    data = json.loads(out)
    assert set(data) >= {"T", "U", "D", "parts"}
    assert data["parts"][0] == {"kind": "body", "name": "cart", "T": "m1/2*x1'^2"}
    assert data["D"] == "0" and "cos(phi)" in data["U"]
    for key in ("T", "U"):  # the derived energies are expressions of the model language
        resonant.expressions.parse(data[key])


def test_cli_energies_text() -> None:
    status, out, _ = run_cli(["energies", PARTS / "quarter_car.toml"])
    assert status == 0
    assert 'spring "tyre"' in out and 'damper "suspension"' in out and "total:" in out
    status, out, _ = run_cli(["energies", EXAMPLES / "base_excitation.toml"])
    assert status == 0 and "no parts" in out


def test_cli_check_every_parts_example() -> None:
    for path in sorted(PARTS.glob("*.toml")):
        status, _, err = run_cli(["check", path])
        assert status == 0, (path, err)


def test_parts_model_is_still_exact() -> None:
    """Everything after the model layer is unchanged: simulate the nonlinear equations."""
    model = resonant.load(PARTS / "pendulum.toml")
    sim = model.simulate(duration=1.0, nonlinear=True)
    data = sim.to_dict()
    assert data["nonlinear"] and data["t_end"] == pytest.approx(1.0)
    assert all(math.isfinite(v) for v in data["steady_amplitudes"].values())
