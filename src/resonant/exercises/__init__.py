"""Exercise variants for teachers: one model, N sets of numbers, solutions, key, Moodle.

:func:`generate` draws N distinct value sets from the model's ``[variants]``
(reproducibly: ``numpy.random.Generator(PCG64(seed))``), derives the model
once and substitutes each variant's numbers into the shared symbolic system,
solves it, and replaces a variant that is not an equilibrium, is unstable or
lies within 5 % of a natural frequency.  :func:`write` writes the statements,
the worked solutions, ``key.json`` and ``moodle.xml``; :func:`grade` checks a
student's answers against the key.  The contract is docs/exercises.md.

Examples
--------
>>> import pathlib, resonant
>>> from resonant.exercises import generate
>>> path = pathlib.Path(resonant.__file__).parents[2] / "examples/teaching/cart_pendulum.toml"
>>> batch = generate(resonant.load(path), 3, seed=1)
>>> len(batch.variants), sorted(batch.variants[0].answers)[:2]
(3, ['C', 'K'])
"""

from .grading import grade, grade_data, grade_text
from .key import KEY_FORMAT, key_data
from .moodle import cloze, moodle_feedback, moodle_xml
from .solutions import solution_report
from .statements import filled_statement
from .variants import RESONANCE_MARGIN, Answer, ExerciseSet, Replacement, Variant, generate
from .writing import FORMATS, write

__all__ = ["generate", "write", "key_data", "moodle_xml", "moodle_feedback", "cloze",
           "filled_statement", "solution_report", "grade", "grade_data", "grade_text",
           "ExerciseSet", "Variant", "Answer", "Replacement", "RESONANCE_MARGIN", "FORMATS",
           "KEY_FORMAT"]
