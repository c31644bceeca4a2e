"""The result of a study: its table, summary statistics and Sobol indices.

Examples
--------
>>> import pandas as pd
>>> frame = pd.DataFrame({"sample": [0, 1, 2], "k": [1.0, 2.0, 3.0],
...                       "stable": [True, True, False], "status": ["ok"] * 3,
...                       "reason": [""] * 3})
>>> summary_table(frame, ["stable"])["mean"].tolist()
[0.6666666666666666]
"""

from __future__ import annotations

import html
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..model.study import StudySpec
from .designs import sobol_problem
from .study_charts import plot_study

if TYPE_CHECKING:
    import pandas as pd

#: the quantiles of a summary
QUANTILES = (0.05, 0.5, 0.95)


def summary_table(frame: pd.DataFrame, columns: Sequence[str]) -> pd.DataFrame:
    """Count, mean, standard deviation, extremes and quantiles of each column.

    Parameters
    ----------
    frame : pandas.DataFrame
    columns : sequence of str

    Returns
    -------
    pandas.DataFrame
        One row per column; NaN values (failed samples) are left out.

    Examples
    --------
    >>> import pandas as pd
    >>> summary_table(pd.DataFrame({"f": [1.0, 2.0, float("nan")]}), ["f"])["count"].tolist()
    [2]
    """
    import pandas as pd

    rows = []
    for name in columns:
        values = np.array(frame[name], dtype=float)  # a copy: the quantiles sort it in place
        if not np.isfinite(values).all():
            values = values[np.isfinite(values)]
        stats: dict[str, Any] = {"quantity": name, "count": int(values.size)}
        if values.size:
            q = np.quantile(values, QUANTILES, overwrite_input=True)
            stats.update(mean=float(values.mean()), std=float(values.std(ddof=1))
                         if values.size > 1 else math.nan, min=float(values.min()),
                         **{f"q{int(p * 100):02d}": float(v) for p, v in zip(QUANTILES, q)},
                         max=float(values.max()))
        rows.append(stats)
    return pd.DataFrame(rows).set_index("quantity")


def bootstrap_seed(seed: int) -> int:
    """The seed of SALib's bootstrap for a study's seed: never 0 (SALib takes a seed of 0
    for none and draws from numpy's global generator, so the confidence intervals would
    change from run to run).

    Examples
    --------
    >>> bootstrap_seed(0), bootstrap_seed(2026)
    (1, 2027)
    """
    return int(seed) % (2**32 - 1) + 1


