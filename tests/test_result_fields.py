"""Results saved by their fields (resonant.analyses.result_fields.FieldsJSON): the JSON of
the bundled examples' results comes back as the same result and the same text, any values
of the fields survive JSON (hypothesis), and the mechanism's ways of saving a field (key
order, a history on request, rows by name, names read back as keys, nested records) refuse
what does not fit with an AnalysisError naming the key."""

from __future__ import annotations

import io
import json
from contextlib import redirect_stdout
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from resonant.analyses.correlate import Correlation, correlate_shapes
from resonant.analyses.fatigue import ResponseFatigue
from resonant.analyses.frf_mimo import MIMOFRF, estimate_frf_matrix
from resonant.analyses.periodic import PeriodicSolution
from resonant.analyses.result_fields import (
    COMPLEX_NUMBER,
    HARMONIC_LISTS,
    PLAIN_NUMBER,
    PLAIN_NUMBERS,
    FieldsJSON,
    saved,
)
from resonant.analyses.shock import ShockSpectrum
from resonant.analyses.transient import ShockPeaks, TransientResponse
from resonant.arrays import ComplexArray
from resonant.cli import main
from resonant.errors import AnalysisError
from resonant.model.load_spec import ShockSpec

EXAMPLES = Path(__file__).parents[1] / "examples"
hypothesis = pytest.importorskip("hypothesis")
st = hypothesis.strategies
hnp = pytest.importorskip("hypothesis.extra.numpy")


def _cli_json(*args: str) -> dict:
    out = io.StringIO()
    with redirect_stdout(out):
        assert main([*args, "--json"]) == 0
    return json.loads(out.getvalue())


@pytest.mark.parametrize(("kind", "args", "key"), [
    (ResponseFatigue, ("fatigue", str(EXAMPLES / "bracket_fatigue.toml")), None),
    (ShockPeaks, ("srs", str(EXAMPLES / "shock_half_sine.toml"), "--largest"), "response"),
    (ShockSpectrum, ("srs", str(EXAMPLES / "shock_half_sine.toml")), None),
], ids=["fatigue", "shock-peaks", "srs"])
def test_the_commands_json_reads_back_to_the_same_text(kind, args, key):
    """What ``resonant fatigue`` / ``srs --json`` printed is read back (from_dict) and
    written again (to_dict) to the same JSON text, key order included."""
    data = _cli_json(*args)
    saved_data = data[key] if key else {k: v for k, v in data.items() if k != "response"}
    back = kind.from_dict(saved_data)
    assert json.dumps(back.to_dict()) == json.dumps(saved_data)


#: finite doubles (JSON keeps them bit for bit), and names
FINITE = st.floats(allow_nan=False, allow_infinity=False, width=64)
NAMES = st.lists(st.text("abxyz'", min_size=1, max_size=4), min_size=1, max_size=4,
                 unique=True)


@hypothesis.settings(max_examples=25, deadline=None)
@hypothesis.given(NAMES, st.integers(1, 4), st.data())
def test_any_periodic_solution_survives_json(names, harmonics, data):
    """Property: from_dict(to_dict()) gives the fields back, bit for bit, whatever they hold
    (rows by coordinate, the coordinates read back as the keys, complex pairs)."""
    n = len(names)
    coefficients = data.draw(hnp.arrays(np.float64, (n, 2 * harmonics + 1), elements=FINITE))
    multipliers = data.draw(hnp.arrays(np.complex128, (2 * n,), elements=st.complex_numbers(
        allow_nan=False, allow_infinity=False, max_magnitude=1e300)))
    numbers = st.dictionaries(st.sampled_from(names), FINITE)
    solution = PeriodicSolution(
        data.draw(st.text(max_size=5)), tuple(names), harmonics, coefficients,
        data.draw(st.floats(1e-3, 1e3)), data.draw(numbers), data.draw(numbers), data.draw(numbers),
        data.draw(numbers), multipliers, data.draw(st.booleans()), data.draw(FINITE),
        data.draw(FINITE), tuple(data.draw(st.lists(st.text(max_size=5), max_size=2))))
    text = json.dumps(solution.to_dict())
    back = PeriodicSolution.from_dict(json.loads(text))
    assert json.dumps(back.to_dict()) == text
    assert back.coordinates == solution.coordinates
    np.testing.assert_array_equal(back.coefficients, solution.coefficients)
    np.testing.assert_array_equal(back.multipliers, solution.multipliers)
    assert list(solution.to_dict()) == list(PeriodicSolution._json_order)


