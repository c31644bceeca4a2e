"""Measured data: functions, modes and geometry from Universal Files, time histories from
CSV and NumPy files (docs/testing.md).

A measurement is untrusted input.  Universal File Format datasets are read and written
through pyuff (the ``testdata`` extra, imported when a file is read): 58 (functions:
time histories, spectra, frequency response functions, coherences; ASCII and the binary
58b), 55 (mode shapes at nodes), 15 and 2411 (node coordinates) and 164 (the file's units,
which convert every function to SI).  Any other dataset, a record pyuff cannot read, a
truncated record, a NaN sample, channels sampled at different rates: a
:class:`~resonant.errors.ModelError` naming the file, the record and what is wrong.
Nothing is resampled.

Time histories in text or NumPy form (:func:`read_histories`):

* CSV: a header line ``time,NAME1,NAME2,...`` then one sample a line, the first column the
  time in seconds at a constant step, each further column one channel;
* ``.npy``: a 2-D array, column 0 the time, columns 1... the channels ``ch1``, ``ch2``, ...;
* ``.npz``: an array ``time`` and one 1-D array per channel, named by its key.

Examples
--------
>>> import numpy as np
>>> f = MeasuredFunction("a3", "time", np.arange(4) * 1e-3, np.array([0.0, 1.0, 0.5, 0.0]),
...                      "s", "m/s^2", (3, 1), (3, 1))
>>> f.step, f.samples
(0.001, 4)
>>> MeasuredData("lab", (f,)).function("a3").ordinate_unit
'm/s^2'
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from types import ModuleType
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..errors import ModelError, Problem, name_list, printable
from ..memory import require
from .files import FileRefused, open_regular_file, read_bounded
from .limits import MAX_COMPRESSION_RATIO
from .uff_bounds import check_uff

#: the largest measurement file read
MAX_BYTES = 512 * 2**20
#: the datasets read (164 only for its units)
DATASETS = (15, 55, 58, 164, 2411)
#: datasets that describe, not measure, and are passed over (named in the data's notes):
#: header, coordinate systems, trace lines, 58 qualifiers, model header, elements, groups
DESCRIPTIVE = {151: "header", 18: "coordinate systems", 82: "trace lines",
               1858: "dataset 58 qualifiers", 2400: "model header", 2412: "elements",
               2420: "coordinate systems", 2429: "groups", 2467: "groups"}
#: function types of dataset 58 (its record 6, field 1) by name
FUNCTION_TYPES = {0: "general", 1: "time", 2: "autospectrum", 3: "cross-spectrum",
                  4: "frf", 5: "transmissibility", 6: "coherence", 9: "psd", 12: "spectrum"}
#: SI units of the UFF specific data types (record 8-10, field 1)
DATA_UNITS = {8: "m", 9: "N", 11: "m/s", 12: "m/s^2", 13: "N", 15: "Pa", 16: "kg",
              17: "s", 18: "Hz"}
#: UFF directions by code (record 6, fields 6 and 9)
DIRECTIONS = {0: "", 1: "+X", 2: "+Y", 3: "+Z", 4: "+RX", 5: "+RY", 6: "+RZ",
              -1: "-X", -2: "-Y", -3: "-Z", -4: "-RX", -5: "-RY", -6: "-RZ"}
#: the most samples a CSV history holds (a line each)
MAX_SAMPLES = 10_000_000
#: most members of an .npz of histories (the time and the channels)
MAX_MEMBERS = 4097
#: relative spread of the sampling steps accepted as one step
STEP_TOLERANCE = 1e-6

#: the suffixes read as Universal Files (the other measurement files: CSV, .npy, .npz)
UFF_SUFFIXES = (".uff", ".unv", ".uf", ".bunv")

__all__ = ["MeasuredFunction", "MeasuredMode", "MeasuredData", "read_uff", "write_uff",
           "read_histories", "DATASETS", "DESCRIPTIVE", "FUNCTION_TYPES"]


@dataclass(frozen=True)
class MeasuredFunction:
    """One measured function: a channel's history, spectrum or frequency response.

    Parameters
    ----------
    name : str
        The channel's name (the UFF record's first ID line, else ``node+direction``).
    kind : str
        ``"time"``, ``"frf"``, ``"coherence"``, ... (:data:`FUNCTION_TYPES`).
    abscissa : ndarray
        Times (s) or frequencies (Hz), equally spaced.
    ordinate : ndarray
        The values (real, or complex for a spectrum or an FRF), in SI units.
    abscissa_unit, ordinate_unit : str
        Their units (``"s"``, ``"Hz"``, ``"m/s^2/N"``; ``""`` when the file gives none).
    response : tuple of int
        The response node and direction code (UFF record 6).
    reference : tuple of int
        The reference (excitation) node and direction code.
    """

    name: str
    kind: str
    abscissa: np.ndarray
    ordinate: np.ndarray
    abscissa_unit: str = ""
    ordinate_unit: str = ""
    response: tuple[int, int] = (0, 0)
    reference: tuple[int, int] = (0, 0)

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def step(self) -> float:
        """The abscissa's constant step (s or Hz)."""
        return float(self.abscissa[1] - self.abscissa[0]) if len(self.abscissa) > 1 else 0.0

    @property
    def samples(self) -> int:
        """The number of samples (or spectral lines)."""
        return len(self.ordinate)


