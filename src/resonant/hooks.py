"""The one inversion of the layer order: lower layers call, upper layers provide.

The layers import only from below (see docs/architecture.md).  A few
conveniences of the lower layers' objects are implemented above them:
``model.linearize()`` (system), ``eom.stationary()``, ``eom.sweep(...)``,
``model.simulate()`` (analyses), ``result.plot()`` and the Jupyter reprs
(views).  Each is a one-line delegate to :func:`call`, which runs the function
that the upper layer registered with :func:`provides` under that name.  The
table :data:`PROVIDERS` says which module registers each name; it is imported
on first use, so ``import resonant.model`` stays light and the lower layer
holds no import of the upper one.

Examples
--------
>>> @provides("example_double")
... def double(x):
...     return 2 * x
>>> call("example_double", 21)
42
"""

from __future__ import annotations

from collections.abc import Callable
from importlib import import_module
from typing import Any, TypeVar

F = TypeVar("F", bound=Callable[..., Any])

#: hook name -> the module that registers it
PROVIDERS: dict[str, str] = {
    "periodic_solution": "resonant.analyses.periodic",
}

_registry: dict[str, Callable[..., Any]] = {}


def provides(name: str) -> Callable[[F], F]:
    """Register the decorated function as the implementation of hook ``name``."""
    def register(fn: F) -> F:
        _registry[name] = fn
        return fn
    return register


def call(name: str, *args: Any, **kwargs: Any) -> Any:
    """Run the implementation of hook ``name`` (importing its provider on first use)."""
    fn = _registry.get(name)
    if fn is None:
        import_module(PROVIDERS[name])
        fn = _registry[name]
    return fn(*args, **kwargs)


__all__ = ["provides", "call", "PROVIDERS"]
