"""Write a simulated impact test of the 3-mass chain as a Universal File (docs/testing.md).

    python examples/make_lab_test.py DIRECTORY [--noise 0.002] [--binary]

writes ``DIRECTORY/impact.uff``: four hammer hits on mass 3 of the "real structure" --
examples/chain3_lab.toml with k1 = 1100 N/m and k2 = 950 N/m instead of 1000 -- and the
displacements of the three masses, 16 s a hit at 256 samples per second, with white noise
of ``--noise`` times each channel's RMS (the histories are the exact response to the
sampled force, resonant.analyses.transient).  The file is generated, not committed.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import resonant
from resonant.analyses.virtual_test import simulated_test
from resonant.model.measured import write_uff

HERE = Path(__file__).resolve().parent
#: the "real structure": what the test measures and the updating should find
TRUTH = {"k1": "1100 N/m", "k2": "950 N/m", "k3": "1000 N/m"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory", type=Path)
    parser.add_argument("--noise", type=float, default=0.002)
    parser.add_argument("--binary", action="store_true", help="write dataset 58b")
    args = parser.parse_args()
    truth = resonant.load(HERE / "chain3_lab.toml").with_parameters(**TRUTH)
    data = simulated_test(truth.linearize(), truth.measurement_section, records=4,
                          duration=16.0, step=1 / 256, noise=args.noise, seed=5)
    args.directory.mkdir(parents=True, exist_ok=True)
    write_uff(args.directory / "impact.uff", data, binary=args.binary)
    print(f"wrote {args.directory / 'impact.uff'}: {', '.join(data.names)}")


if __name__ == "__main__":
    main()
