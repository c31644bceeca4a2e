"""``resonant report --nonlinear``: the section "Beyond small oscillations"."""

from __future__ import annotations

import pytest

from conftest import EXAMPLES, run_cli
from resonant.api import load
from resonant.report import build_report, render
from resonant.report.blocks import Figure, Heading, Table
from resonant.report.nonlinear import NonlinearCurve


def test_duffing_section_has_curve_operating_point_and_difference() -> None:
    report = build_report(load(EXAMPLES / "duffing.toml"), nonlinear=True)
    headings = report.headings()
    assert "Beyond small oscillations" in headings
    assert headings.index("Beyond small oscillations") < headings.index("Warnings") \
        if "Warnings" in headings else True
    start = next(i for i, b in enumerate(report.blocks)
                 if isinstance(b, Heading) and b.text == "Beyond small oscillations")
    section = report.blocks[start:]
    curves = [b for b in section if isinstance(b, Figure) and isinstance(b.plot, NonlinearCurve)]
    assert len(curves) == 1
    curve = curves[0].plot
    assert curve.operating == pytest.approx(1.0)
    # the peak of x (a special point since the peaks are located) and the two folds
    assert [p.kind for p in curve.response.special_points] == ["peak", "fold", "fold"]
    table = next(b for b in section if isinstance(b, Table))
    assert len(table.rows) == 1 and "%" in str(table.rows[0][3])
    text = render(report, "html")
    assert "Beyond small oscillations" in text and "fold at omega" in text
    assert "<svg" in text[text.index("Beyond small oscillations"):]


def test_without_the_flag_no_section() -> None:
    assert "Beyond small oscillations" not in build_report(
        load(EXAMPLES / "duffing.toml"), plots=False).headings()


def test_cli_cart_pendulum(tmp_path) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "cart.md"
    status, _, err = run_cli(["report", EXAMPLES / "cart_pendulum.toml", "--set", "F0=50",
                              "--set", "r0=0.1", "--nonlinear", "-o", out])
    assert status == 0, err
    text = out.read_text()
    section = text[text.index("## Beyond small oscillations"):]
    assert "-6.42 %" in section and "-38.3 %" in section  # x2 and x1 against linear
    assert "Figure" in section
