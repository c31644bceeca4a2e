"""Resolve the docstrings' references to the objects' public pages (nitpicky builds).

The code's docstrings name objects by where they live (``resonant.analyses.sweep.sweep``,
or ``backbone`` inside its own module); the API reference documents the public names
(``resonant.sweep``).  A reference Sphinx cannot find is resolved here:

* to the public page of the same object (``resonant.NAME`` or
  ``resonant.exercises.NAME``), found by identity, not by name; or, for the results and
  analyses that ``import resonant`` does not name (:data:`HOME_PAGES`: the loads beyond a
  sine, fatigue, the nonlinear steady state), to their page under their own module;
* to the online reference of the standard library, numpy and scipy (a link; nothing is
  fetched while building);
* else, for an object of resonant that has no page of its own (an internal helper: the
  API reference has no private helpers), to its name set as code, not a link.

A reference to something that does not exist stays a warning, so that a typo or a
renamed function still fails the nitpicky build.
"""

from __future__ import annotations

import importlib
from typing import Any

from docutils import nodes

#: module -> the results and analyses documented under their own module (docs/api.rst):
#: every result type and analysis function of resonant.analyses that ``import resonant``
#: does not name (tests/test_docs_site.py checks that together with resonant.__all__ they
#: are every result and every function returning one)
HOME_PAGES: dict[str, tuple[str, ...]] = {
    "resonant.analyses.random_response": ("random_response", "RandomResponse"),
    "resonant.analyses.periodic_load": ("fourier_series", "FourierSeries", "periodic_response",
                                        "periodic_load_response", "PeriodicResponse"),
    "resonant.analyses.shock": ("pulse", "shock_response_spectrum", "ShockSpectrum"),
    "resonant.analyses.transient": ("transient_response", "shock_response",
                                    "TransientResponse", "shock_peaks", "ShockPeaks"),
    "resonant.analyses.fatigue": ("SNCurve", "spectral_fatigue", "SpectralFatigue",
                                  "response_fatigue", "ResponseFatigue",
                                  "rainflow_damage", "RainflowDamage"),
    "resonant.analyses.periodic": ("periodic_solution", "PeriodicSolution"),
    "resonant.analyses.slow_sweep": ("swept_state", "SweptState"),
    "resonant.analyses.harmonic_balance": ("nonlinear_sweep", "full_sweep"),
    "resonant.analyses.condensed": ("condensed_sweep",),
    "resonant.analyses.backbone": ("backbone", "BackboneCurve"),
    "resonant.analyses.special_points": ("SpecialPoint",),
    "resonant.analyses.stationary": ("HarmonicResponse",),
    "resonant.analyses.campbell": ("campbell", "CriticalSpeed", "StabilityThreshold",),
    "resonant.analyses.unbalance": ("unbalance_response",),
    "resonant.analyses.rotor_map": ("critical_speed_map", "CriticalSpeedMap"),
    "resonant.analyses.frf_mimo": ("estimate_frf_matrix", "frf_matrix_from_measurement",
                                   "MIMOFRF"),
    "resonant.analyses.frf_update": ("update_to_frf", "FRFUpdate"),
    "resonant.analyses.frf_estimate": ("estimate_frf", "frf_from_measurement",),
    "resonant.analyses.identify": ("identify_modes", "identify_modes_matrix", "Stabilization"),
    "resonant.analyses.correlate": ("correlate", "correlate_shapes",),
    "resonant.analyses.measured_match": ("match_test", "match_test_file", "MatchedTest",
                                         "check_correlation"),
    "resonant.analyses.model_update": ("update_parameters",),
    "resonant.analyses.state_space": ("state_space",),
    "resonant.analyses.fe_checks": ("check_matrices",),
}

#: online references of the libraries the docstrings mention (no intersphinx: the build
#: runs without network)
EXTERNAL = {
    "scipy": "https://docs.scipy.org/doc/scipy/reference/generated/{name}.html",
    "numpy": "https://numpy.org/doc/stable/reference/generated/{name}.html",
    "abc": "https://docs.python.org/3/library/abc.html#{name}",
}


def _find(target: str, module: str | None) -> Any:
    """The object a dotted name denotes, relative to ``module`` first; None if none."""
    candidates = ([f"{module}.{target}"] if module else []) + [target]
    for dotted in candidates:
        parts = dotted.split(".")
        for cut in range(len(parts), 0, -1):
            try:
                obj: Any = importlib.import_module(".".join(parts[:cut]))
            except ImportError:
                continue
            try:
                for attribute in parts[cut:]:
                    obj = getattr(obj, attribute)
            except AttributeError:
                break
            return obj
    return None


def _public_name(obj: Any) -> str | None:
    """``resonant.NAME`` or ``resonant.exercises.NAME`` of the same object."""
    import resonant
    import resonant.exercises

    for package in (resonant, resonant.exercises):
        for name in getattr(package, "__all__", ()):
            if getattr(package, name, None) is obj:
                return f"{package.__name__}.{name}"
    for module, names in HOME_PAGES.items():
        home = importlib.import_module(module)
        for name in names:
            if getattr(home, name, None) is obj:
                return f"{module}.{name}"
    return None


def _resolve(app: Any, env: Any, node: Any, contnode: Any) -> Any:
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"]
    root = target.split(".")[0]
    if root in EXTERNAL:
        link = nodes.reference("", "", internal=False,
                               refuri=EXTERNAL[root].format(name=target))
        link += contnode
        return link
    obj = _find(target, node.get("py:module"))
    if obj is None:  # a name of the module that defines the documented object
        page = _find(str(node["refdoc"]).rsplit("/", 1)[-1], None)
        home = getattr(page, "__module__", None)
        obj = _find(target, home) if home else None
    if obj is None or not getattr(obj, "__module__", "resonant").startswith("resonant"):
        return None
    public = _public_name(obj)
    if public is not None:
        domain = env.get_domain("py")
        for role in ("obj", "func", "class", "data"):
            found = domain.resolve_xref(env, node["refdoc"], app.builder, role, public,
                                        node, contnode)
            if found is not None:
                return found
    return contnode  # resonant's own helper without a page: its name, as code


def setup(app: Any) -> dict[str, Any]:
    """Register the resolver."""
    app.connect("missing-reference", _resolve)
    return {"parallel_read_safe": True, "version": "1"}
