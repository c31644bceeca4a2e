"""``resonant energies``: the T, U, D derived from a model's parts, per part and in total."""

from __future__ import annotations

import argparse
import sys
from typing import Any

import resonant.cli.common as common

from ..model import Model


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser],
             parent: argparse.ArgumentParser) -> None:
    energies = subparsers.add_parser(
        "energies", parents=[parent],
        help="the kinetic and potential energy and the dissipation function derived from "
             "the model's parts ([[body]], [[spring]], ...), per part and in total")
    energies.add_argument("--json", action="store_true",
                          help='print {"T", "U", "D", "parts": [{"kind", "name", '
                               '"T"|"U"|"D"}], "total": {...}}')
    energies.set_defaults(run=run_energies)


def energies_dict(model: Model) -> dict[str, Any]:
    """The derived energies (``"T"``, ``"U"``, ``"D"``), per part, and the totals."""
    derived = model.parts
    data: dict[str, Any] = derived.to_dict() if derived is not None else \
        {"T": "0", "U": "0", "D": "0", "parts": []}
    data["total"] = {key: model.energy[key].text if key in model.energy else "0"
                     for key in ("T", "U", "D")}
    return data


def run_energies(args: argparse.Namespace) -> int:
    model = common.load_model(args)
    data = energies_dict(model)
    if args.json:
        common.emit_json(data)
        return 0
    lines = [f"{model.title or args.model}: energies"]
    if model.parts is None:
        lines.append("  the model has no parts ([[body]], [[spring]], ...); its energies are "
                     "those of [energy]")
    else:
        lines.append("  per part:")
        width = max((len(f'{c["kind"]} "{c["name"]}"') for c in data["parts"]), default=0)
        for item in data["parts"]:
            label = f'{item["kind"]} "{item["name"]}"'
            key = next(k for k in ("T", "U", "D") if k in item)
            lines.append(f"    {label:<{width}}  {key} = {item[key]}")
        lines.append("  derived from the parts:")
        lines.extend(f"    {key} = {data[key]}" for key in ("T", "U", "D"))
        if model.parts.written:
            lines.append("  written in [energy]:")
            lines.extend(f"    {key} = {e.text}" for key, e in model.parts.written.items())
    lines.append("  total:")
    lines.extend(f"    {key} = {data['total'][key]}" for key in ("T", "U", "D"))
    sys.stdout.write("\n".join(lines) + "\n")
    return 0
