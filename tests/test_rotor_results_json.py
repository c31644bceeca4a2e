"""The rotor results back from their JSON: ``from_dict(to_dict())`` gives the same result
(every field, bit for bit; NaN stays NaN), for results built at random (hypothesis) and for
the bundled rotors' results; a hand-edited file of the wrong shape is refused with its key.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from resonant import load
from resonant.analyses.campbell import Campbell, CriticalSpeed, StabilityThreshold
from resonant.analyses.rotor_map import CriticalSpeedMap
from resonant.analyses.unbalance import UnbalanceResponse
from resonant.errors import AnalysisError
from resonant.model.campbell_spec import Unbalance

hypothesis = pytest.importorskip("hypothesis")
st = hypothesis.strategies
hnp = pytest.importorskip("hypothesis.extra.numpy")

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "rotors"
NUMBERS = st.floats(-1e9, 1e9).map(lambda x: round(x, 9)) | st.just(float("nan"))
FINITE = st.floats(-1e6, 1e6, allow_nan=False).map(lambda x: round(x, 9))  # no 1e-300
TEXT = st.text(st.characters(codec="utf-8", exclude_categories=("Cs",)), max_size=8)
WHIRL = st.sampled_from(("forward", "backward", "none"))


def _json(result: object) -> dict:
    return json.loads(json.dumps(result.to_dict(), allow_nan=False))  # type: ignore[attr-defined]


def _same(a: object, b: object) -> None:
    """Every dataclass field equal (arrays with NaN where NaN, and of one dtype kind)."""
    for name in a.__dataclass_fields__:  # type: ignore[attr-defined]
        x, y = getattr(a, name), getattr(b, name)
        if isinstance(x, np.ndarray):
            assert x.shape == y.shape and np.iscomplexobj(x) == np.iscomplexobj(y), name
            assert np.array_equal(x, y, equal_nan=True), name
        else:
            assert x == y, name


def _complex(shape: tuple[int, ...]) -> st.SearchStrategy:
    return st.tuples(
        hnp.arrays(np.float64, shape, elements=NUMBERS),
        hnp.arrays(np.float64, shape, elements=FINITE),
    ).map(lambda p: p[0] + 1j * p[1])


@st.composite
def unbalance_responses(draw: st.DrawFn) -> UnbalanceResponse:
    n, s, b = draw(st.integers(0, 4)), draw(st.integers(1, 3)), draw(st.integers(0, 2))
    stations = tuple(draw(st.lists(TEXT, min_size=s, max_size=s, unique=True)))
    unbalances = tuple(
        Unbalance(draw(st.sampled_from(stations)), draw(FINITE), draw(FINITE))
        for _ in range(draw(st.integers(0, 2)))
    )
    return UnbalanceResponse(
        draw(TEXT),
        draw(TEXT),
        stations,
        draw(hnp.arrays(np.float64, (n,), elements=FINITE)),
        draw(_complex((n, s))),
        draw(_complex((n, s))),
        unbalances,
        tuple(draw(st.lists(TEXT, max_size=2))),
        tuple(f"b{i}" for i in range(b)),
        draw(_complex((n, b, 2))),
    )


@st.composite
def campbells(draw: st.DrawFn) -> Campbell:
    p, k = draw(st.integers(1, 4)), draw(st.integers(1, 3))
    critical = tuple(
        CriticalSpeed(
            draw(FINITE), draw(st.integers(1, k)), draw(FINITE), draw(FINITE), draw(WHIRL)
        )
        for _ in range(draw(st.integers(0, 2)))
    )
    speed = draw(st.none() | FINITE)
    threshold = StabilityThreshold(
        speed,
        None if speed is None else draw(st.integers(1, k)),
        None if speed is None else draw(FINITE),
        "" if speed is None else draw(WHIRL),
        "threshold"
        if speed is not None
        else draw(st.sampled_from(("stable in range", "unstable in range"))),
    )
    return Campbell(
        draw(TEXT),
        draw(TEXT),
        tuple(draw(st.lists(TEXT, max_size=3))),
        draw(hnp.arrays(np.float64, (p,), elements=FINITE)),
        draw(_complex((p, k))),
        draw(hnp.arrays(np.float64, (p, k), elements=NUMBERS)),
        draw(hnp.arrays(np.float64, (p, k), elements=NUMBERS)),
        tuple(draw(st.lists(FINITE, min_size=1, max_size=2))),
        critical,
        threshold,
        draw(st.integers(0, 5)),
        tuple(draw(st.lists(TEXT, max_size=2))),
    )


@st.composite
def speed_maps(draw: st.DrawFn) -> CriticalSpeedMap:
    s, o, m = draw(st.integers(1, 3)), draw(st.integers(1, 2)), draw(st.integers(1, 3))
    whirl = tuple(
        tuple(tuple(draw(st.lists(WHIRL | st.just(""), min_size=m, max_size=m))) for _ in range(o))
        for _ in range(s)
    )
    return CriticalSpeedMap(
        draw(TEXT),
        draw(hnp.arrays(np.float64, (s,), elements=FINITE)),
        tuple(draw(st.lists(FINITE, min_size=o, max_size=o))),
        draw(hnp.arrays(np.float64, (s, o, m), elements=NUMBERS)),
        whirl,
        damped := draw(st.booleans()),
        draw(hnp.arrays(np.float64, (s, o, m), elements=NUMBERS)) if damped else None,
    )


@pytest.mark.parametrize(
    "kind, strategy",
    [
        (UnbalanceResponse, unbalance_responses()),
        (Campbell, campbells()),
        (CriticalSpeedMap, speed_maps()),
    ],
    ids=["unbalance", "campbell", "speed-map"],
)
def test_rotor_results_round_trip_through_json(kind: type, strategy: st.SearchStrategy) -> None:
    @hypothesis.settings(
        max_examples=40, deadline=None, suppress_health_check=list(hypothesis.HealthCheck)
    )
    @hypothesis.given(strategy)
    def check(result: object) -> None:
        back = kind.from_dict(_json(result))
        _same(result, back)
        assert back.to_dict() == result.to_dict()  # type: ignore[attr-defined]

    check()


def test_bundled_rotor_results_round_trip() -> None:
    """The results of the bundled Jeffcott rotor and Friswell's 5.9.1 rotor, as the
    analyses make them (a pedestal-free rotor has no bearing forces: shape (N, 0, 2))."""
    jeffcott = load(EXAMPLES / "jeffcott_rotor.toml")
    friswell = load(EXAMPLES / "friswell_5_9_1.toml")
    results = [
        jeffcott.unbalance_response(np.array([100.0, 316.2, 600.0])),
        friswell.unbalance_response(np.array([50.0, 90.0])),
        jeffcott.campbell(),
        friswell.critical_speed_map([1e6, 1e7], modes=2, orders=(1.0, 2.0)),
        load(EXAMPLES / "friswell_5_9_5.toml").critical_speed_map([1e6], modes=2, damped=True),
    ]
    for result in results:
        back = type(result).from_dict(_json(result))
        _same(result, back)
        assert back.to_dict() == result.to_dict()
    assert results[0].bearing_forces.shape == (3, 0, 2)
    assert results[1].bearing_forces.shape == (2, 2, 2)


def test_a_saved_rotor_result_of_the_wrong_shape_is_refused_with_its_key() -> None:
    jeffcott = load(EXAMPLES / "jeffcott_rotor.toml")
    data = _json(jeffcott.unbalance_response(np.array([100.0, 200.0])))
    data["X"]["real"] = data["X"]["real"][:1]
    with pytest.raises(
        AnalysisError, match=r"UnbalanceResponse 'X.real' has shape \(1, 1\), not \(2, 1\)"
    ):
        UnbalanceResponse.from_dict(data)
    data = _json(jeffcott.campbell())
    data["mac"] = [row[:1] for row in data["mac"]]
    with pytest.raises(AnalysisError, match="'mac'"):
        Campbell.from_dict(data)
    data = _json(load(EXAMPLES / "friswell_5_9_1.toml").critical_speed_map([1e6], modes=2))
    data["whirl"] = [[["forward"]]]
    with pytest.raises(AnalysisError, match="'whirl'"):
        CriticalSpeedMap.from_dict(data)
    data["whirl"] = "forward"
    with pytest.raises(AnalysisError, match="'whirl'"):
        CriticalSpeedMap.from_dict(data)
    data = _json(load(EXAMPLES / "friswell_5_9_1.toml").critical_speed_map([1e6], modes=2))
    data["damped"] = True
    with pytest.raises(AnalysisError, match="damping ratios exactly when it is damped"):
        CriticalSpeedMap.from_dict(data)