@hypothesis.settings(max_examples=25, deadline=None)
@hypothesis.given(NAMES, st.integers(1, 6), st.data())
def test_any_transient_and_its_peaks_survive_json(names, samples, data):
    """Property: a transient response with its histories and the peaks of a pulse, any
    numbers, come back as they were; without the history the response is refused."""
    time = data.draw(hnp.arrays(np.float64, (samples,), elements=FINITE))
    history = {n: data.draw(hnp.arrays(np.float64, (samples,), elements=FINITE))
               for n in names}
    largest = {n: data.draw(FINITE) for n in names}
    response = TransientResponse(time, data.draw(hnp.arrays(np.float64, (samples,),
                                                            elements=FINITE)),
                                 history, largest, tuple(names))
    text = json.dumps(response.to_dict(history=True))
    back = TransientResponse.from_dict(json.loads(text))
    assert json.dumps(back.to_dict(history=True)) == text and back.names == tuple(names)
    with pytest.raises(AnalysisError, match="no time history"):
        TransientResponse.from_dict(response.to_dict())
    spec = ShockSpec("y", data.draw(st.integers(0, 2)), "half-sine", data.draw(FINITE),
                     data.draw(FINITE), data.draw(FINITE), data.draw(FINITE), data.draw(FINITE))
    peaks = ShockPeaks(tuple(names), largest, largest, largest, largest,
                       {n: "m" for n in names}, spec)
    assert ShockPeaks.from_dict(json.loads(json.dumps(peaks.to_dict()))) == peaks


@dataclass(frozen=True)
class _Rows(FieldsJSON):
    """A small result with every new way of saving a field."""

    _json_order = ("count", "rows", "history")

    names: tuple[str, ...] = saved(keys_of="rows")
    rows: np.ndarray = saved(rows_by="names", codec=HARMONIC_LISTS)
    t: np.ndarray = saved(history=True)

    def _derived_json(self) -> dict:
        return {"count": len(self.names)}


def test_the_ways_of_saving_a_field_refuse_what_does_not_fit():
    rows = _Rows(("a", "b"), np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]), np.array([0.0]))
    assert rows.to_dict() == {"count": 2, "rows": {"a": [[1.0], [2.0, 3.0]],
                                                   "b": [[4.0], [5.0, 6.0]]}}
    data = rows.to_dict(history=True)
    assert list(data) == ["count", "rows", "history"] and data["history"] == {"t": [0.0]}
    back = _Rows.from_dict(data)
    assert back.names == ("a", "b") and back.rows.tolist() == rows.rows.tolist()
    with pytest.raises(AnalysisError, match="no time history"):
        _Rows.from_dict(rows.to_dict())
    data["rows"]["b"] = [[4.0], [5.0]]
    with pytest.raises(AnalysisError, match="'rows' holds rows of different lengths"):
        _Rows.from_dict(data)
    data["rows"] = [1.0]
    with pytest.raises(AnalysisError, match="'rows'"):
        _Rows.from_dict(data)

    @dataclass(frozen=True)
    class Unlisted(FieldsJSON):
        _json_order = ("a",)
        a: int
        b: int

    with pytest.raises(TypeError, match=r"Unlisted._json_order does not list \['b'\]"):
        Unlisted(1, 2).to_dict()


def test_a_pulse_is_saved_as_its_sections_keys_and_checked():
    """A plain record (the [shock] pulse) is saved by its compared fields (not where it was
    read from) and a wrong one is refused naming the key."""
    spec = ShockSpec("y", 2, "half-sine", 1.0, 0.01, 1e-5, 0.03, source="a.toml")
    peaks = ShockPeaks(("a",), {"a": 1.0}, {"a": 1.0}, {"a": -1.0}, {"a": 0.0}, {"a": ""},
                       spec)
    data = peaks.to_dict()
    assert list(data["shock"]) == ["signal", "derivative", "pulse", "amplitude", "duration",
                                   "step", "total", "Q"]
    data["shock"] = dict(data["shock"], derivative="two")
    with pytest.raises(AnalysisError, match="shock.derivative"):
        ShockPeaks.from_dict(data)


