"""Every bundled example gives the numbers it gave before the restructuring into layers.

The files in ``tests/golden/`` are the ``--json`` output of ``resonant solve``,
``resonant modes`` and a few ``resonant sweep`` runs of the bundled examples,
written by resonant 0.1.0 (commit b3ff181) before the package was split into
layers.  Numbers must agree to a relative 1e-9 (absolute 1e-12 for values near
zero, which are rounding noise); strings and keys must be identical.  New keys
may be added to the output (the stored ones must all still be there).

One deliberate change since: an antiresonance is a true zero of the response,
so the sweeps of the tuned mass damper (damped: its dips are minima, not zeros) and of
the cart-pendulum (x2's dip at 6.44 rad/s is a minimum of 0.031, not the 0.0 that a
clamped parabola reported) list none; their stored ``antiresonances`` were updated, and
the undamped cart-pendulum's sweep now warns that its peaks are unbounded.  Phases are
compared as angles: -pi is now written as pi.

Another deliberate change (physical units, docs/units.md): the examples now give their data
with units, with the same SI values, except the rotating unbalance's speed, now
``n_rpm = "1200 rpm"``: a value in rpm holds its 2 pi, so its SI value (what
``parameters`` reports) is 125.66 rad/s instead of the bare 1200, and ``Omega = "n_rpm"``
(125.66 rad/s, unchanged).  The stored ``parameters.n_rpm`` was updated.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from resonant.cli import main

ROOT = Path(__file__).parents[1]
GOLDEN = Path(__file__).parent / "golden"

SWEEPS = {
    "tuned_mass_damper.sweep": ["--param", "omega", "--from", "15", "--to", "50",
                                "--points", "141"],
    "cart_pendulum.sweep": ["--param", "omega", "--from", "1", "--to", "30", "--points", "59"],
    "absorber.sweep": ["--param", "k2", "--from", "50", "--to", "400", "--points", "36"],
}


def _compare(stored, now, path="$"):
    if ".phases" in path and isinstance(stored, float) and isinstance(now, float):
        # phases are angles in (-pi, pi] (-pi is written as pi)
        stored = math.remainder(stored - now, 2 * math.pi) + now
    if isinstance(stored, dict):
        assert isinstance(now, dict), path
        for key, value in stored.items():
            assert key in now, f"{path}.{key} is missing"
            _compare(value, now[key], f"{path}.{key}")
    elif isinstance(stored, list):
        assert isinstance(now, list) and len(now) == len(stored), path
        for i, (a, b) in enumerate(zip(stored, now)):
            _compare(a, b, f"{path}[{i}]")
    elif isinstance(stored, float) or (isinstance(stored, int) and not isinstance(stored, bool)
                                       and isinstance(now, float)):
        assert isinstance(now, (int, float)) and not isinstance(now, bool), path
        assert math.isclose(stored, now, rel_tol=1e-9, abs_tol=1e-12), \
            f"{path}: stored {stored!r}, now {now!r}"
    else:
        assert stored == now, f"{path}: stored {stored!r}, now {now!r}"


def _cases():
    for path in sorted(GOLDEN.glob("*.json")):
        example, command = path.stem.rsplit(".", 1)
        yield pytest.param(path, example, command, id=path.stem)


@pytest.mark.parametrize(("path", "example", "command"), list(_cases()))
def test_example_output_unchanged(path, example, command, capsys):
    args = [command, str(ROOT / "examples" / f"{example}.toml"), "--json"]
    if command == "sweep":
        args += SWEEPS[path.stem]
    assert main(args) == 0
    now = json.loads(capsys.readouterr().out)
    _compare(json.loads(path.read_text()), now)