@dataclass(frozen=True)
class MeasuredMode:
    """One mode shape of dataset 55 (identified elsewhere, or written by resonant).

    Parameters
    ----------
    frequency : float
        Natural frequency (Hz).
    damping : float
        Damping ratio (0 for a normal mode).
    nodes : ndarray
        The node numbers.
    shape : ndarray
        (nodes, 3) the translations at each node (complex for a complex mode).
    """

    frequency: float
    damping: float
    nodes: np.ndarray
    shape: np.ndarray

    def __post_init__(self) -> None:
        freeze_fields(self)


@dataclass(frozen=True)
class MeasuredData:
    """What a measurement file holds: functions, modes and node coordinates.

    Parameters
    ----------
    source : str
        The file's name (no folder).
    functions : tuple of MeasuredFunction
    modes : tuple of MeasuredMode
    geometry : mapping
        Node number -> its (x, y, z) coordinates (m).
    notes : tuple of str
        What was passed over (descriptive datasets, :data:`DESCRIPTIVE`).
    """

    source: str
    functions: tuple[MeasuredFunction, ...] = ()
    modes: tuple[MeasuredMode, ...] = ()
    geometry: Mapping[int, tuple[float, float, float]] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    @property
    def names(self) -> tuple[str, ...]:
        """The functions' names in order."""
        return tuple(f.name for f in self.functions)

    def function(self, name: str) -> MeasuredFunction:
        """The function called ``name``.

        Parameters
        ----------
        name : str

        Returns
        -------
        MeasuredFunction

        Raises
        ------
        ModelError
            When the file holds no function of that name (the message lists them).

        Examples
        --------
        >>> MeasuredData("lab.uff").function("a1")
        Traceback (most recent call last):
        resonant.errors.ModelError: lab.uff: no channel 'a1' (channels: none)
        """
        for f in self.functions:
            if f.name == name:
                return f
        raise ModelError(Problem(f"no channel '{printable(name, limit=40)}' (channels: "
                                 f"{name_list(self.names) or 'none'})", self.source))


def _pyuff() -> Any:
    try:
        import pyuff
    except ImportError:
        raise ModelError("reading Universal Files needs pyuff: pip install "
                         "'resonant[testdata]'") from None
    return pyuff