def test_measured_results_survive_json():
    """The H1 matrix of two inputs and the correlation of three test modes with two model
    modes (an unpaired one: NaN frequency error) come back bit for bit."""
    x = np.random.default_rng(1).standard_normal((2, 2048))
    frf = estimate_frf_matrix({"u": x[0], "v": x[1]}, {"y": x[0] + x[1], "z": x[0] - x[1]},
                              0.01, segment=256)
    text = json.dumps(frf.to_dict())
    back = MIMOFRF.from_dict(json.loads(text))
    assert json.dumps(back.to_dict()) == text
    np.testing.assert_array_equal(back.H, frf.H)
    c = correlate_shapes(np.array([2.2, 6.3, 9.0]), np.eye(3), np.array([2.24, 6.28]),
                         np.array([[1.0, 0.1], [0.0, 1.0], [0.2, 0.3]]))
    back_c = Correlation.from_dict(json.loads(json.dumps(c.to_dict())))
    assert back_c.pairs == c.pairs and np.isnan(back_c.frequency_error[2])
    np.testing.assert_array_equal(back_c.mac, c.mac)
    data = c.to_dict()
    data["mac"] = data["mac"][:2]
    with pytest.raises(AnalysisError, match="'mac' has shape"):
        Correlation.from_dict(data)


def test_numbers_saved_by_name_are_records_checked_by_key():
    """A random response's numbers are one record per response (derived 3 sigma among
    them, in the declared order); a record without a number is refused naming it, one
    without its unit reads as no unit."""
    from resonant.analyses.random_response import RandomResponse

    f = np.array([10.0, 20.0])
    r = RandomResponse("t", ("x",), ("y",), f, {"x": np.ones(2)}, {"y": np.ones(2)},
                       {"x": 2.0}, {"x": 1.0}, {"x": 1.5}, {"x": 1e-9}, {}, (10.0, 20.0))
    data = json.loads(json.dumps(r.to_dict()))
    assert data["responses"] == {"x": {"unit": "", "rms": 2.0, "three_sigma": 6.0,
                                       "zero_crossing_rate_hz": 1.0, "peak_rate_hz": 1.5,
                                       "relative_error": 1e-9, "miles_rms": None}}
    assert data["inputs"] == {"y": {"unit": "", "derivative": 0}}
    del data["responses"]["x"]["unit"]
    assert RandomResponse.from_dict(data).to_dict() == r.to_dict()
    del data["responses"]["x"]["rms"]
    with pytest.raises(AnalysisError, match="responses.x"):
        RandomResponse.from_dict(data)


@dataclass(frozen=True)
class _Poles(FieldsJSON):
    """Records per index (two arrays and a tuple), a field written only with another."""

    _group_order = {"modes": ("hz", "pole", "label")}
    poles: np.ndarray = saved(records="modes", key="pole", codec=COMPLEX_NUMBER)
    labels: tuple[str, ...] = saved(records="modes", key="label")
    hz: np.ndarray = saved(records="modes", codec=PLAIN_NUMBER)
    shapes: ComplexArray = saved(axes=(2, "poles"))
    inputs: tuple[str, ...] = saved((), only_with="inputs")
    gains: np.ndarray = saved(default_factory=lambda: np.zeros(0), axes=("inputs",),
                              only_with="inputs")


