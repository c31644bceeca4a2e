"""Axial and torsional coordinates of a ``[rotor]`` (``axial = true``, ``torsional = true``;
docs/rotors.md), against closed forms and Friswell's Example 5.9.1.

References:

- a fixed-free bar: omega_n = (2n - 1) pi / (2 L) sqrt(E / rho) (Rao, Mechanical
  Vibrations, ch. 8, continuous systems: the longitudinal vibration of a bar).  The consistent-mass
  linear elements overestimate omega by about (k h)^2 / 24 (k = omega sqrt(rho / E), h the
  element's length): 4e-5 for the first mode of 50 elements, 4e-4 for the second, 1e-3 for
  the third; the tolerances are these bounds.
- two discs on a torsion shaft: omega^2 = k_t (J1 + J2) / (J1 J2), k_t = G J / L (the
  two-rotor system of the textbooks, e.g. Rao, Mechanical Vibrations, ch. 5, two-degree-
  of-freedom systems), and a rigid-body rotation at 0.  A shaft of density 1e-3 kg/m^3
  adds rho J L / 3 ~ 1e-10 of the discs' inertia: tolerance 1e-9.
- Friswell, Penny, Garvey & Lees, Dynamics of Rotating Machines (2010), Example 5.9.1: the
  book's lowest six frequencies at 0 and 4000 rpm (1e-3, as ROSS's tests pin them), whose
  650.41 rad/s, the same at every speed, is the torsional mode; ROSS 2.3.0 gives it as
  650.407866 rad/s (tests/test_rotor_friswell.py), met to 1e-8.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from conftest import EXAMPLES, run_cli
from resonant import loads
from resonant.errors import ModelError
from resonant.modal import gyroscopic_modes
from resonant.system import linear_system

E, RHO, G, D = 211e9, 7810.0, 81.2e9, 0.05


def _rotor(body: str, flags: str = "axial = true") -> str:
    return f"""
[parameters]
Omega = 0
[rotor]
speed = "Omega"
E = {E}
rho = {RHO}
G = {G}
{flags}
{body}
"""


def _blocks(system, speed: float = 0.0) -> tuple[list[int], list[int]]:
    """The rows of the lateral coordinates and of the others; every M, C, G, K entry
    between them is zero (decoupled)."""
    point = system.numeric(Omega=speed)
    names = system.coordinates
    along = [i for i, n in enumerate(names) if n.endswith(("_z", "_az"))]
    lateral = [i for i in range(len(names)) if i not in along]
    for matrix in (point.M, point.C, point.K):
        dense = np.asarray(matrix.toarray() if hasattr(matrix, "toarray") else matrix)
        assert not np.any(dense[np.ix_(lateral, along)]) and not np.any(
            dense[np.ix_(along, lateral)]
        )
    return lateral, along


def test_fixed_free_bar_axial_frequencies() -> None:
    length, count = 1.0, 50
    model = loads(
        _rotor(
            f"""
shaft = [{{ length = {length}, diameter = {D}, count = {count} }}]
bearing = [{{ station = 0, kxx = 1e7, kyy = 1e7, kz = 1e16 }},
           {{ station = {count}, kxx = 1e7, kyy = 1e7 }}]
"""
        )
    )
    system = linear_system(model)
    assert system.coordinates[-1] == f"s{count}_z" and system.n == 5 * (count + 1)
    _, along = _blocks(system, 300.0)
    point = system.numeric(Omega=300.0)
    M, K = (np.asarray(a)[np.ix_(along, along)] for a in (point.M, point.K))
    found = np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True)[:3])
    exact = (2 * np.arange(1, 4) - 1) * np.pi / (2 * length) * math.sqrt(E / RHO)
    error = found / exact - 1
    assert np.all(error > 0)  # consistent mass: from above
    assert error[0] < 1e-4 and error[1] < 5e-4 and error[2] < 1.2e-3


def test_two_disc_torsional_rotor_closed_form_and_campbell() -> None:
    model = loads(
        _rotor(
            """
shaft = [{ length = 0.5, diameter = 0.05 }]
disc = [{ station = 0, name = "a", m = 30, Ip = 0.3, It = 0.15 },
        { station = 1, name = "b", m = 50, Ip = 0.8, It = 0.4 }]