def _checked_path(path: str | os.PathLike[str]) -> str:
    """The path of a regular, bounded file; a ModelError otherwise."""
    name = os.path.basename(os.fspath(path))
    try:
        with open_regular_file(path, follow_symlinks=True, max_bytes=MAX_BYTES):
            pass
    except (OSError, FileRefused) as exc:
        raise ModelError(Problem(f"cannot read the measurement: {exc}", name)) from None
    return os.fspath(path)


def read_uff(path: str | os.PathLike[str]) -> MeasuredData:
    """The functions, modes and geometry of a Universal File (through pyuff).

    Parameters
    ----------
    path : str or PathLike

    Returns
    -------
    MeasuredData
        Every function in SI units (the file's dataset 164 converts them), in file order.

    Raises
    ------
    ModelError
        For a file whose reading would exceed the memory budget, or whose dataset 58
        header announces more points than the record holds (checked from the bytes before
        pyuff parses them: :func:`resonant.model.uff_bounds.check_uff`), an unreadable
        file, a dataset other than :data:`DATASETS` and
        :data:`DESCRIPTIVE`, a record pyuff cannot read or one that is truncated, NaN or
        infinite values, or functions of one kind sampled at different steps (the message
        names the record).

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> t = np.arange(8) * 0.01
    >>> f = MeasuredFunction("a1", "time", t, np.sin(t), "s", "m/s^2", (1, 3), (1, 3))
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "lab.uff")
    ...     write_uff(path, MeasuredData("lab.uff", (f,)))
    ...     back = read_uff(path)
    >>> a1 = back.functions[0]
    >>> back.names, a1.ordinate_unit, bool(np.allclose(a1.ordinate, np.sin(t)))
    (('a1',), 'm/s^2', True)
    """
    checked = _checked_path(path)
    name = os.path.basename(checked)
    pyuff = _pyuff()
    check_uff(checked)              # the memory and the declared sizes, before pyuff parses
    try:
        uff = pyuff.UFF(checked)
        types = [int(t) for t in uff.get_set_types()]
    except Exception as exc:  # pyuff raises anything for a malformed file
        raise ModelError(Problem(f"not a Universal File pyuff can read ({_reason(exc)})",
                                 name)) from None
    if not types:
        raise ModelError(Problem("no Universal File dataset found (a dataset starts with a "
                                 "line '    -1' and its number)", name))
    _check_ending(checked, name, len(types))
    notes = []
    for record, kind in enumerate(types, start=1):
        if kind in DESCRIPTIVE:
            notes.append(f"record {record}: dataset {kind} ({DESCRIPTIVE[kind]}) passed over")
        elif kind not in DATASETS:
            raise ModelError(Problem(f"record {record}: dataset {kind} is not read (read: "
                                     f"{', '.join(map(str, DATASETS))}; passed over: "
                                     f"{', '.join(map(str, DESCRIPTIVE))})", name))
    sets: list[dict[str, Any]] = []
    for record in range(len(types)):
        if types[record] in DESCRIPTIVE:
            sets.append({"type": types[record]})
            continue
        try:
            sets.append(uff.read_sets(record))
        except Exception as exc:
            raise ModelError(Problem(f"record {record + 1} (dataset {types[record]}) is "
                                     f"malformed or truncated ({_reason(exc)})", name)) from None
    factors = _unit_factors(sets, name)
    functions, modes, geometry = [], [], {}
    for record, dataset in enumerate(sets, start=1):
        kind = types[record - 1]
        where = f"record {record} (dataset {kind})"
        if kind == 58:
            functions.append(_function(dataset, factors, name, where))
        elif kind == 55:
            modes.append(_mode(dataset, name, where))
        elif kind in (15, 2411):
            geometry.update(_nodes(dataset, factors[0], name, where))
    _check_steps(functions, name)
    return MeasuredData(name, tuple(_unique_names(functions)), tuple(modes), geometry,
                        tuple(notes))