def test_records_per_index_and_fields_written_only_with_another():
    """Fields of one ``records`` group are one object per index (in ``_group_order``),
    a ``ComplexArray`` is saved complex even when real, and a field ``only_with`` another
    is left out while that one is empty, and needed once it is not."""
    r = _Poles(np.array([-1 + 2j, -0.5 + 3j]), ("a", "b"), np.array([0.3, 0.5]),
               np.ones((2, 2)))
    data = json.loads(json.dumps(r.to_dict()))
    assert data == {"modes": [{"hz": 0.3, "pole": {"real": -1.0, "imag": 2.0}, "label": "a"},
                              {"hz": 0.5, "pole": {"real": -0.5, "imag": 3.0}, "label": "b"}],
                    "shapes": {"real": [[1.0, 1.0], [1.0, 1.0]],
                               "imag": [[0.0, 0.0], [0.0, 0.0]]}}
    back = _Poles.from_dict(data)
    assert back.labels == ("a", "b") and back.poles.dtype == complex
    np.testing.assert_array_equal(back.poles, r.poles)
    assert back.shapes.dtype == complex and back.to_dict() == data
    with_inputs = _Poles(r.poles, r.labels, r.hz, r.shapes, ("u",), np.array([2.0]))
    data = with_inputs.to_dict()
    assert list(data) == ["modes", "shapes", "inputs", "gains"]
    assert _Poles.from_dict(data).gains.tolist() == [2.0]
    with pytest.raises(AnalysisError, match="no key 'gains'"):
        _Poles.from_dict({k: v for k, v in data.items() if k != "gains"})
    data["modes"][1] = {"hz": 0.5, "label": "b"}
    with pytest.raises(AnalysisError, match=r"no key 'pole' at 'modes\[1\]'"):
        _Poles.from_dict(data)
    data["modes"] = data["modes"][:1]
    with pytest.raises(AnalysisError, match=r"'shapes.real' has shape \(2, 2\), not \(2, 1\)"):
        _Poles.from_dict(data)
    with pytest.raises(ValueError, match="_Poles.labels has 1 values, but its records"):
        _Poles(r.poles, ("a",), r.hz, r.shapes).to_dict()


@dataclass(frozen=True)
class _Branch(FieldsJSON):
    """Records of a mapping and of named rows (two fields merged under one key), fields
    inside one object beside a derived key there, and "..." in the key order."""

    _json_order = ("...", "points", "rest")
    _group_order = {"rest": ("names", "count", "extra")}
    names: tuple[str, ...] = saved(inside="rest")
    values: np.ndarray = saved(records="points", key="value", codec=PLAIN_NUMBER)
    levels: dict[str, np.ndarray] = saved(records="points", codec=PLAIN_NUMBERS)
    rows: np.ndarray = saved(records="points", key="rows", rows_by="names",
                             codec=HARMONIC_LISTS)
    extra: tuple[str, ...] = saved((), inside="rest")
    more: np.ndarray | None = saved(None, records="points", key="rows", rows_by="extra",
                                    codec=HARMONIC_LISTS, omit_none=True)

    def _derived_json(self) -> dict:
        return {"title": "t", "rest": {"count": len(self.values)}}


def test_records_of_mappings_and_named_rows_and_fields_inside_an_object():
    b = _Branch(("a",), np.array([1.0, 2.0]), {"x": np.array([3.0, 4.0])},
                np.array([[[1.0, 2.0, 3.0]], [[4.0, 5.0, 6.0]]]), ("e",),
                np.array([[[7.0, 8.0, 9.0]], [[0.5, 0.25, 0.0]]]))
    data = json.loads(json.dumps(b.to_dict()))
    assert data == {"title": "t", "points": [
        {"value": 1.0, "levels": {"x": 3.0}, "rows": {"a": [[1.0], [2.0, 3.0]],
                                                      "e": [[7.0], [8.0, 9.0]]}},
        {"value": 2.0, "levels": {"x": 4.0}, "rows": {"a": [[4.0], [5.0, 6.0]],
                                                      "e": [[0.5], [0.25, 0.0]]}}],
        "rest": {"names": ["a"], "count": 2, "extra": ["e"]}}
    back = _Branch.from_dict(data)
    np.testing.assert_array_equal(back.rows, b.rows)
    np.testing.assert_array_equal(back.more, b.more)
    np.testing.assert_array_equal(back.levels["x"], b.levels["x"])
    assert back.to_dict() == b.to_dict()
    plain = _Branch(("a",), b.values, b.levels, b.rows)
    assert _Branch.from_dict(plain.to_dict()).more is None
    data["points"][1]["rows"]["a"] = [[4.0], [5.0]]
    with pytest.raises(AnalysisError, match=r"'points\[1\].rows.a' has shape \(2,\), not \(3,"):
        _Branch.from_dict(data)
    del data["points"][0]["levels"]["x"]
    data["points"][0]["levels"]["y"] = 1.0
    with pytest.raises(AnalysisError, match=r"no key 'y' at 'points\[1\].levels'"):
        _Branch.from_dict(data)
    with pytest.raises(AnalysisError, match="no key 'names' at 'rest'"):
        _Branch.from_dict({**data, "rest": {"count": 2}})
