"""The report's rotor section (src/resonant/report/steps/rotor.py): the Campbell diagram's
critical speeds and threshold, the unbalance response said 0-pk and pk-pk, the bearing
forces; the same numbers as the analyses."""

from __future__ import annotations

import numpy as np

import resonant
from conftest import EXAMPLES
from resonant.analyses.campbell import RPM
from resonant.report import write_report

#: a disc on a damped bearing on a pedestal, with a speed range and an unbalance
ROTOR = """
title = "disc on a bearing on a pedestal"
[parameters]
Omega = 0
[rotor]
speed = "Omega"
disc = [{ station = 0, name = "d", m = 10, Ip = 0.1, It = 0.05 }]
[[rotor.bearing]]
station = 0
kxx = 1e6
kyy = 1e6
cxx = 100
cyy = 100
pedestal = { m = 20, kxx = 4e6, kyy = 4e6 }
[campbell]
from = "100 rpm"
to = "12000 rpm"
points = 25
modes = 4
[[unbalance]]
at = "d"
amount = 1e-4
"""


def test_rotor_section(tmp_path) -> None:
    model = resonant.loads(ROTOR)
    text = write_report(model, tmp_path / "r.md", plots=False).read_text(encoding="utf-8")
    assert "## Rotor: Campbell diagram, critical speeds, stability" in text
    assert "## Rotor: unbalance response and bearing forces" in text
    assert "0-pk (semi-axes of the orbit); pk-pk = 2 x 0-pk" in text
    result = model.campbell()
    for c in result.critical_speeds:
        assert f"| {float(c.speed / RPM):.5g} | {float(c.speed):.5g} | {c.mode} |" in text
    response = model.unbalance_response()
    peak = float(np.nanmax(response.bearing_force[:, 0]))
    shown = f"{peak:.5g}".replace("e-0", "e-").replace("e+0", "e").replace("e+", "e")
    assert f"| d | {shown} |" in text
    assert "no threshold of instability" in text


def test_a_model_without_campbell_has_no_rotor_section(tmp_path) -> None:
    text = write_report(resonant.load(EXAMPLES / "two_dof_free.toml"), tmp_path / "r.md",
                        plots=False).read_text(encoding="utf-8")
    assert "Rotor:" not in text