def _check_ending(path: str, name: str, complete: int) -> None:
    """A file that ends inside a record is refused (pyuff leaves such a record out)."""
    with open(path, "rb") as handle:
        handle.seek(0, os.SEEK_END)
        handle.seek(max(0, handle.tell() - 256))
        tail = handle.read().rstrip()
    if not tail.endswith(b"    -1"):        # (58b: the binary values run up to it)
        raise ModelError(Problem(f"record {complete + 1} is truncated: the file ends inside it "
                                 "(a record ends with a line '    -1')", name))


def _reason(exc: BaseException) -> str:
    return printable(f"{type(exc).__name__}: {exc}", limit=120)


def _unit_factors(sets: list[dict[str, Any]], name: str) -> tuple[float, float, float]:
    """Length, force and temperature factors of dataset 164 (file units per SI unit)."""
    for record, dataset in enumerate(sets, start=1):
        if int(dataset.get("type", 0)) == 164:
            try:
                values = tuple(float(dataset[k]) for k in ("length", "force", "temp"))
            except (KeyError, TypeError, ValueError):
                raise ModelError(Problem(f"record {record} (dataset 164): unit factors "
                                         "missing or not numbers", name)) from None
            if not all(math.isfinite(v) and v > 0 for v in values):
                raise ModelError(Problem(f"record {record} (dataset 164): the unit factors "
                                         "must be positive numbers", name))
            return values[0], values[1], values[2]
    return 1.0, 1.0, 1.0


def _axis_unit(dataset: Mapping[str, Any], prefix: str) -> str:
    code = int(dataset.get(f"{prefix}_spec_data_type", 0) or 0)
    return DATA_UNITS.get(code, "")


def _axis_factor(dataset: Mapping[str, Any], prefix: str,
                 factors: tuple[float, float, float]) -> float:
    """Divide a file value by this to get SI (dataset 164: SI = value / factor)."""
    exponents = [float(dataset.get(f"{prefix}_{k}_unit_exp", 0) or 0)
                 for k in ("len", "force", "temp")]
    return float(np.prod([f ** e for f, e in zip(factors, exponents, strict=True)]))


def _function(dataset: Mapping[str, Any], factors: tuple[float, float, float], name: str,
              where: str) -> MeasuredFunction:
    try:
        x = np.asarray(dataset["x"], dtype=float).ravel()
        y = np.asarray(dataset["data"]).ravel()
        kind = FUNCTION_TYPES.get(int(dataset.get("func_type", 0)), "general")
        response = (int(dataset.get("rsp_node", 0)), int(dataset.get("rsp_dir", 0)))
        reference = (int(dataset.get("ref_node", 0)), int(dataset.get("ref_dir", 0)))
        label = str(dataset.get("id1", "") or "").strip()
        label = "" if label.upper() == "NONE" else label
    except (KeyError, TypeError, ValueError) as exc:
        raise ModelError(Problem(f"{where}: malformed function ({_reason(exc)})",
                                 name)) from None
    expected = int(dataset.get("num_pts", len(y)) or len(y))
    if len(y) != expected or len(x) != len(y) or len(y) < 2:
        raise ModelError(Problem(f"{where}: truncated: {len(y)} values of the {expected} its "
                                 "header announces", name))
    if not np.isfinite(y).all() or not np.isfinite(x).all():
        bad = int(np.flatnonzero(~np.isfinite(y) | ~np.isfinite(x))[0])
        raise ModelError(Problem(f"{where}: value {bad + 1} is NaN or infinite; measured "
                                 "data must be finite (remove or repair the sample)", name))
    numerator = _axis_unit(dataset, "ordinate")
    denominator = _axis_unit(dataset, "orddenom") if kind in ("frf", "transmissibility") \
        else ""
    ordinate = y / _axis_factor(dataset, "ordinate", factors)
    if denominator:
        ordinate = ordinate * _axis_factor(dataset, "orddenom", factors)
    unit = f"{numerator}/{denominator}" if numerator and denominator else numerator
    abscissa_unit = _axis_unit(dataset, "abscissa") or ("s" if kind == "time" else "Hz")
    if not label:
        label = f"{response[0]}{DIRECTIONS.get(response[1], '')}"
    return MeasuredFunction(label, kind, x, ordinate, abscissa_unit, unit, response,
                            reference)


