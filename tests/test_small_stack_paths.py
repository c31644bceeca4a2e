"""The entry-by-entry routes for stacks of small matrices, the amplitude-only route and
the result writer's background thread, each against the route it replaces.

Two routes, one answer, bitwise: the dynamic matrix K - w^2 M + i w C built entry by entry
against numpy broadcasting; ``amplitudes`` against the amplitudes of
``amplitude_and_phase``; a study's amplitudes without phases against those with them.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import resonant
from resonant.analyses.kernel import _dynamic_matrix
from resonant.analyses.sweep import amplitude_and_phase, amplitudes
from resonant.studies.files import ResultWriter, read_columns
from resonant.studies.quantities import responses
from resonant.system.base import sample_parameters

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False)
anything = st.floats(allow_nan=True, allow_infinity=True, width=64)


@st.composite
def pencils(draw: st.DrawFn) -> tuple[np.ndarray, ...]:
    """K, M, C of one to three coordinates (three: the broadcast route), each a stack
    (N, n, n) or one matrix (n, n), and the frequencies w (N,)."""
    n, N = draw(st.integers(1, 3)), draw(st.integers(1, 6))

    def matrix() -> np.ndarray:
        shape = (N, n, n) if draw(st.booleans()) else (n, n)
        return draw(arrays(float, shape, elements=finite))

    w = draw(arrays(float, (N,), elements=st.floats(0, 1e3)))
    return matrix(), matrix(), matrix(), w


@given(pencils(), st.booleans())
@settings(max_examples=200, deadline=None)
def test_dynamic_matrix_is_the_broadcast_formula(pencil, undamped):
    K, M, C, w = pencil
    ww = w[:, None, None]
    expected = K - ww**2 * M
    if not undamped:
        expected = expected + 1j * ww * C
    got = _dynamic_matrix(K, M, C, w, undamped)
    assert got.shape == (len(w), K.shape[-1], K.shape[-1])
    assert np.iscomplexobj(got) is not undamped
    np.testing.assert_array_equal(got, np.broadcast_to(expected, got.shape))


@given(arrays(complex, (1, 7, 2), elements=st.complex_numbers(allow_nan=True,
                                                              allow_infinity=True)),
       arrays(float, (1, 7), elements=st.sampled_from([0.0, 1.0, 3.5])))
@settings(max_examples=200, deadline=None)
def test_amplitudes_are_those_of_amplitude_and_phase(Z, omegas):
    """Static points (omega = 0), NaN and infinite parts included."""
    np.testing.assert_array_equal(amplitudes(omegas, Z), amplitude_and_phase(omegas, Z)[0])


def test_amplitudes_of_several_harmonics_are_those_of_amplitude_and_phase():
    rng = np.random.default_rng(3)
    Z = rng.normal(size=(2, 5, 3)) + 1j * rng.normal(size=(2, 5, 3))
    omegas = np.array([[1.0, 2.0, 2.0, 0.0, 1.0], [2.0, 2.0, 4.0, 1.0, 0.0]])
    np.testing.assert_array_equal(amplitudes(omegas, Z), amplitude_and_phase(omegas, Z)[0])


@given(arrays(float, (50,), elements=st.floats(1.0, 400.0)))
@settings(max_examples=25, deadline=None)
def test_study_amplitudes_without_phase_are_those_with_it(k):
    """The cart and pendulum of docs/reference-exercise.md, k varied (including the
    undamped resonances near k = 202 and 376 N/m, where both give NaN)."""
    model = resonant.load("examples/cart_pendulum.toml")
    system = resonant.linear_system(model)
    values, _, _ = sample_parameters(model, {"k": k}, len(k))
    with_phase = responses(system, values, len(k), ["x1", "x2", "phi"])
    without = responses(system, values, len(k), ["x1", "x2", "phi"], phase=False)
    np.testing.assert_array_equal(without[0], with_phase[0])
    np.testing.assert_array_equal(without[2], with_phase[2])
    assert np.isnan(without[1]).all()


def test_writer_keeps_chunk_order_and_raises_a_failed_write(tmp_path):
    """Chunks are written on a thread: in order, and a write that fails raises in the
    caller (at the next write or at close) while the chunks before it stay in the
    file."""
    path = tmp_path / "r.parquet"
    writer = ResultWriter(path, {"study": 1})
    for k in range(5):
        writer.write({"sample": np.arange(3 * k, 3 * k + 3), "x": np.full(3, float(k))})
    writer.write({"sample": np.arange(15, 18), "x": np.array(["a", "b", "c"])})
    with pytest.raises(Exception, match="(?i)float|double|convert|parse|invalid"):
        writer.write({"sample": np.arange(18, 21), "x": np.zeros(3)})
        writer.close()
    writer.close()
    columns = read_columns(path, ["sample", "x"])
    assert columns["sample"].tolist() == list(range(15))
    assert columns["x"].tolist() == [float(k) for k in range(5) for _ in range(3)]
