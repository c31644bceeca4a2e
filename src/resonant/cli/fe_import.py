"""``resonant import FILE [FILE ...] [-o MODEL.toml]``: a model beside FE files.

Writes a model whose ``[matrices]`` section names the matrices of a Nastran OUTPUT4 file,
the DMIG entries of a punch file, an ANSYS ``.full`` file or Abaqus matrix output
(:func:`resonant.model.fe_import.fe_model`: the roles from Nastran's names or the file
names, or ``--mass``/``--stiffness``/``--damping``/``--dofs``), loads it as every command
will (a file that cannot be read is exit 2 naming it, and no model is written), prints the
checks of ``resonant check --matrices`` and what to run next.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import resonant.cli.common as cli

from ..analyses.fe_checks import check_matrices
from ..errors import ModelError, Problem, name_list
from ..model.fe_import import ImportRefused, fe_model
from ..model.loader import loads
from ..system.build import linear_system


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    del parent  # no model file yet: none of the common options apply
    command = subparsers.add_parser(
        "import", help="write a model naming the matrices of FE files (OP4, DMIG, .full, "
                       "Abaqus)",
        description="Write a [matrices] model beside FE files (docs/interop.md): the mass, "
                    "stiffness and damping matrices and the DOF map are found by Nastran's "
                    "names (MAA/MGG/MXX, KAA..., BAA..., DOFS/USET) or the Abaqus file names "
                    "(MASS, STIF, DMP), or named here. The model is loaded and checked "
                    "before it is written.")
    command.add_argument("files", nargs="+", metavar="FILE",
                         help="one .op4, .pch/.bdf/.dat (DMIG) or .full file, or the Abaqus "
                              ".mtx files")
    command.add_argument("-o", "--output", metavar="MODEL.toml",
                         help="the model to write (default: FILE with .toml, beside it)")
    for option, role in (("--mass", "M"), ("--stiffness", "K"), ("--damping", "C"),
                         ("--dofs", "dofs")):
        command.add_argument(option, dest=f"role_{role}", metavar="NAME",
                             help=f"the {option[2:]} matrix: its name in the file (OP4, DMIG)"
                                  " or its file (Abaqus)" if role != "dofs" else
                                  "the n x 2 OP4 matrix of (node, component) pairs")
    command.add_argument("--title", help="the model's title")
    command.add_argument("--drop-unconnected", action="store_true",
                         help="remove the coordinates with neither mass nor stiffness")
    command.add_argument("--force", action="store_true", help="overwrite MODEL.toml")
    command.add_argument("--json", action="store_true", help="print one JSON object")
    command.set_defaults(run=run_import)


def _output(args: argparse.Namespace) -> Path:
    if args.output:
        return Path(args.output)
    return Path(args.files[0]).with_suffix(".toml")


def run_import(args: argparse.Namespace) -> int:
    output = _output(args)
    if output.suffix.lower() != ".toml":
        raise ModelError(Problem("the model must be a .toml file", str(output)))
    if output.exists() and not args.force:
        raise ModelError(Problem("the file exists; choose another -o or pass --force",
                                 str(output)))
    names = {role: value for role in ("M", "K", "C", "dofs")
             if (value := getattr(args, f"role_{role}", None))}
    try:
        imported = fe_model(args.files, output, names=names, title=args.title,
                            drop_unconnected=args.drop_unconnected)
    except ImportRefused as exc:
        raise ModelError(Problem(str(exc), str(exc.path))) from None
    model = loads(imported.text, source=str(output), base_dir=output.resolve().parent,
                  allow_paths=imported.outside)
    system = linear_system(model)
    checks = check_matrices(system)
    _write(output, imported.text)
    if args.json:
        cli.emit_json({"model": str(output), "matrices": imported.matrices,
                       "coordinates": list(model.coordinates),
                       "allow_paths": list(imported.outside), "checks": checks.to_dict()})
        return 0
    print(f"wrote {output}: {len(model.coordinates)} coordinate(s): "
          f"{name_list(model.coordinates, limit=8)}")
    for key, value in imported.matrices.items():
        print(f"  {key} = {value}")
    print(checks.summary())
    allow = "".join(f" --allow-path {folder}" for folder in imported.outside)
    print(f"next: resonant modes {output}{allow}")
    return 0


def _write(path: Path, text: str) -> None:
    """Write the model (a new file unless --force), in one piece."""
    partial = path.with_name(f".{path.name}.partial")
    try:
        partial.write_text(text, encoding="utf-8")
        os.replace(partial, path)
    except OSError as exc:
        partial.unlink(missing_ok=True)
        raise ModelError(Problem(f"cannot write it ({exc.strerror})", str(path))) from None


__all__ = ["register", "run_import"]
