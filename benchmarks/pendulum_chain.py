"""Generator of the N-link planar pendulum chain as a resonant model file.

Point masses m1..mN on massless rods l1..lN, absolute angles th1..thN from
the downward vertical, gravity g; hanging down, so the reference state
th_i = 0 is the (stable) equilibrium.  The positions are ``[definitions]``::

    x_i = x_{i-1} + l_i sin(th_i),   y_i = y_{i-1} - l_i cos(th_i)
    T = sum m_i (x_i'^2 + y_i'^2) / 2,   U = sum m_i g y_i

Run ``python benchmarks/pendulum_chain.py 5`` to print the 5-link model.

Examples
--------
>>> text = pendulum_chain_toml(2)
>>> "y2 = \\"y1 - l2*cos(th2)\\"" in text
True
"""

from __future__ import annotations

import sys
from pathlib import Path


def pendulum_chain_toml(n: int) -> str:
    """The model file text of an ``n``-link pendulum chain (n >= 1)."""
    if n < 1:
        raise ValueError("a pendulum chain needs at least one link")
    lines = [f'title = "{n}-link planar pendulum chain"', "", "[parameters]", "g = 9.81"]
    # Distinct, irregular values so that no accidental symmetry hides an error.
    for i in range(1, n + 1):
        lines.append(f"m{i} = {1.0 + 0.1 * (i % 7):g}")
    for i in range(1, n + 1):
        lines.append(f"l{i} = {0.5 + 0.05 * (i % 5):g}")
    lines += ["", "[coordinates]"]
    lines += [f'th{i} = "angle of link {i} from the downward vertical"'
              for i in range(1, n + 1)]
    lines += ["", "[definitions]"]
    for i in range(1, n + 1):
        prev_x = f"x{i - 1} + " if i > 1 else ""
        prev_y = f"y{i - 1} - " if i > 1 else "-"
        lines.append(f'x{i} = "{prev_x}l{i}*sin(th{i})"')
        lines.append(f'y{i} = "{prev_y}l{i}*cos(th{i})"')
    kinetic = " + ".join(f"m{i}*(x{i}'^2 + y{i}'^2)/2" for i in range(1, n + 1))
    potential = " + ".join(f"m{i}*g*y{i}" for i in range(1, n + 1))
    lines += ["", "[energy]", f'T = "{kinetic}"', f'U = "{potential}"', ""]
    return "\n".join(lines)


def write_pendulum_chain(n: int, directory: str | Path) -> Path:
    """Write ``pendulum_chain_<n>.toml`` into ``directory``; return its path."""
    path = Path(directory) / f"pendulum_chain_{n}.toml"
    path.write_text(pendulum_chain_toml(n), encoding="utf-8")
    return path


if __name__ == "__main__":
    print(pendulum_chain_toml(int(sys.argv[1]) if len(sys.argv) > 1 else 3))