def sobol_indices(frame: pd.DataFrame, spec: StudySpec, seed: int | None = None
                  ) -> dict[str, dict[str, Any]]:
    """First-order and total Sobol indices of every quantity, with 95 % confidence
    intervals, by SALib from the rows of a ``sobol`` design (in sample order).

    Saltelli's sample is a block of ``len(vary) + 2`` rows per base sample; a block
    where a quantity is missing (a failed sample, or a partial file) is left out of that
    quantity's indices, and the note says from how many base samples they are.  A
    quantity that is constant, or missing from nearly every block, has no indices
    (None) and a note saying why.

    Parameters
    ----------
    frame : pandas.DataFrame
    spec : StudySpec
    seed : int, optional
        The seed of SALib's bootstrap of the confidence intervals (default: from the
        study's seed, so that a run gives the same intervals every time).

    Returns
    -------
    dict
        quantity column -> {"parameters", "S1", "S1_conf", "ST", "ST_conf", "note"}.

    Examples
    --------
    >>> import pandas as pd
    >>> from resonant.model.study import study_spec
    >>> from resonant.studies.designs import chunk_values
    >>> spec = study_spec({"a": "uniform(0, 1)", "b": "uniform(0, 1)"}, ["stable"],
    ...                   design="sobol", samples=256, parameters=["a", "b", "stable_"],
    ...                   coordinates=["x"], outputs=[])
    >>> v = chunk_values(spec, 0, spec.size)
    >>> frame = pd.DataFrame({"sample": range(spec.size), "stable": 3 * v["a"]})
    >>> [round(s, 3) for s in sobol_indices(frame, spec)["stable"]["ST"]]
    [1.0, 0.0]
    """
    from SALib.analyze import sobol

    problem = sobol_problem(len(spec.vary))
    step = len(spec.vary) + 2
    ordered = frame.sort_values("sample") if "sample" in frame else frame  # files: in order
    bootstrap = bootstrap_seed(spec.seed if seed is None else seed)
    out: dict[str, dict[str, Any]] = {}
    for name in spec.columns:
        y = np.asarray(ordered[name], dtype=float)
        entry: dict[str, Any] = {"parameters": list(spec.vary)}
        blocks = y[:(min(y.size, spec.size) // step) * step].reshape(-1, step)
        complete = blocks[np.isfinite(blocks).all(axis=1)]
        none = [None] * len(spec.vary)
        if len(complete) < 2:
            entry.update(S1=none, S1_conf=none, ST=none, ST_conf=none,
                         note="no indices: the quantity is missing from nearly every "
                              "sample (failed samples or a partial file)")
        elif np.ptp(complete) == 0:
            entry.update(S1=none, S1_conf=none, ST=none, ST_conf=none,
                         note="no indices: the quantity is constant")
        else:
            with np.errstate(all="ignore"):
                result = sobol.analyze(problem, complete.ravel(), calc_second_order=False,
                                       seed=bootstrap)
            entry.update({k: [float(v) if math.isfinite(v) else None for v in result[k]]
                          for k in ("S1", "S1_conf", "ST", "ST_conf")})
            left = spec.samples - len(complete)
            entry["note"] = "" if left == 0 else (
                f"from {len(complete)} of {spec.samples} base samples: the quantity is "
                f"missing (failed samples or a partial file) in the others")
        out[name] = entry
    return out


@dataclass(frozen=True)
class StudyResult:
    """A study's samples and quantities, and what they say.

    Attributes
    ----------
    table : pandas.DataFrame
        One row per sample: ``sample``, the varied parameters, the quantities,
        ``status`` and ``reason``.
    spec : StudySpec
        The study.
    description : dict
        The model, the request, the chunk size (as stored in a result file).
    sensitivity : dict or None
        Sobol indices per quantity (``sobol`` designs; :func:`sobol_indices`).
    where : str
        Where the chunks ran.

    Examples
    --------
    >>> import pandas as pd
    >>> from resonant.model.study import study_spec
    >>> spec = study_spec({"k": [1, 2]}, ["stable"], parameters=["k"], coordinates=["x"],
    ...                   outputs=[])
    >>> result = StudyResult(pd.DataFrame({"sample": [0, 1], "k": [1.0, 2.0],
    ...                                    "stable": [True, True], "status": ["ok", "ok"],
    ...                                    "reason": ["", ""]}), spec)
    >>> result.to_dict()["status"]
    {'ok': 2}
    """

    table: Any
    spec: StudySpec
    description: dict[str, Any] = field(default_factory=dict)
    sensitivity: dict[str, dict[str, Any]] | None = None
    where: str = ""

    def summary(self) -> Any:
        """Statistics of every quantity over the samples where it exists.

        Returns
        -------
        pandas.DataFrame
        """
        return summary_table(self.table, self.spec.columns)

    def failures(self) -> Any:
        """The number of samples by status.

        Returns
        -------
        pandas.Series
        """
        return self.table["status"].value_counts(sort=True).loc[lambda c: c > 0]

    def to_dict(self) -> dict[str, Any]:
        """The JSON form: the study, the summary, the Sobol indices and the rows' count
        by status (the rows themselves are in the table).

        Returns
        -------
        dict
        """
        summary = self.summary()
        return {"study": self.spec.to_dict(), "rows": int(len(self.table)),
                "status": {str(k): int(v) for k, v in self.failures().items()},
                "summary": {name: {k: (None if isinstance(v, float) and not math.isfinite(v)
                                       else v) for k, v in row.items()}
                            for name, row in summary.to_dict(orient="index").items()},
                "sensitivity": self.sensitivity, "where": self.where}

    def _repr_html_(self) -> str:
        head = (f"<p>Study of {len(self.table)} samples ({html.escape(self.spec.design)}), "
                f"varying {html.escape(', '.join(self.spec.vary))}</p>")
        return head + self.summary().to_html(float_format=lambda v: f"{v:.6g}")

    def plot(self, directory: str | Path) -> list[Path]:
        """Write the study's pictures into ``directory``
        (:func:`resonant.studies.study_charts.plot_study`).

        Parameters
        ----------
        directory : str or Path

        Returns
        -------
        list of Path
            The files written.
        """
        return plot_study(self.table, list(self.spec.vary), list(self.spec.columns),
                          directory, self.sensitivity, grid=self.spec.design == "grid")


__all__ = ["StudyResult", "bootstrap_seed", "sobol_indices", "summary_table"]
