"""A command whose reader goes away (``resonant modes m.toml | head -1``): it stops quietly
with exit status 141, as a program ended by SIGPIPE (resonant.cli._run).  It said
"internal error (BrokenPipeError ...); this is a bug in resonant" and exited 1."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "matrices" / "frame.toml"


def test_a_closed_pipe_is_no_internal_error() -> None:
    read, write = os.pipe()
    os.close(read)   # the reader is gone before the command prints
    try:
        run = subprocess.run([sys.executable, "-m", "resonant", "modes", str(EXAMPLE)],
                             stdout=write, stderr=subprocess.PIPE, text=True, timeout=120)
    finally:
        os.close(write)
    assert run.returncode == 141, run.stderr
    assert "internal error" not in run.stderr and "Traceback" not in run.stderr