def _mode(dataset: Mapping[str, Any], name: str, where: str) -> MeasuredMode:
    try:
        nodes = np.asarray(dataset["node_nums"], dtype=int).ravel()
        columns = [np.asarray(dataset[k]).ravel() for k in ("r1", "r2", "r3")]
        frequency = float(dataset.get("freq", 0.0))
        damping = float(dataset.get("modal_damp_vis", 0.0) or 0.0)
    except (KeyError, TypeError, ValueError) as exc:
        raise ModelError(Problem(f"{where}: malformed mode shape ({_reason(exc)})",
                                 name)) from None
    shape = np.column_stack(columns) if all(len(c) == len(nodes) for c in columns) else None
    if shape is None or not np.isfinite(shape).all() or not math.isfinite(frequency):
        raise ModelError(Problem(f"{where}: the mode shape is truncated or holds NaN", name))
    return MeasuredMode(frequency, damping, nodes, shape)


def _nodes(dataset: Mapping[str, Any], length: float, name: str, where: str
           ) -> dict[int, tuple[float, float, float]]:
    try:
        nodes = np.asarray(dataset["node_nums"], dtype=int).ravel()
        xyz = np.column_stack([np.asarray(dataset[k], dtype=float).ravel()
                               for k in ("x", "y", "z")]) / length
    except (KeyError, TypeError, ValueError) as exc:
        raise ModelError(Problem(f"{where}: malformed node coordinates ({_reason(exc)})",
                                 name)) from None
    if len(xyz) != len(nodes) or not np.isfinite(xyz).all():
        raise ModelError(Problem(f"{where}: node coordinates truncated or NaN", name))
    return {int(n): (float(p[0]), float(p[1]), float(p[2])) for n, p in zip(nodes, xyz,
                                                                            strict=True)}


def _check_steps(functions: Sequence[MeasuredFunction], name: str) -> None:
    """Every function equally spaced, and all of one kind at one step."""
    first: dict[str, tuple[float, str]] = {}
    for f in functions:
        steps = np.diff(f.abscissa)
        step = float(steps.mean())
        if not step > 0 or np.abs(steps - step).max() > STEP_TOLERANCE * step:
            raise ModelError(Problem(f"channel '{f.name}': the abscissa is not equally spaced; "
                                     "resample it before reading (nothing is resampled here)",
                                     name))
        seen = first.setdefault(f.kind, (step, f.name))
        if abs(step - seen[0]) > STEP_TOLERANCE * seen[0]:
            raise ModelError(Problem(
                f"channel '{f.name}' is sampled at a step of {step:.6g} {f.abscissa_unit}, "
                f"channel '{seen[1]}' at {seen[0]:.6g}: the channels must share one sampling "
                "rate (nothing is resampled)", name))


def _unique_names(functions: list[MeasuredFunction]) -> list[MeasuredFunction]:
    """The names made unique by a suffix (``a1``, ``a1#2``): a channel is found by name."""
    seen: dict[str, int] = {}
    out = []
    for f in functions:
        count = seen.get(f.name, 0) + 1
        seen[f.name] = count
        out.append(f if count == 1 else MeasuredFunction(
            f"{f.name}#{count}", f.kind, f.abscissa, f.ordinate, f.abscissa_unit,
            f.ordinate_unit, f.response, f.reference))
    return out


_CODES = {v: k for k, v in FUNCTION_TYPES.items()}
_UNIT_CODES = {"m": 8, "m/s": 11, "m/s^2": 12, "N": 13, "Pa": 15, "kg": 16, "s": 17,
               "Hz": 18}
#: the (length, force) exponents of each unit (dataset 58 records 8-10, fields 2 and 3)
_EXPONENTS = {"m": (1, 0), "m/s": (1, 0), "m/s^2": (1, 0), "N": (0, 1), "Pa": (-2, 1),
              "kg": (-1, 1)}


