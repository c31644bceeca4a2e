"""Vectors and density tables of ``[random]`` from files (model/random_spec.py,
model/csv_tables.py): ``base = "r.npy"``, ``load = "f.csv"``, ``values = "psd.csv"``.

Reference: the same model with the vectors and the table written inline gives the same
random response, to the last bit (the same numbers reach the same computation); every
problem names the model file, the section, the key, the vector's file and, in a CSV
file, the line.
"""

from __future__ import annotations

import numpy as np
import pytest

from conftest import run_cli
from resonant.analyses.random_response import random_response
from resonant.errors import ModelError
from resonant.model import load, loads
from resonant.system import linear_system

CHAIN = """
[matrices]
M = [[2.0, 0, 0], [0, 1.0, 0], [0, 0, 1.5]]
K = [[3e4, -1e4, 0], [-1e4, 2e4, -1e4], [0, -1e4, 1e4]]
C = [[3.0, -1.0, 0], [-1.0, 2.0, -1.0], [0, -1.0, 1.0]]

[random]
band = [1, 200]
tolerance = 1e-6

[random.psd.ground]
unit = "(m/s^2)^2/Hz"
"""
TABLE = [[1.0, 0.01], [20.0, 0.04], [200.0, 0.002]]


def inline(base: str, values: str) -> str:
    return CHAIN + f"base = {base}\nvalues = {values}\n"


@pytest.fixture(scope="module")
def folder(tmp_path_factory):  # type: ignore[no-untyped-def]
    path = tmp_path_factory.mktemp("random_files")
    np.save(path / "r.npy", np.array([1.0, 1.0, 0.5]))
    (path / "r.csv").write_text("influence\n1\n1\n0.5  # the top storey: half\n")
    (path / "psd.csv").write_text("# GEVS-like\nf [Hz], G\n" +
                                  "".join(f"{f!r}, {g!r}\n" for f, g in TABLE))
    return path


@pytest.fixture(scope="module")
def reference():  # type: ignore[no-untyped-def]
    model = loads(inline("[1, 1, 0.5]", str(TABLE)))
    return random_response(linear_system(model))


@pytest.mark.parametrize("base, values", [('"r.npy"', str(TABLE)), ('"r.csv"', '"psd.csv"')])
def test_files_equal_the_inline_section(folder, reference, base: str,  # type: ignore
                                        values: str) -> None:
    (folder / "m.toml").write_text(inline(base, values))
    result = random_response(linear_system(load(folder / "m.toml")))
    for name in reference.names:
        assert result.rms[name] == reference.rms[name]
    assert np.array_equal(result.frequency, reference.frequency)


def test_load_vector_from_a_file(folder) -> None:  # type: ignore[no-untyped-def]
    text = CHAIN.replace("[random.psd.ground]\nunit = \"(m/s^2)^2/Hz\"\n",
                         "[random.psd.F]\nvalues = 1.0\n")
    (folder / "f.toml").write_text(text + 'load = "r.csv"\n')
    by_file = random_response(linear_system(load(folder / "f.toml")))
    by_list = random_response(linear_system(loads(text + "load = [1, 1, 0.5]\n")))
    assert by_file.rms == by_list.rms


@pytest.mark.parametrize("files, base, values, message", [
    ({"bad.csv": "1\n1\nx\n"}, '"bad.csv"', "0.01", "'bad.csv': line 3: expected one number"),
    ({"two.csv": "1\n1\n"}, '"two.csv"', "0.01", "holds 2 entries; the model has 3"),
    ({}, '"../r.npy"', "0.01", "outside the model's folder"),
    ({}, '"nothere.npy"', "0.01", "nothere.npy"),
    ({"t.csv": "1,2\n3\n"}, "[1, 1, 1]", '"t.csv"', "'t.csv': line 2: expected 2 numbers"),
    ({"d.csv": "10,1\n5,1\n"}, "[1, 1, 1]", '"d.csv"', "frequencies of the table must increase"),
    ({"n.csv": "1\nnan\n1\n"}, '"n.csv"', "0.01", "line 2: expected one number"),
])
def test_file_problems_name_the_file_and_line(tmp_path, files: dict, base: str,  # type: ignore
                                              values: str, message: str) -> None:
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    (tmp_path / "m.toml").write_text(inline(base, values))
    with pytest.raises(ModelError) as caught:
        load(tmp_path / "m.toml")
    text = str(caught.value)
    assert message in text and "[random.psd.ground]" in text, text
    assert str(tmp_path) not in text.replace(str(tmp_path / "m.toml"), "")


def test_check_is_exit_2_and_a_text_model_reads_no_file(tmp_path) -> None:  # type: ignore
    (tmp_path / "m.toml").write_text(inline('"r.csv"', "0.01"))
    status, _, err = run_cli(["check", tmp_path / "m.toml"])
    assert status == 2 and "base" in err and "r.csv" in err
    with pytest.raises(ModelError, match="no folder to read"):
        loads(inline('"r.npy"', "0.01"))
