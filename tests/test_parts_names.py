"""Parts (docs/parts.md): names of points and bodies that collide with the model's names, and
negative masses or inertias after the parameters are replaced (``Model.with_parameters``)."""

from __future__ import annotations

import pytest

import resonant
from conftest import EXAMPLES
from resonant.errors import ModelError

BASE = """
[parameters]
m = 1
k = 2
[coordinates]
x = ""
[signals]
s = "sin(t)"
[definitions]
d = "2*x"
"""


@pytest.mark.parametrize("name", ["m", "x", "s", "d"])
@pytest.mark.parametrize("kind", ["point", "body"])
def test_part_names_collide_with_model_names(name: str, kind: str) -> None:
    part = (f'[[point]]\nname = "{name}"\nposition = ["0", "0"]\n' if kind == "point" else
            f'[[body]]\nname = "{name}"\nmass = "m"\nposition = ["x", "0"]\n')
    other = '[[body]]\nname = "cart"\nmass = "m"\nposition = ["x", "0"]\n' \
        if kind == "point" else ""
    with pytest.raises(ModelError) as info:
        resonant.loads(BASE + part + other, source="t.toml")
    assert f"t.toml: [{kind} \"{name}\"] name: '{name}' is already a name of the model" \
        in str(info.value)


def test_with_parameters_rechecks_masses_and_inertias() -> None:
    model = resonant.load(EXAMPLES / "parts" / "cart_pendulum.toml")
    with pytest.raises(ModelError) as info:
        model.with_parameters(m2="-1")
    message = str(info.value)
    assert '[body "rod"] mass: the mass is negative (-1)' in message
    assert '[body "rod"] inertia: the inertia is negative' in message
    assert model.with_parameters(m2=3).parameter_values["m2"] == 3.0
    with pytest.raises(ModelError, match=r'\[body "cart"\] mass: the mass is negative'):
        model.with_parameters(m1="1 - 3")


def test_an_invalid_body_is_one_problem_not_also_a_missing_energy(tmp_path):
    """A model of parts whose only body is invalid: its problem alone, not also "the
    section [energy] is missing" (the parts give the energies)."""
    from resonant.api import loads
    from resonant.errors import ModelError

    with pytest.raises(ModelError) as info:
        loads('[parameters]\nm = 1\n[coordinates]\nx = ""\n[[body]]\nname = "a"\nmass = "m"\n')
    assert [p.section for p in info.value.problems] == ['body "a"']
