"""``resonant random``'s output grows with what is asked for, not with the model
(cli/random.py, cli/common.py ``emit_json_streamed``).

References: the streamed JSON is ``RandomResponse.to_dict()`` itself (equal after a JSON
round trip, and ``RandomResponse.from_dict`` reads it back); the text of many responses
shows the 40 of largest RMS, whose values are the full result's.  Measured on a 3,168-DOF
chain (docs/random.md, Output): the JSON without densities is 1.4 MB (it was 1.5 GB with
them, each number on its own line).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.sparse as sp

import resonant.cli.random as random_cli
from conftest import run_cli
from resonant.analyses.random_response import RandomResponse, random_response
from resonant.model import load
from resonant.system import linear_system

N = 120


@pytest.fixture(scope="module")
def chain(tmp_path_factory):  # type: ignore[no-untyped-def]
    folder = tmp_path_factory.mktemp("chain")
    k = np.full(N, 1e5)
    K = sp.diags([np.r_[k[:-1] + k[1:], k[-1]], -k[1:], -k[1:]], [0, 1, -1]).tocsr()
    M = sp.identity(N, format="csr")
    for name, a in (("M", M), ("K", K), ("C", (1e-4 * K + 0.2 * M).tocsr())):
        sp.save_npz(folder / f"{name}.npz", a)
    np.save(folder / "r.npy", np.ones(N))
    path = folder / "chain.toml"
    path.write_text('[matrices]\nM = "M.npz"\nC = "C.npz"\nK = "K.npz"\n[random]\n'
                    'band = [1, 20]\ntolerance = 1e-3\nlines = 40\n[random.psd.ground]\n'
                    'base = "r.npy"\nvalues = 0.01\n')
    return path, random_response(linear_system(load(path)))


def test_streamed_json_is_the_result(chain) -> None:  # type: ignore[no-untyped-def]
    path, result = chain
    status, out, err = run_cli(["random", path, "--json"])
    assert status == 0, err
    data = json.loads(out)
    assert data == json.loads(json.dumps(result.to_dict()))
    back = RandomResponse.from_dict(data)
    assert back.rms == result.rms and np.array_equal(back.psd["q7"], result.psd["q7"])


def test_densities_left_out_above_the_budget(chain, monkeypatch) -> None:  # type: ignore
    path, result = chain
    monkeypatch.setattr(random_cli, "MAX_JSON_NUMBERS", 1000)
    status, out, err = run_cli(["random", path, "--json"])
    assert status == 0 and "--densities all" in err and "'psd' is empty" in err
    data = json.loads(out)
    assert data["psd"] == {} and len(data["responses"]) == N
    assert data["responses"]["q3"]["rms"] == result.rms["q3"]
    status, out, err = run_cli(["random", path, "--json", "--densities", "all"])
    assert status == 0 and len(json.loads(out)["psd"]) == N and "psd" not in err
    status, out, _ = run_cli(["random", path, "--json", "--densities", "none", "--only",
                              "q1"])
    assert json.loads(out)["psd"] == {}


def test_text_shows_the_largest_responses(chain) -> None:  # type: ignore[no-untyped-def]
    path, result = chain
    status, out, err = run_cli(["random", path])
    assert status == 0, err
    rows = [line.split()[0] for line in out.splitlines() if line.startswith("  q")]
    largest = sorted(result.names, key=lambda n: -result.rms[n])[:random_cli.TEXT_ROWS]
    assert sorted(rows) == sorted(largest)
    assert f"40 of {N} responses" in out
    status, out, _ = run_cli(["random", path, "--only", ",".join(f"q{i}" for i in
                                                                 range(1, N + 1))])
    assert f"of {N} responses" not in out and out.count("\n  q") == N
