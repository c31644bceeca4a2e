"""The ``[rotor]`` section: a rotor of shaft elements, discs and bearings, assembled into
the matrices of M q'' + (C + Omega G) q' + K(Omega) q = 0 (docs/rotors.md).

```toml
[rotor]
speed = "Omega"                       # the speed parameter (rad/s)
E = "211 GPa"                         # the shaft's material
rho = "7810 kg/m^3"
G = "81.2 GPa"                        # with G: Timoshenko elements, else Euler-Bernoulli
axial = false                         # true: each station's axial displacement NAME_z
torsional = false                     # true: each station's twist NAME_az (needs G)

[[rotor.shaft]]                       # elements, station after station from station 0
length = "0.25 m"
diameter = "50 mm"                    # inner_diameter optional
count = 6                             # this many equal elements

[[rotor.disc]]
station = 2
name = "disc1"                        # its coordinates: disc1_x, disc1_y, disc1_ax, disc1_ay
m = "33 kg"                           # or width, diameter, inner_diameter (of rho)
Ip = "0.3 kg*m^2"
It = "0.17 kg*m^2"

[[rotor.bearing]]
station = 0
kxx = "1 MN/m"                        # kxx kxy kyx kyy cxx cxy cyx cyy: a number, an
kyy = "1e6 + 10*Omega"                # expression of the parameters (the speed), or a
cxx = { speed = [0, 500], values = [100, 200] }   # table interpolated in speed
kz = "1 GN/m"                         # with axial = true: a thrust bearing (kz, cz);
kaz = "1 kN*m/rad"                    # with torsional = true: a torsional support (kaz, caz)
```

Each station has four coordinates: the displacements x, y and the tilts ax (about x) and
ay (about y); the spin is about z, from x towards y for a positive speed.  A station is
named by its disc or bearing (``name``), else ``s<index>``.  The shaft's elements are
those of Nelson (J. Mech. Design 102, 1980) and Friswell et al. (Dynamics of Rotating
Machines, CUP 2010, sec. 5.4): consistent mass, rotary inertia and gyroscopic matrices,
with the shear factor Phi = 12 E I / (kappa G A L^2) (Cowper's kappa of a tube).

With ``axial`` and ``torsional`` each station also has its axial displacement ``NAME_z``
and its twist about the spin axis ``NAME_az``, listed after the lateral (and pedestal)
coordinates: the shaft's bar elements (E A / L, consistent mass rho A L / 6 [[2, 1], [1, 2]])
and torsion elements (G J / L, rho J L / 6 [[2, 1], [1, 2]], J the polar second moment of
area), a disc's mass on z and its polar moment Ip on the twist, a bearing's kz, cz and
kaz, caz to the ground.  For a straight shaft spinning at a constant speed they are
decoupled from the lateral motion (no entry of M, C, G or K joins them).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ModelError, Problem
from ..expressions import Expression, ExpressionError
from ..expressions.numeric import numeric_value
from ..memory import require
from .matrix_spec import MatrixSpec
from .units import parse_with_unit

COEFFICIENTS = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")
#: a bearing's axial (kz, cz) and torsional (kaz, caz) coefficients, to the ground
AXIAL_COEFFICIENTS = ("kz", "cz", "kaz", "caz")
ROTOR_KEYS = ("speed", "E", "rho", "G", "shaft", "disc", "bearing", "axial", "torsional")
#: the most stations of a [rotor]: 10^5 coordinates (assembled sparse above
#: :data:`SPARSE_STATIONS`: some 60 stored entries a station and matrix)
MAX_STATIONS = 25_000
#: a rotor of more stations is assembled sparse (CSR; 400 coordinates, where the Campbell
#: diagram turns to the sparse eigensolver); fewer, dense
SPARSE_STATIONS = 100


@dataclass(frozen=True)
class SpeedTable:
    """A bearing coefficient tabulated in speed, interpolated linearly (held constant
    beyond the table's ends).

    Parameters
    ----------
    speeds : tuple of float
        Increasing speeds (rad/s).
    values : tuple of float
        The coefficient at each (SI).

    Examples
    --------
    >>> SpeedTable((0.0, 10.0), (1.0, 3.0))(np.array([5.0, 20.0])).tolist()
    [2.0, 3.0]
    """

    speeds: tuple[float, ...]
    values: tuple[float, ...]

    def __call__(self, speed: np.ndarray) -> np.ndarray:
        return np.interp(np.asarray(speed, dtype=float), self.speeds, self.values)


@dataclass(frozen=True)
class SpeedTerm:
    """An entry of K or C that depends on the parameters (a bearing coefficient).

    Parameters
    ----------
    key : str
        ``"K"`` or ``"C"``.
    row, column : int
        Its place.
    value : Expression or SpeedTable
        Added to the entry.
    where : str
        The bearing and coefficient, for messages (``bearing 1 kxx``).
    """

    key: str
    row: int
    column: int
    value: Expression | SpeedTable
    where: str
    sign: float = 1.0


@dataclass(frozen=True)
class Bearing:
    """A bearing of a ``[rotor]``, as the bearing forces need it: the force it transmits
    is (K_b + i Omega C_b) (z_station - z_pedestal), K_b = [[kxx, kxy], [kyx, kyy]].

    Parameters
    ----------
    name : str
        Its name (that of its station where it has none).
    station : tuple of int
        The rows of its station's x and y.
    pedestal : tuple of int or None
        The rows of its pedestal's x and y (None: the bearing is on the ground).
    coefficients : tuple of (str, value)
        ``kxx`` ... ``cyy`` given: a number (SI), an expression of the parameters or a
        :class:`SpeedTable`.
    """

    name: str
    station: tuple[int, int]
    pedestal: tuple[int, int] | None
    coefficients: tuple[tuple[str, float | Expression | SpeedTable], ...]


class _Reader:
    """The section's values with their problems collected."""

    def __init__(self, source: str, params: Sequence[str]) -> None:
        self.source, self.params, self.problems = source, params, []  # type: ignore[var-annotated]

    def problem(self, message: str, section: str, key: str) -> None:
        self.problems.append(Problem(message, self.source, section, key))

    def number(self, table: dict, key: str, section: str, *, default: float | None = None,
               positive: bool = True, signed: bool = False) -> float | None:
        """A constant (a number or a value with a unit, in SI), > 0 (or >= 0, or any
        finite number where ``signed``)."""
        raw = table.get(key, default)
        if raw is None:
            self.problem("missing", section, key)
            return None
        if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
            self.problem("must be a number or a value with a unit", section, key)
            return None
        try:
            value = float(numeric_value(parse_with_unit(raw, [], self.source, section, key)[0],
                                        {}))
        except (ExpressionError, ValueError, TypeError) as exc:
            self.problem(f"not a constant: {exc}", section, key)
            return None
        if signed and math.isfinite(value):
            return value
        if not math.isfinite(value) or value < 0 or (positive and value == 0):
            self.problem(f"must be {'positive' if positive else 'at least 0'}, got {raw!r}",
                         section, key)
            return None
        return value

    def station(self, table: dict, section: str, stations: int) -> int | None:
        raw = table.get("station")
        if isinstance(raw, bool) or not isinstance(raw, int) or not 0 <= raw < stations:
            self.problem(f"must be a station from 0 to {stations - 1}, got {raw!r}", section,
                         "station")
            return None
        return raw

    def coefficient(self, raw: object, section: str, key: str) -> Expression | SpeedTable | None:
        if isinstance(raw, dict):
            return self.table(raw, section, key)
        if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
            self.problem("must be a number, an expression of the parameters or a table "
                         "{ speed = [...], values = [...] }", section, key)
            return None
        try:
            return parse_with_unit(raw, self.params, self.source, section, key)[0]
        except ExpressionError as exc:
            self.problem(str(exc), section, key)
            return None

    def table(self, raw: dict, section: str, key: str) -> SpeedTable | None:
        speeds, values = raw.get("speed"), raw.get("values")
        if not (isinstance(speeds, list) and isinstance(values, list) and len(speeds) >= 2
                and len(speeds) == len(values)) or set(raw) - {"speed", "values"}:
            self.problem("a table is { speed = [...], values = [...] } of equal lengths (at "
                         "least 2)", section, key)
            return None
        s = [self.number({"v": v}, "v", section, positive=False) for v in speeds]
        v = [self.number({"v": x}, "v", section, positive=False) if not
             (isinstance(x, (int, float)) and not isinstance(x, bool) and x < 0)
             else float(x) for x in values]
        if any(x is None for x in s + v):
            return None
        if any(b <= a for a, b in zip(s, s[1:])):  # type: ignore[operator]
            self.problem("the table's speeds must increase", section, key)
            return None
        return SpeedTable(tuple(s), tuple(v))  # type: ignore[arg-type]


def shaft_matrices(length: float, outer: float, inner: float, E: float, rho: float,
                   shear: float | None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """One shaft element's matrices in one plane, on (w1, slope1, w2, slope2): stiffness,
    translational mass, rotary inertia mass, and P = 2 x the rotary inertia (the
    gyroscopic coupling of the two planes); Timoshenko with the shear modulus ``shear``,
    Euler-Bernoulli (Phi = 0) without (Friswell et al. 2010, eqs. 5.47-5.52).

    Examples
    --------
    >>> K, MT, MR, P = shaft_matrices(1.0, 0.1, 0.0, 2e11, 7800.0, 8e10)
    >>> rigid = np.array([1.0, 0.0, 1.0, 0.0])          # a translation: the element's mass
    >>> round(float(rigid @ MT @ rigid / (7800 * np.pi * 0.1**2 / 4)), 12)
    1.0
    >>> bool(np.allclose(K @ rigid, 0)), bool(np.allclose(P, 2 * MR))
    (True, True)
    """
    L = length
    A = math.pi * (outer ** 2 - inner ** 2) / 4
    second = math.pi * (outer ** 4 - inner ** 4) / 64
    phi = 0.0
    if shear is not None:
        nu = E / (2 * shear) - 1
        r2 = (inner / outer) ** 2
        r12 = (1 + r2) ** 2
        kappa = 6 * r12 * (1 + nu) / (r12 * (7 + 6 * nu) + r2 * (20 + 12 * nu))
        phi = 12 * E * second / (kappa * shear * A * L * L)
    c = E * second / ((1 + phi) * L ** 3)
    near, far = (4 + phi) * L * L, (2 - phi) * L * L
    K = c * np.array([[12, 6 * L, -12, 6 * L], [6 * L, near, -6 * L, far],
                      [-12, -6 * L, 12, -6 * L], [6 * L, far, -6 * L, near]])
    m1, m2, m3 = 312 + 588 * phi + 280 * phi ** 2, 44 + 77 * phi + 35 * phi ** 2, \
        108 + 252 * phi + 140 * phi ** 2
    m4, m5, m6 = 26 + 63 * phi + 35 * phi ** 2, 8 + 14 * phi + 7 * phi ** 2, \
        6 + 14 * phi + 7 * phi ** 2
    MT = rho * A * L / (840 * (1 + phi) ** 2) * np.array([
        [m1, m2 * L, m3, -m4 * L], [m2 * L, m5 * L * L, m4 * L, -m6 * L * L],
        [m3, m4 * L, m1, -m2 * L], [-m4 * L, -m6 * L * L, -m2 * L, m5 * L * L]])
    m7, m8 = 36.0, 3 - 15 * phi
    m9, m10 = 4 + 5 * phi + 10 * phi ** 2, -1 - 5 * phi + 5 * phi ** 2
    MR = rho * second / (30 * (1 + phi) ** 2 * L) * np.array([
        [m7, m8 * L, -m7, m8 * L], [m8 * L, m9 * L * L, -m8 * L, m10 * L * L],
        [-m7, -m8 * L, m7, -m8 * L], [m8 * L, m10 * L * L, -m8 * L, m9 * L * L]])
    return K, MT, MR, 2 * MR


def bar_matrices(length: float, outer: float, inner: float, modulus: float, rho: float,
                 torsion: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """One shaft element's axial (bar) or, with ``torsion``, torsional stiffness and
    consistent mass on (end 1, end 2): E A / L [[1, -1], [-1, 1]] and rho A L / 6
    [[2, 1], [1, 2]], or G J / L and rho J L / 6 with J = pi (D^4 - d^4) / 32
    (``modulus``: E, or G for torsion).

    Examples
    --------
    >>> K, M = bar_matrices(2.0, 0.1, 0.0, 8e10, 7800.0, torsion=True)
    >>> J = np.pi * 0.1**4 / 32
    >>> bool(np.allclose(K, 8e10 * J / 2 * np.array([[1, -1], [-1, 1]]))), float(M.sum() / J)
    (True, 15600.0)
    """
    area = math.pi * (outer ** 2 - inner ** 2) / 4
    section = math.pi * (outer ** 4 - inner ** 4) / 32 if torsion else area
    K = modulus * section / length * np.array([[1.0, -1.0], [-1.0, 1.0]])
    M = rho * section * length / 6 * np.array([[2.0, 1.0], [1.0, 2.0]])
    return K, M


@dataclass(frozen=True)
class Motions:
    """Where a rotor's axial and torsional coordinates start (None: not modelled); the
    coordinate of station i is ``axial + i`` (``torsional + i``).

    Parameters
    ----------
    axial, torsional : int or None
        The row of station 0's axial displacement (twist).
    """

    axial: int | None = None
    torsional: int | None = None


def _planes(a: int, b: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The coordinates of an element from station a to b in the xz plane (x, ay) and in the
    yz plane (y, ax), and the signs of the yz plane's (its slope dy/dz is -ax)."""
    xz = np.array([4 * a, 4 * a + 3, 4 * b, 4 * b + 3])
    yz = np.array([4 * a + 1, 4 * a + 2, 4 * b + 1, 4 * b + 2])
    return xz, yz, np.array([1.0, -1.0, 1.0, -1.0])


class Assembly:
    """The entries of a rotor's M, K, C and G collected as (row, column, value) triplets
    and summed into dense arrays (a small rotor) or CSR matrices (a large one).

    Parameters
    ----------
    n : int
        The coordinates.

    Examples
    --------
    >>> a = Assembly(2)
    >>> a.add("K", np.array([0, 1]), np.array([0, 1]), np.array([[1.0, 2.0], [3.0, 4.0]]))
    >>> a.add("K", np.array([1]), np.array([1]), np.array([[10.0]]))
    >>> a.matrix("K", sparse=False).tolist(), a.matrix("K", sparse=True).nnz
    ([[1.0, 2.0], [3.0, 14.0]], 4)
    """

    def __init__(self, n: int) -> None:
        self.n = n
        self.parts: dict[str, list[tuple[np.ndarray, np.ndarray, np.ndarray]]] = {
            k: [] for k in ("M", "K", "C", "G")}

    def add(self, key: str, rows: np.ndarray, columns: np.ndarray, block: np.ndarray
            ) -> None:
        """Add ``block`` (len(rows), len(columns)) at ``rows`` x ``columns`` of ``key``."""
        r, c = np.meshgrid(rows, columns, indexing="ij")
        self.parts[key].append((r.ravel(), c.ravel(), np.asarray(block, dtype=float).ravel()))

    def entries(self) -> int:
        """The triplets collected (an upper bound of the stored entries)."""
        return sum(len(v) for part in self.parts.values() for _, _, v in part)

    def matrix(self, key: str, sparse: bool) -> Any:
        """The summed matrix: CSR where ``sparse``, else a dense array."""
        parts = self.parts[key]
        rows, columns, values = (np.concatenate([p[i] for p in parts]) if parts else
                                 np.zeros(0, dtype=float if i == 2 else int) for i in range(3))
        if sparse:
            import scipy.sparse

            return scipy.sparse.coo_matrix((values, (rows, columns)),
                                           shape=(self.n, self.n)).tocsr()
        out = np.zeros((self.n, self.n))
        np.add.at(out, (rows.astype(int), columns.astype(int)), values)
        return out


def add_element(assembly: Assembly, a: int, b: int,
                element: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> None:
    """Add one plane matrix set (:func:`shaft_matrices`) to both planes, and P to G."""
    Ke, MT, MR, P = element
    xz, yz, sign = _planes(a, b)
    flip = np.outer(sign, sign)
    for key, block in (("K", Ke), ("M", MT + MR)):
        assembly.add(key, xz, xz, block)
        assembly.add(key, yz, yz, flip * block)
    # T = rho Ip Omega ax' ay per unit length: ay rows, ax columns +P; ax rows, ay columns -P
    assembly.add("G", xz, yz, P * sign[None, :])
    assembly.add("G", yz, xz, -sign[:, None] * P)


def _disc(reader: _Reader, entry: dict, where: str, rho: float | None
          ) -> tuple[float, float, float] | None:
    if "m" in entry:
        m = reader.number(entry, "m", where)
        Ip = reader.number(entry, "Ip", where, default=0, positive=False)
        It = reader.number(entry, "It", where, default=0, positive=False)
        return None if m is None or Ip is None or It is None else (m, Ip, It)
    width, outer = reader.number(entry, "width", where), reader.number(entry, "diameter", where)
    inner = reader.number(entry, "inner_diameter", where, default=0, positive=False)
    if width is None or outer is None or inner is None or rho is None:
        return None
    m = rho * math.pi * (outer ** 2 - inner ** 2) / 4 * width
    Ip = m * (outer ** 2 + inner ** 2) / 8
    return m, Ip, Ip / 2 + m * width ** 2 / 12


def _names(stations: int, entries: list[tuple[int | None, str]]) -> list[str]:
    names = [f"s{i}" for i in range(stations)]
    for station, name in entries:
        if station is not None and name:
            names[station] = name
    return names


def read_rotor(section: object, params: Sequence[str], source: str
               ) -> tuple[MatrixSpec, tuple[str, ...]]:
    """The ``[rotor]`` section assembled: its matrices (``G`` and ``speed`` set, the
    bearings' parameter-dependent coefficients as :class:`SpeedTerm`) and coordinates.

    Raises
    ------
    ModelError
        Naming the file, the entry and the key of every problem.

    Examples
    --------
    >>> spec, names = read_rotor({"speed": "W", "disc": [{"station": 0, "name": "d", "m": 2,
    ...     "Ip": 0.1, "It": 0.05}], "bearing": [{"station": 0, "kxx": 100, "kyy": "100 + W"}]},
    ...     ["W"], "r.toml")
    >>> names, spec.M.diagonal().tolist(), float(spec.G[2, 3]), len(spec.speed_terms)
    (('d_x', 'd_y', 'd_ax', 'd_ay'), [2.0, 2.0, 0.05, 0.05], 0.1, 1)
    """
    if not isinstance(section, dict):
        raise ModelError(Problem("[rotor] must be a table", source, "rotor"))
    reader = _Reader(source, params)
    for key in section:
        if key not in ROTOR_KEYS:
            reader.problem(f"unknown key; [rotor] takes {', '.join(ROTOR_KEYS)}", "rotor", key)
    speed = section.get("speed")
    if not isinstance(speed, str) or speed not in params:
        reader.problem(f"must name a parameter (the spin speed), got {speed!r}", "rotor",
                       "speed")
    shafts, discs, bearings = (_entries(reader, section, k) for k in ("shaft", "disc", "bearing"))
    E = reader.number(section, "E", "rotor") if shafts else None
    rho = reader.number(section, "rho", "rotor") if shafts or any(
        "m" not in d for d in discs) else None
    shear = reader.number(section, "G", "rotor") if "G" in section else None
    axial, torsional = (_flag(reader, section, key) for key in ("axial", "torsional"))
    if torsional and shafts and "G" not in section:
        reader.problem("torsional coordinates need the shaft's shear modulus G (its "
                       "torsional stiffness is G J / L): give G in [rotor]", "rotor",
                       "torsional")
    elements = _shaft_elements(reader, shafts)
    stations = 1 + len(elements)
    if stations > MAX_STATIONS:
        raise ModelError(Problem(f"{stations} stations: at most {MAX_STATIONS}", source,
                                 "rotor", "shaft"))
    sparse = stations > SPARSE_STATIONS
    pedestals = sum(1 for b in bearings if "pedestal" in b)
    n = 4 * stations + 2 * pedestals
    motions = Motions(n if axial else None,
                      n + stations * axial if torsional else None)
    n += stations * (axial + torsional)
    _require_memory(n, len(elements) + len(discs) + len(bearings), sparse)
    assembly = Assembly(n)
    if E is not None and rho is not None:
        _add_shaft(assembly, elements, E, rho, shear, motions)
    named = _add_discs(reader, discs, stations, rho, assembly, motions)
    terms, bearing_names, records = _add_bearings(reader, bearings, stations, assembly,
                                                  motions)
    if reader.problems:
        raise ModelError(reader.problems)
    M, K, C, G = (assembly.matrix(k, sparse) for k in ("M", "K", "C", "G"))
    names = _names(stations, named + bearing_names)
    coordinates = tuple(f"{s}_{c}" for s in names for c in ("x", "y", "ax", "ay"))
    named_bearings = tuple(_named_bearing(b, names) for b in records)
    coordinates += tuple(f"{b.name}_pedestal_{c}" for b in named_bearings
                         if b.pedestal is not None for c in ("x", "y"))
    coordinates += tuple(f"{s}_z" for s in names if axial)
    coordinates += tuple(f"{s}_az" for s in names if torsional)
    if len(set(coordinates)) != len(coordinates):
        raise ModelError(Problem("two stations have the same name", source, "rotor", "name"))
    return MatrixSpec(M=M, K=K, C=C, G=G, speed=str(speed), speed_terms=tuple(terms),
                      bearings=named_bearings), coordinates


def _named_bearing(bearing: Bearing, names: list[str]) -> Bearing:
    """The bearing named after its station where it has no name."""
    if bearing.name:
        return bearing
    return Bearing(names[bearing.station[0] // 4], bearing.station, bearing.pedestal,
                   bearing.coefficients)


def _flag(reader: _Reader, section: dict, key: str) -> bool:
    value = section.get(key, False)
    if not isinstance(value, bool):
        reader.problem(f"must be true or false, got {value!r}", "rotor", key)
        return False
    return value


def _add_shaft(assembly: Assembly, elements: list[tuple[float, float, float]], E: float,
               rho: float, shear: float | None, motions: Motions = Motions()) -> None:
    """Every shaft element's matrices (computed once for the equal elements of a run), and
    its bar and torsion elements where the rotor has those coordinates."""
    computed: dict[tuple[float, float, float], Any] = {}
    along = [(start, modulus, torsion)
             for start, modulus, torsion in ((motions.axial, E, False),
                                             (motions.torsional, shear, True))
             if start is not None and modulus is not None]
    bars: dict[tuple[float, float, float, bool], tuple[np.ndarray, np.ndarray]] = {}
    for i, geometry in enumerate(elements):
        if geometry not in computed:
            computed[geometry] = shaft_matrices(*geometry, E, rho, shear)
        add_element(assembly, i, i + 1, computed[geometry])
        for start, modulus, torsion in along:
            key = (*geometry, torsion)
            if key not in bars:
                bars[key] = bar_matrices(*geometry, modulus, rho, torsion)
            rows = np.array([start + i, start + i + 1])
            assembly.add("K", rows, rows, bars[key][0])
            assembly.add("M", rows, rows, bars[key][1])


def _require_memory(n: int, parts: int, sparse: bool) -> None:
    """Refuse a rotor whose assembly would not fit the memory budget, before it starts:
    each element, disc or bearing adds at most 192 triplets (row, column, value: 24 bytes,
    kept while they are summed into as many stored entries), and a dense rotor four
    n x n arrays."""
    triplets = 192 * parts * (24 + 12)
    require(triplets + (0 if sparse else 4 * 8.0 * n * n),
            f"the matrices of a [rotor] of {n} coordinates", "use fewer shaft elements")


def _entries(reader: _Reader, section: dict, key: str) -> list[dict]:
    raw = section.get(key, [])
    if not isinstance(raw, list) or not all(isinstance(e, dict) for e in raw):
        reader.problem(f"must be an array of tables ([[rotor.{key}]])", "rotor", key)
        return []
    return raw


def _shaft_elements(reader: _Reader, shafts: list[dict]) -> list[tuple[float, float, float]]:
    elements = []
    for i, entry in enumerate(shafts, start=1):
        where = f"rotor.shaft {i}"
        length, outer = reader.number(entry, "length", where), \
            reader.number(entry, "diameter", where)
        inner = reader.number(entry, "inner_diameter", where, default=0, positive=False)
        count = entry.get("count", 1)
        if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= \
                MAX_STATIONS:
            reader.problem(f"must be a positive integer, got {count!r}", where, "count")
            continue
        if inner is not None and outer is not None and inner >= outer:
            reader.problem("must be below diameter", where, "inner_diameter")
            continue
        if length is not None and outer is not None and inner is not None:
            elements += [(length / count, outer, inner)] * count
    return elements


def _add_discs(reader: _Reader, discs: list[dict], stations: int, rho: float | None,
               assembly: Assembly, motions: Motions = Motions()
               ) -> list[tuple[int | None, str]]:
    named = []
    for i, entry in enumerate(discs, start=1):
        where = f"rotor.disc {i}"
        station = reader.station(entry, where, stations)
        inertia = _disc(reader, entry, where, rho)
        named.append((station, str(entry.get("name", ""))))
        if station is None or inertia is None:
            continue
        m, Ip, It = inertia
        s = 4 * station + np.arange(4)
        assembly.add("M", s, s, np.diag([m, m, It, It]))
        assembly.add("G", s[2:], s[2:], np.array([[0.0, Ip], [-Ip, 0.0]]))
        for start, value in ((motions.axial, m), (motions.torsional, Ip)):
            if start is not None:
                assembly.add("M", np.array([start + station]), np.array([start + station]),
                             np.array([[value]]))
    return named


PEDESTAL_KEYS = ("m", *COEFFICIENTS)


def _add_bearings(reader: _Reader, bearings: list[dict], stations: int, assembly: Assembly,
                  motions: Motions = Motions()
                  ) -> tuple[list[SpeedTerm], list[tuple[int | None, str]], list[Bearing]]:
    """Every bearing's coefficients into K and C (between its station and the ground, or
    its pedestal), the pedestals' masses and supports; the bearings' records."""
    terms: list[SpeedTerm] = []
    named: list[tuple[int | None, str]] = []
    records: list[Bearing] = []
    pedestal_row = 4 * stations
    for i, entry in enumerate(bearings, start=1):
        where = f"rotor.bearing {i}"
        station = reader.station(entry, where, stations)
        named.append((station, str(entry.get("name", ""))))
        _check_bearing_keys(reader, entry, where)
        pedestal = None
        if "pedestal" in entry:
            pedestal = (pedestal_row, pedestal_row + 1)
            pedestal_row += 2
            terms += _add_pedestal(reader, entry["pedestal"], f"{where} pedestal", pedestal,
                                   assembly)
        if station is None:
            continue
        rows = (4 * station, 4 * station + 1)
        given = []
        for key in COEFFICIENTS:
            if key not in entry:
                continue
            value = _coefficient(reader, entry, where, key)
            if value is None:
                continue
            given.append((key, value))
            terms += _connect(assembly, key, value, rows, pedestal, f"{where} {key}")
        terms += _add_axial(reader, entry, where, station, assembly, motions)
        records.append(Bearing(str(entry.get("name", "")), rows, pedestal, tuple(given)))
    return terms, named, records


def _coefficient(reader: _Reader, entry: dict, where: str, key: str
                 ) -> float | Expression | SpeedTable | None:
    """A bearing coefficient as read, a constant expression folded to its number."""
    read = reader.coefficient(entry[key], where, key)
    if isinstance(read, Expression) and not read.names():
        return float(numeric_value(read, {}))
    return read


def _check_bearing_keys(reader: _Reader, entry: dict, where: str) -> None:
    for key in ("k", "c"):
        if key in entry:
            reader.problem(f"give the coefficients one by one ({key}xx, {key}xy, {key}yx, "
                           f"{key}yy): a bearing's matrix is 2 x 2 on x and y", where, key)
    for key in set(entry) - {"station", "name", "k", "c", "pedestal", *COEFFICIENTS,
                             *AXIAL_COEFFICIENTS}:
        reader.problem(f"unknown key; a bearing takes station, name, pedestal, "
                       f"{', '.join(COEFFICIENTS)} and {', '.join(AXIAL_COEFFICIENTS)}",
                       where, key)


def _add_axial(reader: _Reader, entry: dict, where: str, station: int, assembly: Assembly,
               motions: Motions) -> list[SpeedTerm]:
    """A bearing's axial (kz, cz) and torsional (kaz, caz) coefficients, between its
    station and the ground (a pedestal carries the lateral coefficients only)."""
    terms = []
    for key in AXIAL_COEFFICIENTS:
        if key not in entry:
            continue
        torsional = key.endswith("az")
        start = motions.torsional if torsional else motions.axial
        if start is None:
            reader.problem(f"{key} needs {'torsional' if torsional else 'axial'} = true in "
                           "[rotor]", where, key)
            continue
        value = _coefficient(reader, entry, where, key)
        if value is None:
            continue
        row, matrix = start + station, key[0].upper()
        if isinstance(value, float):
            assembly.add(matrix, np.array([row]), np.array([row]), np.array([[value]]))
        else:
            terms.append(SpeedTerm(matrix, row, row, value, f"{where} {key}"))
    return terms


def _connect(assembly: Assembly, key: str, value: float | Expression | SpeedTable,
             rows: tuple[int, int], pedestal: tuple[int, int] | None, where: str
             ) -> list[SpeedTerm]:
    """One coefficient (``kxy``: the force on x per displacement in y) between the station
    and the ground (one entry) or the pedestal (+ on the station's and the pedestal's own
    entries, - on the cross ones); a parameter-dependent one as speed terms."""
    a, b = int(key[1] == "y"), int(key[2] == "y")
    ends = [(rows[a], rows[b], 1.0)]
    if pedestal is not None:
        ends += [(rows[a], pedestal[b], -1.0), (pedestal[a], rows[b], -1.0),
                 (pedestal[a], pedestal[b], 1.0)]
    matrix = key[0].upper()
    if isinstance(value, float):
        for row, column, sign in ends:
            assembly.add(matrix, np.array([row]), np.array([column]),
                         np.array([[sign * value]]))
        return []
    return [SpeedTerm(matrix, row, column, value, where, sign) for row, column, sign in ends]


def _add_pedestal(reader: _Reader, raw: object, where: str, rows: tuple[int, int],
                  assembly: Assembly) -> list[SpeedTerm]:
    """A pedestal (support) mass m on x and y, on the ground through its coefficients
    kxx ... cyy: numbers (a direct one at least 0), expressions of the parameters (the
    speed) or tables in speed, as a bearing's; those that are not constants as speed
    terms (``where`` names the pedestal)."""
    if not isinstance(raw, dict):
        reader.problem("a pedestal is a table { m = ..., kxx = ..., kyy = ..., cxx = ... }",
                       where, "pedestal")
        return []
    for key in set(raw) - set(PEDESTAL_KEYS):
        reader.problem(f"unknown key; a pedestal takes {', '.join(PEDESTAL_KEYS)}", where, key)
    m = reader.number(raw, "m", where)
    if m is not None:
        assembly.add("M", np.array(rows), np.array(rows), m * np.eye(2))
    terms: list[SpeedTerm] = []
    for key in COEFFICIENTS:
        if key not in raw:
            continue
        constant = isinstance(raw[key], (int, float)) and not isinstance(raw[key], bool)
        if constant or (isinstance(raw[key], str) and not _has_names(raw[key], reader)):
            value = reader.number(raw, key, where, positive=False, signed=key[1] != key[2])
            if value is not None:
                _connect(assembly, key, value, rows, None, where)
            continue
        read = reader.coefficient(raw[key], where, key)
        if read is not None:
            terms += _connect(assembly, key, read, rows, None, f"{where} {key}")
    return terms


def _has_names(text: str, reader: _Reader) -> bool:
    """Whether a coefficient's text names a parameter (else it is a constant)."""
    try:
        return bool(parse_with_unit(text, reader.params, reader.source, "", "")[0].names())
    except ExpressionError:
        return False