def write_uff(path: str | os.PathLike[str], data: MeasuredData, *,
              binary: bool = False) -> None:
    """Write the functions (dataset 58, or 58b with ``binary``), the modes (55) and the
    geometry (15) of ``data`` as a Universal File, in SI units (with its dataset 164).

    Parameters
    ----------
    path : str or PathLike
        The file (overwritten).
    data : MeasuredData
    binary : bool, optional
        Write the functions as binary 58b records.

    Raises
    ------
    ModelError
        For NaN or infinite values (pyuff would write them as zeros).

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> f = np.arange(1.0, 5.0)
    >>> h = MeasuredFunction("H33", "frf", f, 1 / (1 + 1j * f), "Hz", "m/N", (3, 3), (3, 3))
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "frf.uff")
    ...     write_uff(path, MeasuredData("frf.uff", (h,)), binary=True)
    ...     back = read_uff(path).functions[0]
    >>> back.kind, back.ordinate_unit, bool(np.allclose(back.ordinate, h.ordinate))
    ('frf', 'm/N', True)
    """
    for f in data.functions:
        if not (np.isfinite(f.ordinate).all() and np.isfinite(f.abscissa).all()):
            raise ModelError(Problem(f"channel '{printable(f.name, limit=40)}' holds NaN or "
                                     "infinite values, which a Universal File cannot hold",
                                     os.path.basename(os.fspath(path))))
    pyuff = _pyuff()
    sets: list[dict[str, Any]] = [pyuff.prepare_164(units_code=1, units_description="SI",
                                                    temp_mode=2, length=1.0, force=1.0,
                                                    temp=1.0, temp_offset=273.15)]
    if data.geometry:
        nodes = sorted(data.geometry)
        xyz = np.array([data.geometry[n] for n in nodes])
        sets.append(pyuff.prepare_15(node_nums=nodes, def_cs=[0] * len(nodes),
                                     disp_cs=[0] * len(nodes), color=[1] * len(nodes),
                                     x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2]))
    sets.extend(_dataset58(pyuff, f, binary) for f in data.functions)
    for number, mode in enumerate(data.modes, start=1):
        sets.append(_dataset55(pyuff, mode, number))
    if os.path.exists(path):
        os.remove(path)
    uff = pyuff.UFF(os.fspath(path))
    uff.write_sets(sets, mode="add")


def _dataset58(pyuff: ModuleType, f: MeasuredFunction, binary: bool) -> dict[str, Any]:
    per_newton = f.kind in ("frf", "transmissibility") and f.ordinate_unit.endswith("/N")
    numerator = f.ordinate_unit[:-2] if per_newton else f.ordinate_unit
    complex_data = np.iscomplexobj(f.ordinate)
    length, force = _EXPONENTS.get(numerator, (0, 0))
    code = _CODES.get(f.kind, 0)
    return pyuff.prepare_58(
        binary=int(binary), id1=f.name, func_type=code if code in (0, 1, 2, 3, 4, 6, 9) else 0,
        rsp_node=f.response[0], rsp_dir=f.response[1], ref_node=f.reference[0],
        ref_dir=f.reference[1], ord_data_type=6 if complex_data else 4,
        abscissa_spacing=1, abscissa_min=float(f.abscissa[0]), abscissa_inc=f.step,
        abscissa_spec_data_type=_UNIT_CODES.get(f.abscissa_unit, 0),
        abscissa_axis_units_lab=f.abscissa_unit or "NONE",
        ordinate_spec_data_type=_UNIT_CODES.get(numerator, 0), ordinate_len_unit_exp=length,
        ordinate_force_unit_exp=force, ordinate_axis_units_lab=numerator or "NONE",
        orddenom_spec_data_type=13 if per_newton else 0,
        orddenom_force_unit_exp=1 if per_newton else 0,
        orddenom_axis_units_lab="N" if per_newton else "NONE",
        data=np.asarray(f.ordinate, dtype=complex if complex_data else float),
        x=np.asarray(f.abscissa, dtype=float), num_pts=f.samples)


