"""``resonant example [NAME] [-o FILE]``: the bundled example models, also after ``pip install``.

Without a name it lists the examples with their titles; with one it writes the model file
to ``examples/NAME.toml`` under the current folder (so that the commands of the guide,
``resonant solve examples/cart_pendulum.toml``, work as written), or to ``-o FILE``
(``-o -``: standard output), and copies the data files the model reads from its folder
(``matrices/inboard_fixed``: its ``inboard_fixed.op4``) beside it.  The examples come from
the installed package (``resonant/examples``, copied there when the package is built) or,
in a checkout of the repository, from its ``examples/`` folder.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from ..errors import ModelError, Problem

HERE = Path(__file__).resolve()


def examples_folder() -> Path | None:
    """The folder of the bundled examples: the package's own, else the repository's.

    Examples
    --------
    >>> (examples_folder() / "cart_pendulum.toml").is_file()
    True
    """
    for folder in (HERE.parents[1] / "examples", HERE.parents[3] / "examples"):
        if (folder / "cart_pendulum.toml").is_file():
            return folder
    return None


def example_names(folder: Path) -> list[str]:
    """Every example as ``name`` or ``folder/name`` (without ``.toml``), sorted.

    Examples
    --------
    >>> names = example_names(examples_folder())
    >>> "cart_pendulum" in names and "parts/quarter_car" in names
    True
    """
    return sorted(p.relative_to(folder).with_suffix("").as_posix()
                  for p in folder.rglob("*.toml"))


#: the data files an example may read beside it (shipped with it: setup.py's SHIPPED)
DATA_SUFFIXES = (".op4", ".mtx", ".csv")


def example_data(model: Path) -> list[Path]:
    """The data files an example reads from its own folder: those of its folder whose name
    the model file quotes (``M = "inboard_fixed.op4:MQQ"``), sorted.

    Examples
    --------
    >>> [p.name for p in example_data(examples_folder() / "matrices" / "inboard_fixed.toml")]
    ['inboard_fixed.op4']
    >>> example_data(examples_folder() / "cart_pendulum.toml")
    []
    """
    text = model.read_text(encoding="utf-8")
    return [path for path in sorted(model.parent.iterdir())
            if path.suffix.lower() in DATA_SUFFIXES and path.is_file()
            and re.search(rf"""["']{re.escape(path.name)}(?::|["'])""", text)]


def _differing(files: list[Path], folder: Path) -> None:
    """Refuse before anything is written when a data file would replace another file."""
    for source in files:
        copy = folder / source.name
        if copy.exists() and (not copy.is_file() or copy.read_bytes() != source.read_bytes()):
            raise ModelError(Problem(f"'{copy}' exists and differs from the example's data "
                                     "file: remove it or write elsewhere with -o FILE",
                                     "example"))


def _copy_beside(files: list[Path], folder: Path) -> None:
    """Copy the example's data files into ``folder``."""
    for source in files:
        copy = folder / source.name
        data = source.read_bytes()
        try:
            copy.write_bytes(data)
        except OSError as exc:
            raise ModelError(Problem(f"cannot write '{copy}': {exc.strerror or exc}",
                                     "example")) from None
        print(f"wrote {copy}", file=sys.stderr)


def _title(path: Path) -> str:
    match = re.search(r'^title\s*=\s*"([^"]*)"', path.read_text(encoding="utf-8"), re.M)
    return match.group(1) if match else ""


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    parser = subparsers.add_parser(
        "example", help="list the bundled example models, or write one to a file",
        description="Without NAME: list the bundled examples. With NAME: write the model "
                    "file to examples/NAME.toml (or to -o FILE; -o - prints it), ready for "
                    "`resonant solve examples/NAME.toml`, with the data files it reads copied "
                    "beside it.")
    parser.add_argument("name", nargs="?", help="the example, e.g. cart_pendulum or "
                                                "parts/quarter_car")
    parser.add_argument("-o", "--output", metavar="FILE",
                        help="where to write it (default examples/NAME.toml; - for stdout); "
                             "the data files it reads are copied beside it")
    parser.set_defaults(run=run_example)


def run_example(args: argparse.Namespace) -> int:
    folder = examples_folder()
    if folder is None:
        raise ModelError(Problem("the bundled examples are not installed with this copy of "
                                 "resonant", "example"))
    names = example_names(folder)
    if args.name is None:
        width = max(len(n) for n in names)
        for name in names:
            print(f"{name:<{width}}  {_title(folder / f'{name}.toml')}")
        return 0
    name = args.name.removesuffix(".toml").removeprefix("examples/")
    if name not in names:
        close = [n for n in names if name in n][:5]
        raise ModelError(Problem(f"no example named '{args.name}'"
                                 + (f" (did you mean {', '.join(close)}?)" if close else "")
                                 + "; `resonant example` lists them", "example"))
    text = (folder / f"{name}.toml").read_text(encoding="utf-8")
    data = example_data(folder / f"{name}.toml")
    if args.output == "-":
        sys.stdout.write(text)
        if data:
            print(f"the model reads {', '.join(p.name for p in data)} beside it: write it "
                  "with -o FILE (or without -o) to get them copied too", file=sys.stderr)
        return 0
    target = Path(args.output) if args.output else Path("examples") / f"{name}.toml"
    if target.exists() and (not target.is_file()
                            or target.read_text(encoding="utf-8") != text):
        raise ModelError(Problem(f"'{target}' exists and differs from the example: remove it "
                                 "or write elsewhere with -o FILE", "example"))
    _differing(data, target.parent)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise ModelError(Problem(f"cannot write '{target}': {exc.strerror or exc}",
                                 "example")) from None
    print(f"wrote {target}", file=sys.stderr)
    _copy_beside(data, target.parent)
    return 0
