"""Generator of hostile ``[matrices]`` models and a crash-isolating runner (docs/fuzzing.md).

Each case is a fresh folder holding a valid model whose ``M``, ``K`` or ``C`` is a
path to a hostile matrix file or special file:

* ``npy``: dense ``.npy`` with mutated headers (shape, dtype, fortran order, object
  dtype / pickles, header lengths), truncated or extended bodies;
* ``npz_dense`` / ``npz_sparse``: numpy archives, dense or in scipy's ``save_npz``
  layout (csr/csc/coo/bsr/dia) with mutated ``indices``/``indptr``/``row``/``col``/
  ``shape``/``data``/``format``, dtypes, duplicate entries, negative and huge
  indices, wrong lengths;
* ``mtx``: Matrix Market with mutated banners (field/symmetry words), size lines,
  entry counts, truncated bodies, out-of-range indices;
* ``archive``: hand-built zip files -- many members, bomb-like ratios (small on
  disk), encrypted flag bits, unknown compression methods, ZIP64 markers, lying
  sizes in the central directory;
* ``special``: FIFOs, symbolic links (to /dev/zero, outside the folder, loops,
  dangling), directories, absolute and ``../`` paths, NUL bytes, device files;
* any file case may also get byte-level mutations on top (``+bytes``).

Each input runs ``python -m resonant`` in a subprocess (so a SIGSEGV is seen as a
signal) under a wall-clock budget and ``RLIMIT_AS``; peak RSS comes from
``wait4``.  See ``run_case`` and ``verdict``.
"""

from __future__ import annotations

import contextlib
import io
import os
import random
import resource
import signal
import struct
import subprocess
import sys
import threading
import time
import warnings
import zipfile
import zlib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
N = 3  # size of the valid model
MEMORY_LIMIT = int(1.5 * 2**30)  # RLIMIT_AS of each subprocess
RSS_BOUND = 1 * 2**30  # peak RSS above this is a bug
HUGE = [2**31 - 1, 2**31, 2**32, 2**63 - 1, -1, -2**31, -2**63, 10**6, 200_001, 0, 1, 2, 3, 4]
DTYPES = ["<f8", ">f8", "<f4", "<f2", "<i4", "<i8", ">i8", "<u8", "<i1", "|b1", "<c16", "|O",
          "<U3", "|S4", "<M8[s]", "<V8", "<f16", "[('a','<f8')]"]


def _model(K: str, M: str = "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]", C: str | None = None) -> str:
    text = f"[parameters]\nw = 3\n\n[matrices]\nM = {M}\nK = {K}\n"
    if C is not None:
        text += f"C = {C}\n"
    return text + '\n[[harmonic]]\nomega = "w"\nF_S = [1, 0, 0]\n'


def _q(path: str) -> str:
    import json
    return json.dumps(path)


# -- file builders: (rng) -> bytes ---------------------------------------------------------