def _dataset55(pyuff: ModuleType, mode: MeasuredMode, number: int) -> dict[str, Any]:
    complex_shape = np.iscomplexobj(mode.shape)
    w = 2 * np.pi * mode.frequency
    kind: dict[str, Any] = dict(
        analysis_type=3, eig=complex(-mode.damping * w, w * math.sqrt(max(
            0.0, 1 - mode.damping ** 2))), modal_a=0j, modal_b=0j) if complex_shape else \
        dict(analysis_type=2, freq=mode.frequency, modal_m=1.0, modal_damp_vis=mode.damping,
             modal_damp_his=0.0)
    return pyuff.prepare_55(
        model_type=1, data_ch=2, spec_data_type=8, data_type=5 if complex_shape else 2,
        n_data_per_node=3, mode_n=number, load_case=1, node_nums=np.asarray(mode.nodes),
        r1=mode.shape[:, 0], r2=mode.shape[:, 1], r3=mode.shape[:, 2], **kind)


def read_histories(path: str | os.PathLike[str]) -> MeasuredData:
    """Time histories of several channels from a CSV, ``.npy`` or ``.npz`` file.

    Parameters
    ----------
    path : str or PathLike
        The layout is the module's (time first, then one column per channel).

    Returns
    -------
    MeasuredData
        One ``"time"`` function per channel, units left empty (the mapping says them).

    Raises
    ------
    ModelError
        For an unreadable file, a row that is not numbers, NaN, too few samples or
        times that are not equally spaced.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "test.csv")
    ...     _ = open(path, "w").write("time,force,a3\\n0,1,0\\n0.001,0,2\\n0.002,0,1\\n")
    ...     data = read_histories(path)
    >>> data.names, data.function("a3").ordinate.tolist()
    (('force', 'a3'), [0.0, 2.0, 1.0])
    """
    checked = _checked_path(path)
    name = os.path.basename(checked)
    suffix = os.path.splitext(name)[1].lower()
    if suffix == ".npz":
        time, columns = _npz(checked, name)
    elif suffix == ".npy":
        array = _npy(checked, name)
        time = array[:, 0]
        columns = {f"ch{k}": array[:, k] for k in range(1, array.shape[1])}
    else:
        time, columns = _csv(checked, name)
    if len(time) < 2 or not columns:
        raise ModelError(Problem("the histories need a time column, at least one channel "
                                 "and two samples", name))
    functions = []
    for channel, values in columns.items():
        values = np.asarray(values, dtype=float).ravel()
        if len(values) != len(time):
            raise ModelError(Problem(f"channel '{printable(channel, limit=40)}' has "
                                     f"{len(values)} samples, the time {len(time)}", name))
        bad = np.flatnonzero(~np.isfinite(values))
        if len(bad):
            raise ModelError(Problem(f"channel '{printable(channel, limit=40)}': sample "
                                     f"{bad[0] + 1} is NaN or infinite", name))
        functions.append(MeasuredFunction(str(channel), "time", np.asarray(time, dtype=float),
                                          values, "s"))
    _check_steps(functions, name)
    return MeasuredData(name, tuple(functions))