bearing = [{ station = 0, kxx = 1e6, kyy = 1e6 }, { station = 1, kxx = 1e6, kyy = 1e6 }]
""",
            "torsional = true",
        ).replace(f"rho = {RHO}", "rho = 1e-3")
    )
    system = linear_system(model)
    assert system.coordinates[-2:] == ("a_az", "b_az")
    _blocks(system, 500.0)
    k_t = G * math.pi * D**4 / 32 / 0.5
    exact = math.sqrt(k_t * (0.3 + 0.8) / (0.3 * 0.8))
    result = model.campbell(np.linspace(0.0, 1000.0, 6), modes=6)
    j = result.motion.index("torsional")
    assert result.motion.count("torsional") == 1
    assert np.allclose(result.frequencies[:, j], exact, rtol=1e-9)  # the same at every speed
    assert {row[j] for row in result.whirl} == {"none"}
    assert any("rigid-body" in w for w in result.warnings)  # the free rotation left out


@pytest.mark.parametrize(
    "rpm, book",
    [
        (0.0, [86.66, 86.66, 274.31, 274.31, 650.41, 716.78]),
        (4000.0, [85.39, 87.80, 251.78, 294.71, 600.18, 650.41]),
    ],
)
def test_friswell_5_9_1_with_its_torsional_mode(rpm: float, book: list[float]) -> None:
    text = (EXAMPLES / "rotors" / "friswell_5_9_1.toml").read_text()
    model = loads(text.replace('G = "81.2 GPa"', 'G = "81.2 GPa"\naxial = true\ntorsional = true'))
    system = linear_system(model)
    lateral, along = _blocks(system, rpm * math.pi / 30)
    point = system.numeric(Omega=rpm * math.pi / 30)
    s, q = gyroscopic_modes(point.M, point.C, point.K)
    moving = np.abs(s) > 1.0  # the free axial and torsional rigid-body motions left out
    s, q = s[moving], q[:, moving]
    assert np.allclose(np.abs(s.imag[:6]), book, rtol=1e-3)
    torsional = np.abs(s.imag)[np.linalg.norm(q[along], axis=0) > 0.99][0]
    assert torsional == pytest.approx(650.407866, rel=1e-8)


@pytest.mark.parametrize(
    "flags, body, key, words",
    [
        ("torsional = true", "", "torsional", "shear modulus G"),
        ("axial = 1", "", "axial", "true or false"),
        ("", "kz = 1e9", "kz", "axial = true"),
        ("axial = true", "kaz = 1e3", "kaz", "torsional = true"),
    ],
)
def test_axial_and_torsional_bad_input(flags: str, body: str, key: str, words: str) -> None:
    text = _rotor(
        f"""
shaft = [{{ length = 0.5, diameter = 0.05 }}]
bearing = [{{ station = 0, kxx = 1e6, kyy = 1e6{", " + body if body else ""} }}]
""",
        flags,
    )
    if key == "torsional":
        text = text.replace(f"G = {G}\n", "")
    with pytest.raises(ModelError) as info:
        loads(text, source="r.toml")
    problem = next(p for p in info.value.problems if p.key == key)
    assert words in problem.message and problem.file == "r.toml"


# -- the text tables: columns as wide as their widest cell ---------------------------------

ALIGNED_ROTOR = """title = "aligned"
[parameters]
Omega = "0 rpm"
[rotor]
speed = "Omega"
E = 211e9
rho = 7810
G = 81.2e9
axial = true
torsional = true
[[rotor.shaft]]
length = 1.5
diameter = 0.05
count = 4
[[rotor.disc]]
station = 2
name = "a_disc_with_a_long_name"
width = 0.07
diameter = 0.28
inner_diameter = 0.05
[[rotor.bearing]]
station = 0
name = "the_drive_end_bearing"
kxx = 1e6
kyy = 1e6
cxx = 300
cyy = 300
kz = 1e9
kaz = 1e4
[[rotor.bearing]]
station = 4
kxx = 1e6
kyy = 1e6
[campbell]
from = "0 rpm"
to = "20000 rpm"
points = 5
modes = 6
orders = [1]
[[unbalance]]
at = "a_disc_with_a_long_name"
amount = "1e-4 kg*m"
phase = "0 deg"
"""


def _table(text: str, first: str) -> list[str]:
    """The lines of the table whose header line starts (stripped) with ``first``."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.strip().startswith(first))
    end = next((i for i in range(start + 1, len(lines)) if not lines[i].strip()), len(lines))
    return lines[start:end]


def _column(table: list[str], heading: str, cells: set[str]) -> None:
    """Every row's cell of a left-aligned column starts where its heading does."""
    at = table[0].index(heading)
    for line in table[1:]:
        assert line[at:].split()[0] in cells, (heading, line, table)
        assert line[at - 1] == " ", (heading, line)


def _ends(table: list[str], heading: str) -> None:
    """Every row's cell of a right-aligned column ends where its heading does."""
    end = table[0].index(heading) + len(heading)
    for line in table[1:]:
        assert line[end - 1] != " " and line[end] == " ", (heading, line, table)


def test_whirl_and_name_columns_are_not_cut_or_shifted(tmp_path: Path) -> None:
    """The Campbell, unbalance and speed-map texts with 'backward', 'forward', 'torsional'
    and 'axial' labels and long station and bearing names: each column as wide as its
    widest cell, so that a right-aligned column ends, and a left-aligned one starts, at
    the same place on every line."""
    model = tmp_path / "aligned.toml"
    model.write_text(ALIGNED_ROTOR, encoding="utf-8")
    status, text, err = run_cli(["campbell", model])
    assert status == 0, err
    modes = _table(text, "mode")
    labels = {line.split()[1] for line in modes[1:]}
    assert {"backward", "forward", "torsional"} <= labels
    assert len({len(line) for line in modes}) == 1, modes   # the last column ends together
    _column(modes, "whirl", {"backward", "forward", "torsional", "axial", "-"})
    critical = _table(text, "speed [rpm]")
    assert len(critical) > 2
    _column(critical, "whirl", {"backward", "forward", "none"})
    _ends(critical, "order")
    status, text, err = run_cli(["unbalance", model, "--points", "5"])
    assert status == 0, err
    stations = _table(text, "station")
    assert any("a_disc_with_a_long_name" in line for line in stations)
    _column(stations, "precession", {"forward", "backward", "line"})
    _ends(stations, "minor 0-pk")
    bearings = _table(text, "bearing")
    assert any("the_drive_end_bearing" in line for line in bearings)
    assert len({len(line) for line in bearings}) == 1, bearings
    status, text, err = run_cli(["speed-map", model, "--damped", "--stiffness", "1e5:1e7:3"])
    assert status == 0, err
    rows = _table(text, "k [N/m]")
    assert len(rows) == 4 and len({len(line) for line in rows}) == 1, rows
