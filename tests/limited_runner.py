"""``resonant ARGS`` in a child process under an address-space limit, without paying the
interpreter's start and resonant's imports for every run.

The security and memory tests run the command line in a process of its own under
``RLIMIT_AS``, so that a regression fails the test instead of killing the test run.  A
fresh interpreter for each of about a hundred such runs spends a second of CPU each on
importing numpy, scipy, sympy and resonant.  Instead, one server process per test worker
imports ``resonant.cli`` once and forks a child for each run: the child sets the limit,
takes the run's environment, working folder and output files, calls
``resonant.cli.main`` and exits with its status, exactly as ``python -c "...main(...)"``
would, with the modules of the package already loaded (lazily imported extras, such as
pyuff or matplotlib, are still imported by the child under the limit).  The server has no
threads (one BLAS thread), so forking it is safe; it stops when the test session ends
(:func:`stop`), and a child that outlives its timeout is killed.
"""

from __future__ import annotations

import atexit
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

SERVER = r'''
import io, json, os, resource, signal, sys, time
from resonant.cli import main

def child(request):
    os.chdir(request["cwd"])
    os.environ.clear()
    os.environ.update(request["env"])
    memory = request["memory"]
    if memory:
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    for fd, name in ((1, request["stdout"]), (2, request["stderr"])):
        os.dup2(os.open(name, os.O_WRONLY | os.O_CREAT | os.O_TRUNC), fd)
    os.dup2(os.open(os.devnull, os.O_RDONLY), 0)  # the protocol's pipe is the server's
    sys.stdin = open(0, encoding="utf-8", closefd=False)
    sys.stdout = open(1, "w", encoding="utf-8", closefd=False)
    sys.stderr = open(2, "w", encoding="utf-8", closefd=False)
    try:
        status = main(request["args"])
    except SystemExit as exc:
        status = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        if isinstance(exc.code, str):
            print(exc.code, file=sys.stderr)
    except BaseException:
        import traceback
        traceback.print_exc()
        status = 1
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0 if status is None else int(status))

protocol = sys.stdout
for line in sys.stdin:
    request = json.loads(line)
    pid = os.fork()
    if pid == 0:
        child(request)
    end = time.monotonic() + request["timeout"]
    status = None
    while status is None:
        done, code = os.waitpid(pid, os.WNOHANG)
        if done:
            status = os.waitstatus_to_exitcode(code)
        elif time.monotonic() > end:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            status = "timeout"
        else:
            time.sleep(0.005)
    protocol.write(json.dumps({"status": status}) + "\n")
    protocol.flush()
'''

_server: subprocess.Popen[str] | None = None


def _started() -> subprocess.Popen[str]:
    global _server
    if _server is None or _server.poll() is not None:
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
                   MKL_NUM_THREADS="1")
        _server = subprocess.Popen([sys.executable, "-c", SERVER], stdin=subprocess.PIPE,
                                   stdout=subprocess.PIPE, text=True, env=env)
    return _server


def run_resonant(args: list[str], *, memory: int, timeout: float = 60,
                 env: dict[str, str] | None = None,
                 cwd: str | os.PathLike[str] | None = None
                 ) -> subprocess.CompletedProcess[str]:
    """``resonant ARGS`` in a child process with at most ``memory`` bytes of address space
    (0: no limit) and the environment ``env`` (default: this process's); its exit status,
    standard output and standard error as :func:`subprocess.run` gives them.

    Raises
    ------
    subprocess.TimeoutExpired
        When the run takes longer than ``timeout`` seconds (the child is killed).
    """
    server = _started()
    with tempfile.TemporaryDirectory(prefix="resonant-limited-") as folder:
        out, err = Path(folder) / "stdout", Path(folder) / "stderr"
        request = {"args": [str(a) for a in args], "memory": int(memory),
                   "timeout": float(timeout), "env": dict(os.environ if env is None else env),
                   "cwd": str(Path(cwd) if cwd is not None else Path.cwd()),
                   "stdout": str(out), "stderr": str(err)}
        assert server.stdin is not None and server.stdout is not None
        server.stdin.write(json.dumps(request) + "\n")
        server.stdin.flush()
        reply = server.stdout.readline()
        if not reply:
            raise RuntimeError("the limited-run server stopped")
        status = json.loads(reply)["status"]
        stdout = out.read_text(encoding="utf-8", errors="replace") if out.exists() else ""
        stderr = err.read_text(encoding="utf-8", errors="replace") if err.exists() else ""
    if status == "timeout":
        raise subprocess.TimeoutExpired(["resonant", *map(str, args)], timeout, stdout,
                                        stderr)
    return subprocess.CompletedProcess(["resonant", *map(str, args)], int(status), stdout,
                                       stderr)


def stop() -> None:
    """Stop the server (at the end of the session, and at exit)."""
    global _server
    if _server is not None:
        if _server.stdin is not None:
            _server.stdin.close()
        try:
            _server.wait(timeout=10)
        except subprocess.TimeoutExpired:
            _server.kill()
            _server.wait()
        _server = None


atexit.register(stop)