def _check_archive(path: str, name: str) -> None:
    """Refuse a hostile archive from its directory, before anything is decompressed: too
    many members, more than :data:`MAX_BYTES` decompressed, or a member compressed beyond
    ``resonant.model.limits.MAX_COMPRESSION_RATIO`` (a zip bomb)."""
    import zipfile

    try:
        with zipfile.ZipFile(path) as archive:
            members = archive.infolist()
    except (OSError, zipfile.BadZipFile) as exc:
        raise ModelError(Problem(f"not a NumPy archive ({_reason(exc)})", name)) from None
    total = sum(m.file_size for m in members)
    if len(members) > MAX_MEMBERS or total > MAX_BYTES or any(
            m.file_size > MAX_COMPRESSION_RATIO * max(m.compress_size, 1) for m in members):
        raise ModelError(Problem(f"the archive's {len(members)} members decompress to "
                                 f"{total} bytes: at most {MAX_MEMBERS} members, {MAX_BYTES} "
                                 f"bytes and a compression ratio of {MAX_COMPRESSION_RATIO}",
                                 name))


def _npz(path: str, name: str) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    _check_archive(path, name)
    try:
        with np.load(path, allow_pickle=False) as archive:
            arrays = {k: np.asarray(archive[k]) for k in archive.files}
    except (OSError, ValueError) as exc:
        raise ModelError(Problem(f"not a NumPy archive ({_reason(exc)})", name)) from None
    if "time" not in arrays:
        raise ModelError(Problem("the archive has no array 'time'", name))
    time = arrays.pop("time")
    if any(a.dtype.kind not in "fiu" for a in (time, *arrays.values())):
        raise ModelError(Problem("every array must hold real numbers", name))
    return time.astype(float).ravel(), arrays


def _npy(path: str, name: str) -> np.ndarray:
    try:
        array = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as exc:
        raise ModelError(Problem(f"not a NumPy array file ({_reason(exc)})", name)) from None
    if array.ndim != 2 or array.shape[1] < 2 or array.dtype.kind not in "fiu":
        raise ModelError(Problem(f"expected a 2-D array of numbers with the time in column 0, "
                                 f"got shape {array.shape}", name))
    return array.astype(float)


def _csv(path: str, name: str) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    with open_regular_file(path, follow_symlinks=True, max_bytes=MAX_BYTES) as handle:
        data = read_bounded(handle, MAX_BYTES).removeprefix(b"\xef\xbb\xbf")
    lines = ((n, raw.decode("utf-8", errors="replace").split("#", 1)[0].strip())
             for n, raw in enumerate(_byte_lines(data), start=1))
    content = ((n, line) for n, line in lines if line)
    first = next(content, None)
    if first is None:
        raise ModelError(Problem("the file is empty", name))
    header = [p.strip() for p in first[1].replace(";", ",").split(",")]
    try:
        values = [float(p) for p in header]
        names = [f"ch{k}" for k in range(1, len(header))]
        pending = [(first[0], values)]
    except ValueError:
        names, pending = header[1:], []
    count = data.count(b"\n") + 1
    if count > MAX_SAMPLES:
        raise ModelError(Problem(f"{count} lines; at most {MAX_SAMPLES} samples are read "
                                 "(resample, or save the histories as .npy)", name))
    require(8.0 * count * (len(names) + 1), f"the histories ({count} samples x "
            f"{len(names) + 1} columns)", "read fewer channels or a shorter record")
    rows = np.empty((count, len(names) + 1))
    row = 0
    for _, values in pending:
        rows[row] = values
        row += 1
    for number, line in content:
        parts = line.replace(";", ",").split(",")
        try:
            if len(parts) != len(names) + 1:
                raise ValueError
            rows[row] = [float(p) for p in parts]
        except ValueError:
            raise ModelError(Problem(f"line {number}: expected {len(names) + 1} numbers (time "
                                     f"and {', '.join(names[:8])}), got "
                                     f"'{printable(line, limit=60)}'", name)) from None
        row += 1
    rows = rows[:row]
    return rows[:, 0], {channel: rows[:, k + 1] for k, channel in enumerate(names)}


def _byte_lines(data: bytes) -> Iterator[bytes]:
    """The lines of ``data`` one at a time (no list of them all: a file may hold millions)."""
    start = 0
    while start < len(data):
        end = data.find(b"\n", start)
        end = len(data) if end < 0 else end
        yield data[start:end]
        start = end + 1