def _npy_bytes(array: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    np.save(buffer, array, allow_pickle=True)
    return buffer.getvalue()


def _npy_raw(descr: str, fortran: bool, shape: tuple, body: bytes, pad: int = 0) -> bytes:
    header = f"{{'descr': {descr!r}, 'fortran_order': {fortran}, 'shape': {shape}, }}"
    if descr.startswith("["):
        header = f"{{'descr': {descr}, 'fortran_order': {fortran}, 'shape': {shape}, }}"
    header = header + " " * pad
    total = 10 + len(header) + 1
    header += " " * ((64 - total % 64) % 64) + "\n"
    if len(header) < 65536:
        return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode("latin1") \
            + body
    return b"\x93NUMPY\x02\x00" + struct.pack("<I", len(header)) + header.encode("latin1") + body


def _shape(rng: random.Random) -> tuple:
    return rng.choice([(N, N), (N,), (N, N, N), (), (0, 0), (N, N + 1), (rng.choice(HUGE),) * 2,
                       (200_000, 200_000), (2**40, 1), (-1, 3), (N, 0), (1, 1), (2**62, 2**62)])


def gen_npy(rng: random.Random) -> bytes:
    op = rng.random()
    if op < 0.3:
        array = np.eye(N) * rng.choice([1.0, np.nan, np.inf, -1e308, 1e-320, 0.0])
        array = array.astype(rng.choice(["f8", "f4", "i4", "i8", "c16", "u1", "bool", ">f8"]))
        if rng.random() < 0.3:
            array = np.asfortranarray(array)
        return _npy_bytes(array)
    if op < 0.4:  # pickles and object arrays
        return _npy_bytes(np.array([[1, 2, 3], [4, None, 6], [7, 8, {}]], dtype=object))
    descr = rng.choice(DTYPES)
    shape = _shape(rng)
    size = rng.choice([0, 8, 8 * N * N, 8 * N * N - 1, 8 * N * N + 5, 4 * N * N, 1000])
    body = np.eye(N).tobytes()[:size].ljust(size, b"\x00")
    data = _npy_raw(descr, rng.random() < 0.3, shape, body, pad=rng.choice([0, 0, 0, 70000]))
    if rng.random() < 0.2:  # mangle version or header length
        data = bytearray(data)
        if rng.random() < 0.5:
            data[6] = rng.choice([0, 2, 3, 9, 255])
        else:
            data[8:10] = struct.pack("<H", rng.randrange(65536))
        data = bytes(data)
    return data


def _zip(members: dict[str, bytes], compression: int = zipfile.ZIP_STORED) -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", compression) as archive:
        for name, data in members.items():
            archive.writestr(name, data)
    return buffer.getvalue()


def _sparse_members(rng: random.Random) -> dict[str, np.ndarray]:
    import scipy.sparse as sp

    fmt = rng.choice(["csr", "csc", "coo", "bsr", "dia"])
    matrix = sp.random(N, N, density=0.7, random_state=rng.randrange(2**31), format="csr") \
        + sp.eye(N, format="csr")
    matrix = matrix.asformat(fmt)
    members: dict[str, np.ndarray] = {"format": np.array(fmt), "shape": np.array(matrix.shape)}
    if fmt in ("csr", "csc", "bsr"):
        members.update(indices=matrix.indices, indptr=matrix.indptr, data=matrix.data)
    elif fmt == "coo":
        members.update(row=matrix.row, col=matrix.col, data=matrix.data)
    else:
        members.update(offsets=matrix.offsets, data=matrix.data)
    return members


def _mutate_array(array: np.ndarray, rng: random.Random) -> np.ndarray:
    op = rng.randrange(9)
    flat = np.array(array).ravel().copy()
    if op == 0 and flat.size:
        flat = flat.astype(np.int64) if flat.dtype.kind in "iu" else flat
        flat[rng.randrange(flat.size)] = rng.choice(HUGE) if flat.dtype.kind in "iu" \
            else rng.choice([np.nan, np.inf, 1e308])
        return flat
    if op == 1:
        return flat[:max(0, flat.size - rng.randint(1, 2))]
    if op == 2:
        return np.concatenate([flat, flat[: rng.randint(1, 3)]])
    if op == 3:  # duplicate entries
        return np.concatenate([flat, flat])
    if op == 4:
        return flat.astype(rng.choice(["f8", "i1", "u8", "c16", "U4", "O", "bool", "f2", ">i8"]))
    if op == 5:
        return np.array(rng.choice([[], [[1, 2], [3, 4]], "csr", [rng.choice(HUGE)] * 2,
                                    [N, N, N], 7, [-N, -N]]))
    if op == 6:
        return flat[::-1].copy()
    if op == 7 and flat.size:
        return np.full(rng.choice([1, flat.size, 1000]), rng.choice(HUGE), dtype=np.int64)
    return flat.reshape(-1, 1) if flat.size else flat


def gen_npz_sparse(rng: random.Random) -> bytes:
    members = _sparse_members(rng)
    for _ in range(rng.randint(1, 3)):
        name = rng.choice(sorted(members) + ["format", "shape"])
        if rng.random() < 0.12:
            del members[name]
        elif name == "format" and rng.random() < 0.5:
            members[name] = np.array(rng.choice(["csr", "csc", "coo", "bsr", "dia", "lil", "dok",
                                                 "", "CSR", "csr\x00", "x" * 1000]))
        else:
            members[name] = _mutate_array(members[name], rng)
    if rng.random() < 0.1:
        members["extra"] = np.zeros(3)
    return _npz(members, rng)


def _npz(members: dict[str, np.ndarray], rng: random.Random) -> bytes:
    raw = {f"{k}.npy": _npy_bytes(np.asarray(v)) for k, v in members.items()}
    return _zip(raw, rng.choice([zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED]))


def gen_npz_dense(rng: random.Random) -> bytes:
    key = rng.choice(["K", "M", "C", "arr_0", "x", "K.npy"])
    members: dict[str, np.ndarray] = {key: np.eye(N) * 2}
    op = rng.random()
    if op < 0.3:
        members[rng.choice(["M", "arr_1", "K"])] = np.ones((N, N))
    elif op < 0.6:
        members[key] = _mutate_array(members[key], rng)
    raw = {f"{k}.npy" if not k.endswith(".npy") else k: _npy_bytes(np.asarray(v))
           for k, v in members.items()}
    if rng.random() < 0.3:
        raw[f"{key}.npy"] = gen_npy(rng)
    return _zip(raw, rng.choice([zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED]))


def gen_mtx(rng: random.Random) -> bytes:
    obj = rng.choice(["matrix", "vector", "MATRIX", "tensor"])
    fmt = rng.choice(["coordinate", "array", "coordinate", "sparse"])
    field = rng.choice(["real", "integer", "complex", "pattern", "double", "real", "unsigned"])
    sym = rng.choice(["general", "symmetric", "skew-symmetric", "hermitian", "general", "weird"])
    banner = f"%%MatrixMarket {obj} {fmt} {field} {sym}"
    if rng.random() < 0.1:
        banner = rng.choice(["", "%%MatrixMarket", "%MatrixMarket matrix coordinate real general",
                             "%%MatrixMarket matrix coordinate real general extra"])
    rows = cols = N
    if rng.random() < 0.3:
        rows = rng.choice(HUGE)
        cols = rng.choice([rows, N, rng.choice(HUGE)])
    lines = [banner, "% comment"]
    if fmt == "array":
        lines.append(f"{rows} {cols}")
        values = [str(rng.choice([1.0, 0.0, 2.5, "nan", "inf", "1e999", "x", "1 2"]))
                  for _ in range(N * N)]
        lines += values
    else:
        entries = [(i, i, 2.0) for i in range(1, N + 1)] + [(1, 2, -1.0), (2, 1, -1.0)]
        if rng.random() < 0.3:
            entries += entries  # duplicates
        if rng.random() < 0.3:
            entries.append((rng.choice(HUGE), rng.choice(HUGE), 1.0))
        count = len(entries)
        if rng.random() < 0.3:
            count = rng.choice(HUGE + [count + 1, count - 1])
        lines.append(f"{rows} {cols} {count}")
        for i, j, v in entries:
            lines.append(f"{i} {j}" if field == "pattern" else f"{i} {j} {v}")
    if rng.random() < 0.3:
        lines = lines[: rng.randint(1, len(lines))]  # truncated
    text = "\n".join(lines) + rng.choice(["\n", "", "\r\n", "\n\n\n"])
    if rng.random() < 0.1:
        text = text.replace(" ", rng.choice(["\t", "  ", ",", "\x00"]))
    return text.encode("utf-8")


# -- hand-built zip archives ----------------------------------------------------------------

def _local(name: bytes, data: bytes, method: int, flags: int, crc: int, csize: int, usize: int,
           extra: bytes = b"") -> bytes:
    return struct.pack("<IHHHHHIIIHH", 0x04034B50, 20, flags, method, 0, 0, crc, csize, usize,
                       len(name), len(extra)) + name + extra + data


def _central(name: bytes, method: int, flags: int, crc: int, csize: int, usize: int,
             offset: int, extra: bytes = b"") -> bytes:
    return struct.pack("<IHHHHHHIIIHHHHHII", 0x02014B50, 20, 20, flags, method, 0, 0, crc, csize,
                       usize, len(name), len(extra), 0, 0, 0, 0, offset) + name + extra


def _eocd(count: int, size: int, offset: int) -> bytes:
    return struct.pack("<IHHHHIIH", 0x06054B50, 0, 0, count, count, size, offset, 0)


def gen_archive(rng: random.Random) -> bytes:
    kind = rng.choice(["many", "bomb", "encrypted", "method", "zip64", "lying", "nested"])
    good = _npy_bytes(np.eye(N) * 2)
    entries: list[tuple[bytes, bytes, int, int, int, int, int, bytes]] = []
    if kind == "many":
        for i in range(rng.choice([100, 1000, 5000, 70000 // 10])):
            entries.append((f"a{i}.npy".encode(), b"", 0, 0, 0, 0, 0, b""))
        entries.append((b"K.npy", good, 0, 0, zlib.crc32(good), len(good), len(good), b""))
    elif kind == "bomb":
        # 10 MB of zeros in an npy body compresses to ~10 kB; claim and/or really hold it
        size = rng.choice([10**7, 5 * 10**7])
        header = _npy_raw("<f8", False, (int((size // 8) ** 0.5),) * 2, b"")
        compressor = zlib.compressobj(9, zlib.DEFLATED, -15)
        payload = compressor.compress(header)
        chunk = b"\x00" * 2**20
        for _ in range(size // len(chunk)):
            payload += compressor.compress(chunk)
        payload += compressor.flush()
        claimed = rng.choice([size + len(header), 100, 2**32 - 1])
        entries.append((b"K.npy", payload, 8, 0, 0, len(payload), claimed, b""))
    elif kind == "encrypted":
        entries.append((b"K.npy", good, rng.choice([0, 8]), rng.choice([1, 0x41, 0x2001]),
                        zlib.crc32(good), len(good), len(good), b""))
    elif kind == "method":
        entries.append((b"K.npy", good, rng.choice([1, 6, 9, 12, 14, 93, 95, 99, 255, 65535]), 0,
                        zlib.crc32(good), len(good), len(good), b""))
    elif kind == "zip64":
        extra = struct.pack("<HHQQ", 1, 16, len(good), len(good))
        entries.append((b"K.npy", good, 0, 0, zlib.crc32(good), 0xFFFFFFFF, 0xFFFFFFFF, extra))
    elif kind == "lying":
        entries.append((b"K.npy", good, 0, 0, rng.choice([0, zlib.crc32(good)]),
                        rng.choice([len(good), 1, 10**9]), rng.choice([len(good), 1, 2**31]),
                        b""))
    else:  # an archive inside an archive, and odd names
        inner = _zip({"K.npy": good})
        entries.append((rng.choice([b"K.npy", b"../K.npy", b"/etc/K.npy", b"K\x00.npy"]), inner,
                        0, 0, zlib.crc32(inner), len(inner), len(inner), b""))
    local, central = b"", b""
    for name, data, method, flags, crc, csize, usize, extra in entries:
        offset = len(local)
        local += _local(name, data, method, flags, crc, csize, usize, extra)
        central += _central(name, method, flags, crc, csize, usize, offset, extra)
    count = len(entries)
    if kind == "zip64" and rng.random() < 0.5:
        count = 0xFFFF  # ZIP64 marker in the end record
    end = _eocd(min(count, 0xFFFF), len(central), len(local))
    return local + central + end


# -- byte mutations -------------------------------------------------------------------------

def mutate_file_bytes(data: bytes, rng: random.Random) -> bytes:
    data = bytearray(data)
    for _ in range(rng.randint(1, 6)):
        if not data:
            data += bytes([rng.randrange(256)])
            continue
        i = rng.randrange(len(data))
        op = rng.random()
        if op < 0.4:
            data[i] = rng.randrange(256)
        elif op < 0.55:
            del data[i:i + rng.randint(1, 16)]
        elif op < 0.7:
            data[i:i] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        elif op < 0.85 and len(data) >= 4:  # an interesting integer
            j = rng.randrange(len(data) - 3)
            data[j:j + 4] = struct.pack("<I", rng.choice([0, 1, 0xFFFFFFFF, 0x7FFFFFFF, 0xFFFF,
                                                          0x10000, 0x80000000]))
        else:
            data = data[:i]  # truncate
    return bytes(data)


FILE_GENERATORS = {"npy": (gen_npy, ".npy"), "npz_dense": (gen_npz_dense, ".npz"),
                   "npz_sparse": (gen_npz_sparse, ".npz"), "mtx": (gen_mtx, ".mtx"),
                   "archive": (gen_archive, ".npz")}
GENERATORS = sorted(FILE_GENERATORS) + ["special"]


def _special(rng: random.Random, folder: Path) -> str:
    """A path value naming a special file or an escaping path; creates what it names."""
    suffix = rng.choice([".npy", ".npz", ".mtx"])
    name = "K" + suffix
    op = rng.randrange(12)
    target = folder / name
    if op == 0:
        os.mkfifo(target)
    elif op == 1:
        os.symlink("/dev/zero", target)
    elif op == 2:
        outside = folder.parent / f"outside{suffix}"
        outside.write_bytes(_npy_bytes(np.eye(N)) if suffix == ".npy" else gen_mtx(rng))
        os.symlink(outside, target)
    elif op == 3:
        os.symlink(name, target)  # a loop onto itself
    elif op == 4:
        os.symlink("L2" + suffix, target)
        os.symlink(name, folder / ("L2" + suffix))
    elif op == 5:
        target.mkdir()
    elif op == 6:
        os.symlink(folder / "missing.npy", target)
    elif op == 7:
        return rng.choice(["/dev/zero", "/dev/urandom", "/dev/null", "/proc/self/mem",
                           "/etc/passwd", "/proc/self/fd/0", "/dev/stdin"])
    elif op == 8:
        return rng.choice(["../K.npy", "../../../../etc/passwd", "sub/../../K.npz",
                           "./" + "../" * 40 + "dev/zero", "K.npy/.", "sub/..//K.mtx"])
    elif op == 9:
        return rng.choice(["", ".", "..", "/", "K.npy\x00.txt", "K" * 5000 + ".npy", "~/K.npy",
                           "K.NPY", "K.npy ", "\\\\server\\share\\K.npy", "K.txt", "file:///K.npy"])
    elif op == 10:
        (folder / "sub").mkdir()
        os.symlink("..", folder / "sub" / "up")
        return "sub/up/" + ("sub/up/" * rng.randint(1, 30)) + name
    else:
        os.symlink("/proc/self/fd/0", target)
    return name


def make_case(rng: random.Random, folder: Path) -> tuple[str, Path]:
    """Fill ``folder`` with a hostile case: (generator name, model path)."""
    kind = rng.choice(GENERATORS)
    folder.mkdir(parents=True, exist_ok=True)
    if kind == "special":
        value = _special(rng, folder)
    else:
        generate, suffix = FILE_GENERATORS[kind]
        for _ in range(20):  # a mutation may be impossible (e.g. "1e+" as float): retry
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    data = generate(rng)
                break
            except (ValueError, TypeError, KeyError, OverflowError, struct.error):
                continue
        else:
            data = b""
        if rng.random() < 0.35:
            data = mutate_file_bytes(data, rng)
            kind += "+bytes"
        value = "K" + suffix
        (folder / value).write_bytes(data)
    slot = rng.choice(["K", "K", "M", "C"])
    ref = _q(value)
    eye = "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]"
    if slot == "K":
        text = _model(ref)
    elif slot == "M":
        text = _model("[[2, -1, 0], [-1, 2, -1], [0, -1, 2]]", M=ref)
    else:
        text = _model(eye, C=ref)
    path = folder / "model.toml"
    path.write_text(text, encoding="utf-8", errors="surrogateescape")
    return kind, path


def save_case(folder: Path, target: Path, note: str = "") -> None:
    """Copy a case to ``target``: small regular files as they are, and a ``CASE.txt``
    describing every entry (symbolic links with their targets, FIFOs, directories), since
    git keeps neither FIFOs nor links that point outside."""
    import shutil

    target.mkdir(parents=True, exist_ok=True)
    lines = [note] if note else []
    for entry in sorted(folder.rglob("*")):
        rel = entry.relative_to(folder)
        if entry.is_symlink():
            lines.append(f"{rel}: symbolic link -> {os.readlink(entry)}")
        elif entry.is_fifo():
            lines.append(f"{rel}: FIFO (os.mkfifo)")
        elif entry.is_dir():
            lines.append(f"{rel}: directory")
            (target / rel).mkdir(parents=True, exist_ok=True)
        elif entry.is_file():
            size = entry.stat().st_size
            lines.append(f"{rel}: regular file, {size} bytes")
            if size <= 2**20:
                (target / rel).parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(entry, target / rel)
    (target / "CASE.txt").write_text("\n".join(lines) + "\n", encoding="utf-8")


# -- running in a subprocess ----------------------------------------------------------------

def _limit(memory: int) -> None:
    resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))


def _address_space() -> int:
    """This process's virtual size in bytes (0 where /proc is not there).  A forked child
    inherits its parent's mappings -- libraries, thread stacks, allocator arenas, which
    grow with every test run before it -- so its limit is what it may add to them."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return 0


def run_case(args: list[str], budget: float, memory: int = MEMORY_LIMIT, cwd: Path | None = None
             ) -> tuple[int | str, str, str, float, int]:
    """``python -m resonant ARGS`` in a subprocess: (status, stdout, stderr, seconds, peak RSS).

    status is the exit code, ``"signal NAME"`` or ``"hang"``; the peak RSS (bytes) is the
    child's ``ru_maxrss`` from ``wait4``.
    """
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"), PYTHONFAULTHANDLER="")
    env.pop("PYTHONFAULTHANDLER")
    t0 = time.monotonic()
    proc = subprocess.Popen([sys.executable, "-m", "resonant", *args], stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, cwd=cwd,
                            preexec_fn=lambda: _limit(memory), start_new_session=True)
    chunks: dict[str, bytes] = {}

    def drain(name: str, stream) -> None:
        chunks[name] = stream.read(4 * 2**20)  # bounded; the rest is discarded
        while stream.read(2**16):
            pass
    readers = [threading.Thread(target=drain, args=(n, s), daemon=True)
               for n, s in (("out", proc.stdout), ("err", proc.stderr))]
    for reader in readers:
        reader.start()
    hung, code, rss = False, 0, 0
    while True:  # wait4 gives this child's own peak RSS
        pid, wstatus, usage = os.wait4(proc.pid, os.WNOHANG)
        if pid:
            code = os.waitstatus_to_exitcode(wstatus)
            rss = usage.ru_maxrss * 1024
            break
        if time.monotonic() - t0 > budget and not hung:
            hung = True
            os.killpg(proc.pid, signal.SIGKILL)
        time.sleep(0.005)
    proc.returncode = code  # reaped here; keep Popen from waiting again
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)  # grandchildren, if any
    for reader in readers:
        reader.join(5)
    out, err = chunks.get("out", b""), chunks.get("err", b"")
    elapsed = time.monotonic() - t0
    status: int | str = "hang" if hung else (
        f"signal {signal.Signals(-code).name}" if code < 0 else code)
    return status, out.decode("utf-8", "replace"), err.decode("utf-8", "replace"), elapsed, rss


def run_forked(args: list[str], budget: float, memory: int = MEMORY_LIMIT,
               cwd: Path | None = None) -> tuple[int | str, str, str, float, int]:
    """Like :func:`run_case`, but the child is forked from this (already imported) process.

    Much faster than a fresh interpreter per input (no imports), and as isolated: the
    child sets ``RLIMIT_AS`` (``memory`` beyond what it inherited), runs ``resonant.cli.main`` with stdout/stderr sent to files,
    and leaves with ``os._exit``; a signal, a hang or the peak RSS is seen by ``wait4``.
    """
    import tempfile

    import resonant.cli  # noqa: F401  (imported before forking)

    with tempfile.TemporaryFile() as out_file, tempfile.TemporaryFile() as err_file:
        t0 = time.monotonic()
        pid = os.fork()
        if pid == 0:  # the child
            code = 1
            try:
                os.setsid()
                import faulthandler
                faulthandler.disable()  # pytest's handler writes to the terminal, not fd 2
                _limit(memory + _address_space())
                if cwd is not None:
                    os.chdir(cwd)
                null = os.open(os.devnull, os.O_RDONLY)
                os.dup2(null, 0)
                os.dup2(out_file.fileno(), 1)
                os.dup2(err_file.fileno(), 2)
                sys.stdout = open(1, "w", encoding="utf-8", errors="replace", closefd=False)
                sys.stderr = open(2, "w", encoding="utf-8", errors="replace", closefd=False)
                signal.signal(signal.SIGALRM, signal.SIG_DFL)
                signal.setitimer(signal.ITIMER_REAL, 0)
                from resonant.cli import main
                try:
                    code = main(args)
                except SystemExit as exc:
                    code = exc.code if isinstance(exc.code, int) else 2
                code = code if isinstance(code, int) else 1
            except BaseException:  # noqa: BLE001 -- reported as a traceback
                import traceback
                traceback.print_exc()
                code = 1
            finally:
                with contextlib.suppress(BaseException):
                    sys.stdout.flush()
                    sys.stderr.flush()
                os._exit(code)
        hung, code, rss = False, 0, 0
        delay = 0.001
        while True:
            got, wstatus, usage = os.wait4(pid, os.WNOHANG)
            if got:
                code = os.waitstatus_to_exitcode(wstatus)
                rss = usage.ru_maxrss * 1024
                break
            if time.monotonic() - t0 > budget and not hung:
                hung = True
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(pid, signal.SIGKILL)
            time.sleep(delay)
            delay = min(delay * 2, 0.02)
        elapsed = time.monotonic() - t0
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(pid, signal.SIGKILL)  # grandchildren, if any
        out_file.seek(0)
        err_file.seek(0)
        out, err = out_file.read(4 * 2**20), err_file.read(4 * 2**20)
    status: int | str = "hang" if hung else (
        f"signal {signal.Signals(-code).name}" if code < 0 else code)
    return status, out.decode("utf-8", "replace"), err.decode("utf-8", "replace"), elapsed, rss


def verdict(status: int | str, out: str, err: str, rss: int, rss_bound: int = RSS_BOUND
            ) -> str | None:
    """Why a subprocess outcome is a bug, or None."""
    if status == "hang":
        return "hang"
    if isinstance(status, str):
        return status  # "signal SIGSEGV", ...
    if status not in (0, 2, 3):
        return f"exit status {status}"
    if "internal error" in err or "internal error" in out:
        return "internal error"
    if "Traceback" in err or "Traceback" in out:
        return "traceback"
    if "MemoryError" in err:
        return "MemoryError"
    if status != 0 and not err.strip():
        return "failure without a message"
    if rss > rss_bound:
        return f"peak RSS {rss // 2**20} MiB"
    return None


COMMANDS = (["solve", "--json"], ["check"], ["modes", "--json"])


def fuzz_case(rng: random.Random, folder: Path, budget: float, memory: int = MEMORY_LIMIT,
              isolation: str = "fork", rss_bound: int = RSS_BOUND) -> dict:
    """One hostile case through one command, in a forked child or a fresh subprocess."""
    kind, path = make_case(rng, folder)
    command = rng.choice(COMMANDS)
    args = [command[0], str(path), "--timeout", "10", *command[1:]]
    runner = run_forked if isolation == "fork" else run_case
    status, out, err, elapsed, rss = runner(args, budget, memory, cwd=folder)
    return {"kind": kind, "command": command[0], "status": status, "seconds": elapsed,
            "rss": rss, "bug": verdict(status, out, err, rss, rss_bound), "stderr": err,
            "folder": folder}
