"""Measured data in and out: Universal Files through pyuff, CSV/NumPy histories, the
``[measurement]`` section (docs/testing.md).

References: the Universal File Format's dataset descriptions (SDRC/Siemens, as pyuff
documents them): dataset 164 gives the factors file-unit / SI unit, so SI = value / factor;
a 58 record's ordinate carries its length and force exponents.  Every round trip is exact
to the written precision (ASCII 58 writes 12 significant digits: 1e-11 relative; binary 58b
is exact).
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from resonant.errors import ModelError
from resonant.model import loads
from resonant.model.measured import (
    MeasuredData,
    MeasuredFunction,
    MeasuredMode,
    read_histories,
    read_uff,
    write_uff,
)
from resonant.model.measurement_spec import match_channels

pyuff = pytest.importorskip("pyuff")

CHAIN = open("examples/chain3_damped.toml").read()


def _functions() -> tuple[MeasuredFunction, ...]:
    t = np.arange(256) / 128.0
    f = np.arange(1, 65) * 0.25
    return (MeasuredFunction("hammer", "time", t, np.exp(-t) * np.sin(9 * t), "s", "N",
                             (3, 3), (3, 3)),
            MeasuredFunction("a3", "time", t, np.cos(5 * t), "s", "m/s^2", (3, 3), (3, 3)),
            MeasuredFunction("H33", "frf", f, 1 / (100 - f ** 2 + 1j * f), "Hz", "m/N",
                             (3, 3), (3, 3)))


@pytest.mark.parametrize("binary", [False, True])
def test_functions_modes_geometry_round_trip(tmp_path, binary):
    mode = MeasuredMode(2.24, 0.014, np.array([1, 2, 3]),
                        np.array([[0, 0, 0.33], [0, 0, 0.59], [0, 0, 0.74]]))
    data = MeasuredData("lab.uff", _functions(), (mode,),
                        {1: (0.0, 0.0, 0.0), 2: (0.5, 0.0, 0.0), 3: (1.0, 0.0, 0.0)})
    path = tmp_path / "lab.uff"
    write_uff(path, data, binary=binary)
    back = read_uff(path)
    assert back.names == ("hammer", "a3", "H33")
    for a, b in zip(data.functions, back.functions):
        assert (a.kind, a.ordinate_unit, a.abscissa_unit, a.response, a.reference) == \
            (b.kind, b.ordinate_unit, b.abscissa_unit, b.response, b.reference)
        # ASCII: 12 digits
        np.testing.assert_allclose(b.ordinate, a.ordinate, rtol=1e-11, atol=1e-13)
        np.testing.assert_allclose(b.abscissa, a.abscissa, rtol=1e-10, atol=1e-12)
    assert back.geometry[3] == pytest.approx((1.0, 0.0, 0.0))
    assert back.modes[0].frequency == pytest.approx(2.24)
    np.testing.assert_allclose(back.modes[0].shape, mode.shape, rtol=1e-6)


def test_units_from_dataset_164(tmp_path):
    """A file in millimetres: an acceleration of 1000 mm/s^2 is 1 m/s^2; an FRF of
    1000 mm/N is 1 m/N; node coordinates in mm become metres."""
    t = np.arange(8) * 0.01
    sets = [pyuff.prepare_164(units_code=5, units_description="mm/mN", temp_mode=2,
                              length=1000.0, force=1000.0, temp=1.0, temp_offset=273.15),
            pyuff.prepare_2411(node_nums=[7], def_cs=[0], disp_cs=[0], color=[1],
                               x=[500.0], y=[0.0], z=[0.0]),
            pyuff.prepare_58(func_type=1, rsp_node=7, rsp_dir=3, ref_node=7, ref_dir=3,
                             ord_data_type=4, abscissa_spacing=1, abscissa_min=0.0,
                             abscissa_inc=0.01, abscissa_spec_data_type=17,
                             ordinate_spec_data_type=12, ordinate_len_unit_exp=1,
                             orddenom_spec_data_type=0, data=np.full(8, 1000.0), x=t,
                             num_pts=8, id1="acc"),
            pyuff.prepare_58(func_type=4, rsp_node=7, rsp_dir=3, ref_node=7, ref_dir=3,
                             ord_data_type=6, abscissa_spacing=1, abscissa_min=1.0,
                             abscissa_inc=1.0, abscissa_spec_data_type=18,
                             ordinate_spec_data_type=8, ordinate_len_unit_exp=1,
                             orddenom_spec_data_type=13, orddenom_force_unit_exp=1,
                             data=np.full(4, 1.0 + 0j), x=np.arange(1.0, 5.0), num_pts=4)]
    path = tmp_path / "mm.uff"
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    back = read_uff(path)
    acc, frf = back.functions
    np.testing.assert_allclose(acc.ordinate, 1.0)
    assert acc.ordinate_unit == "m/s^2" and frf.ordinate_unit == "m/N"
    # 1 mm/mN = 1e-3 m / 1e-3 N = 1 m/N
    np.testing.assert_allclose(frf.ordinate, 1.0)
    assert frf.name == "7+Z"
    assert back.geometry[7] == pytest.approx((0.5, 0.0, 0.0))


def _write(tmp_path, functions, name="lab.uff"):
    path = tmp_path / name
    write_uff(path, MeasuredData(name, tuple(functions)))
    return path


def test_truncated_record_names_the_record(tmp_path):
    path = _write(tmp_path, _functions())
    text = path.read_text()
    path.write_text(text[: int(len(text) * 0.8)])
    with pytest.raises(ModelError, match=r"lab\.uff: record 4 is truncated"):
        read_uff(path)


def test_unknown_dataset_named(tmp_path):
    path = tmp_path / "odd.uff"
    path.write_text("    -1\n  2414\nresults\nNONE\n    -1\n")
    with pytest.raises(ModelError, match=r"odd\.uff: record 1: dataset 2414 is not read"):
        read_uff(path)


def test_not_a_universal_file(tmp_path):
    path = tmp_path / "junk.uff"
    path.write_bytes(b"\x00\x01garbage\n")
    with pytest.raises(ModelError, match="junk.uff"):
        read_uff(path)


def test_nan_sample_named(tmp_path):
    """pyuff writes a NaN as 0; a file with 'nan' in a record is refused naming the value."""
    t = np.arange(8) * 0.1
    path = _write(tmp_path, [MeasuredFunction("a1", "time", t, np.ones(8), "s", "m/s^2")])
    text = path.read_text()
    head, data = text.rsplit("NONE", 1)       # the values follow the last label
    path.write_text(head + "NONE" + data.replace("   1.00000000000e+00", " " * 17 + "nan", 1))
    with pytest.raises(ModelError, match=r"record 2 \(dataset 58\): value \d is NaN"):
        read_uff(path)
    y = np.ones(8)
    y[3] = np.nan
    with pytest.raises(ModelError, match="channel 'a1' holds NaN"):
        _write(tmp_path, [MeasuredFunction("a1", "time", t, y, "s", "m/s^2")])


def test_different_sampling_rates_refused(tmp_path):
    a = MeasuredFunction("a1", "time", np.arange(16) * 0.1, np.ones(16), "s", "m/s^2")
    b = MeasuredFunction("a2", "time", np.arange(16) * 0.05, np.ones(16), "s", "m/s^2")
    path = _write(tmp_path, [a, b])
    with pytest.raises(ModelError, match="share one sampling rate .nothing is resampled"):
        read_uff(path)


def test_csv_npy_npz_histories(tmp_path):
    t = np.arange(5) * 0.002
    (tmp_path / "h.csv").write_text("time,hammer,a3\n" + "".join(
        f"{x},{x * 2},{x * 3}\n" for x in t))
    np.save(tmp_path / "h.npy", np.column_stack([t, 2 * t, 3 * t]))
    np.savez(tmp_path / "h.npz", time=t, hammer=2 * t, a3=3 * t)
    for name, names in (("h.csv", ("hammer", "a3")), ("h.npy", ("ch1", "ch2")),
                        ("h.npz", ("hammer", "a3"))):
        data = read_histories(tmp_path / name)
        assert data.names == names
        np.testing.assert_allclose(data.functions[1].ordinate, 3 * t)
        assert data.functions[0].step == pytest.approx(0.002)


@pytest.mark.parametrize("text, match", [
    ("time,a\n0,1\n0.1,nan\n0.2,1\n", "channel 'a': sample 2 is NaN"),
    ("time,a\n0,1\n0.1,x\n", "line 3: expected 2 numbers"),
    ("time,a\n0,1\n0.1,2\n0.3,1\n", "not equally spaced"),
])
def test_bad_csv(tmp_path, text, match):
    (tmp_path / "bad.csv").write_text(text)
    with pytest.raises(ModelError, match=match):
        read_histories(tmp_path / "bad.csv")


def test_measurement_section():
    model = loads(CHAIN + '[measurement]\nexcitation = "hammer"\ninput = "F"\n'
                  '[measurement.channels]\na1 = "x1\'\'"\na3 = "x3"\n')
    spec = model.measurement_section
    assert spec.channels["a1"].derivative == 2 and spec.channels["a3"].derivative == 0
    with pytest.raises(ModelError, match=r"\[measurement.channels\] a3: lab.uff has no "):
        match_channels(spec, ["hammer", "a1"], model.source, "lab.uff")


@pytest.mark.parametrize("section, match", [
    ('[measurement]\ninput = "G"\n[measurement.channels]\na = "x1"\n',
     r"\[measurement\] input: 'G' is neither"),
    ('[measurement]\ninput = "F"\n[measurement.channels]\na = "x9"\n',
     r"\[measurement.channels\] a: 'x9' is not a coordinate"),
    ('[measurement]\ninputs = "F"\n[measurement.channels]\na = "x1"\n',
     r"\[measurement\] inputs: unknown key 'inputs'; did you mean 'input'"),
])
def test_measurement_section_problems(section, match):
    with pytest.raises(ModelError, match=match):
        loads(CHAIN + section)


def test_pyuff_imported_lazily():
    code = ("import sys, resonant.model.measured; "
            "print('pyuff' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "False"


SAMPLES = __import__("pathlib").Path(__file__).parent / "data" / "pyuff"


def test_pyuff_sample_files_read_as_pyuff_reads_them():
    """Files from real exporters (pyuff's sample data, tests/data/pyuff/README.md): the
    values are pyuff's own (these files are in SI or carry no unit record), the headers'
    descriptive datasets passed over and named."""
    raw = pyuff.UFF(str(SAMPLES / "binary8byte.uff")).read_sets(0)
    f = read_uff(SAMPLES / "binary8byte.uff").functions[0]
    assert (f.kind, f.samples, f.ordinate_unit) == ("time", 250, "m/s^2")
    np.testing.assert_array_equal(f.ordinate, raw["data"])
    assert f.step == pytest.approx(0.01)
    partial = read_uff(SAMPLES / "time-history-not-all-columns-filled.uff").functions[0]
    assert partial.samples == 13
    modes = read_uff(SAMPLES / "uff55_translation.uff").modes
    assert [m.frequency for m in modes] == [10.0, 12.0, 13.0]
    assert modes[0].shape.shape == (4, 3)
    testlab = read_uff(SAMPLES / "TestLab 161 164 18 15 82.uff")
    assert len(testlab.geometry) == 36 and not testlab.functions
    assert any("dataset 82 (trace lines) passed over" in n for n in testlab.notes)


def test_hostile_npz_refused_from_its_directory(tmp_path):
    """Too many members (or too many bytes, or a zip bomb's ratio): refused before numpy
    decompresses anything."""
    import zipfile

    path = tmp_path / "many.npz"
    with zipfile.ZipFile(path, "w") as archive:
        for k in range(4100):
            archive.writestr(f"c{k}.npy", b"")
    with pytest.raises(ModelError, match="many.npz: the archive's 4100 members"):
        read_histories(path)
