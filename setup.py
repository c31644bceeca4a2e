"""Packaging hook: the bundled examples go into the package as ``resonant/examples``.

Everything else about the package is declared in ``pyproject.toml``.  The model files of
``examples/`` (with their ``parts/``, ``teaching/`` and ``matrices/`` folders) are copied
into the built package, so that ``resonant example NAME`` finds them after
``pip install resonant`` as it does in a checkout of the repository.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = Path(__file__).resolve().parent
#: the files of examples/ that ship with the package
SHIPPED = ("*.toml", "*/*.toml", "*/*.mtx", "*/*.csv", "*/*.op4")


class BuildWithExamples(build_py):
    """``build_py`` that also copies the example model files into the package."""

    def run(self) -> None:
        super().run()
        target = Path(self.build_lib) / "resonant" / "examples"
        for pattern in SHIPPED:
            for source in sorted((HERE / "examples").glob(pattern)):
                copy = target / source.relative_to(HERE / "examples")
                copy.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(source, copy)


setup(cmdclass={"build_py": BuildWithExamples})
