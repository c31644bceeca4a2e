"""Exercise variants for teachers (the contract: docs/exercises.md).

The reference exercise as a teacher's model (examples/teaching/cart_pendulum.toml):
30 variants, reproducible from the seed, every answer equal to ``resonant solve`` of
the variant, none near a resonance; the Moodle XML question bank; ``resonant grade``.
"""

from __future__ import annotations

import json
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from conftest import EXAMPLES, run_cli, solve_json

MODEL = EXAMPLES / "teaching" / "cart_pendulum.toml"
N = 30
#: Moodle's NUMBER_REGEX and NUMERICAL alternative (question/type/multianswer/questiontype.php)
NUMBER = r"-?(?:[0-9]+[.,]?[0-9]*|[.,][0-9]+)(?:[eE][-+]?[0-9]+)?"
CLOZE = re.compile(r"\{([0-9]*):(NUMERICAL|NM):=(" + NUMBER + r")(?::(" + NUMBER + r"))?\}")
ANY_CLOZE = re.compile(r"\{[0-9]*:[A-Z_]+:")


def files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def exercise(folder: Path, *extra: str, seed: int = 1, count: int = N) -> tuple[str, str]:
    status, out, err = run_cli(["exercise", MODEL, "--variants", count, "--seed", seed,
                                "-o", folder, *extra])
    assert status == 0, err
    return out, err


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    base = tmp_path_factory.mktemp("exercises")
    out = {}
    for name, seed in (("a", 1), ("b", 1)):
        exercise(base / name, "--format", "html,md,moodle,json", "--no-plots", seed=seed)
        out[name] = base / name
    exercise(base / "c", "--format", "json", seed=2)
    out["c"] = base / "c"
    return out


def key(folder: Path) -> dict:
    return json.loads((folder / "key.json").read_text(encoding="utf-8"))


# -- reproducibility -----------------------------------------------------------------------

def test_same_seed_is_byte_identical(runs: dict[str, Path]) -> None:
    a, b = files(runs["a"]), files(runs["b"])
    assert a.keys() == b.keys()
    assert len(a) == N * 5 + 2  # statement/solution .html .md, solution.json; key, moodle
    for name in a:
        assert a[name] == b[name], name


def test_other_seed_differs(runs: dict[str, Path]) -> None:
    first = [v["varied"] for v in key(runs["a"])["variants"]]
    other = [v["varied"] for v in key(runs["c"])["variants"]]
    assert first != other
    assert (runs["a"] / "key.json").read_bytes() != (runs["c"] / "key.json").read_bytes()


def test_variants_distinct_and_declared_values_only(runs: dict[str, Path]) -> None:
    import resonant

    declared = {v.name: set(v.values) for v in resonant.load(MODEL).exercise.variants}
    for run in ("a", "c"):
        variants = key(runs[run])["variants"]
        assert [v["variant"] for v in variants] == list(range(1, N + 1))
        sets = {tuple(sorted(v["varied"].items())) for v in variants}
        assert len(sets) == N
        for v in variants:
            assert v["varied"].keys() == declared.keys()
            for name, value in v["varied"].items():
                assert value in declared[name], (name, value)
                assert v["parameters"][name] == value


# -- the answers ----------------------------------------------------------------------------

def test_key_equals_resonant_solve_of_each_variant(runs: dict[str, Path]) -> None:
    data = key(runs["a"])
    assert data["answers"] == ["M", "K", "C", "L", "N", "amplitude:x2", "amplitude:phi",
                               "natural_frequencies"]
    for v in data["variants"]:
        sets = [f"--set={k}={x!r}" for k, x in v["varied"].items()]
        solved = solve_json(MODEL, *sets)
        expected = {"M": solved["M"], "K": solved["K"], "C": solved["C"],
                    "L": solved["harmonics"][0]["L"], "N": solved["harmonics"][0]["N"],
                    "amplitude:x2": solved["amplitudes"]["x2"],
                    "amplitude:phi": solved["amplitudes"]["phi"],
                    "natural_frequencies": solved["natural_frequencies"]}
        assert len(solved["harmonics"]) == 1
        for name, value in expected.items():
            answer = v["answers"][name]
            assert answer["value"] == value, (v["variant"], name)
            assert answer["tolerance"] == 0.01
        assert v["answers"]["amplitude:x2"]["unit"] == "m"
        assert v["answers"]["natural_frequencies"]["unit"] == "rad/s"
        assert v["answers"]["M"]["unit"] == "kg"


def test_no_variant_near_a_natural_frequency(runs: dict[str, Path]) -> None:
    for run in ("a", "c"):
        for v in key(runs[run])["variants"]:
            omega = v["parameters"]["omega"]
            for wn in v["answers"]["natural_frequencies"]["value"]:
                assert abs(omega - wn) > 0.05 * wn, (v["variant"], omega, wn)


def test_replacements_are_said(tmp_path: Path) -> None:
    _, err = exercise(tmp_path / "x", "--format", "json", seed=1)
    replaced = key(tmp_path / "x")["replaced"]
    assert replaced, "seed 1 draws value sets near a resonance: they must be replaced"
    assert err.count("replaced the value set") == len(replaced)
    assert all("natural frequency" in r["reason"] for r in replaced)
    for r in replaced:  # and really near one
        m = re.search(r"within ([0-9.]+) %", r["reason"])
        assert m and float(m.group(1)) <= 5


def test_statement_fills_values_and_units(runs: dict[str, Path]) -> None:
    v = key(runs["a"])["variants"][0]
    text = (runs["a"] / "1" / "statement.md").read_text(encoding="utf-8")
    assert f"m1 = {v['varied']['m1']:g} kg" in text
    assert f"k = {v['varied']['k']:g} N/m" in text
    assert "{" not in text.split("| parameter")[0]
    page = (runs["a"] / "1" / "statement.html").read_text(encoding="utf-8")
    assert "<table" in page and f"omega = {v['varied']['omega']:g} rad/s" in page
    solution = (runs["a"] / "1" / "solution.html").read_text(encoding="utf-8")
    assert "Task 2: the stationary solution" in solution


# -- Moodle ----------------------------------------------------------------------------------

def flatten(value: object) -> list[float]:
    if isinstance(value, list):
        return [x for item in value for x in flatten(item)]
    return [float(value)]  # type: ignore[arg-type]


def test_moodle_xml(runs: dict[str, Path]) -> None:
    root = ET.parse(runs["a"] / "moodle.xml").getroot()
    assert root.tag == "quiz"
    questions = root.findall("question")
    assert [q.get("type") for q in questions] == ["category"] + ["cloze"] * N
    category = questions[0].find("category/text")
    assert category is not None and (category.text or "").startswith("$course$/top/")
    data = key(runs["a"])
    tolerance = data["tolerance"]
    names = set()
    for q, v in zip(questions[1:], data["variants"]):
        name = q.find("name/text")
        assert name is not None and name.text
        names.add(name.text)
        text = q.find("questiontext/text")
        assert q.find("questiontext").get("format") == "html"  # type: ignore[union-attr]
        assert text is not None and text.text
        found = CLOZE.findall(text.text)
        # every {n:TYPE: of the text is a valid NUMERICAL sub-question
        assert len(found) == len(ANY_CLOZE.findall(text.text))
        expected = [x for a in data["answers"] for x in flatten(v["answers"][a]["value"])]
        assert len(found) == len(expected) == 4 + 4 + 4 + 2 + 2 + 1 + 1 + 2
        for (weight, _, value, tol), want in zip(found, expected):
            assert weight == "1"
            assert float(value) == want
            assert math.isclose(float(tol), tolerance * abs(want), rel_tol=1e-15, abs_tol=0)
        statement = text.text.split("<table")[0]
        assert f"{v['varied']['k']:g} N/m" in statement
        feedback = q.find("generalfeedback")
        assert feedback is not None and feedback.get("format") == "html"
        body = feedback.find("text")
        assert body is not None and "stationary solution" in (body.text or "")
        assert q.find("penalty") is not None and q.find("idnumber") is not None
    assert len(names) == N
    raw = (runs["a"] / "moodle.xml").read_text(encoding="utf-8")
    assert raw.count("<![CDATA[") >= 2 * N


def test_moodle_escapes_model_text(tmp_path: Path) -> None:
    text = MODEL.read_text(encoding="utf-8").replace(
        'title = "Cart with pendulum under force and support excitation"',
        'title = "Cart <b>&</b> ]]> {1:NUMERICAL:=1:0}"').replace(
        "Use x1 (cart)", "Use <script>x</script> ]]> {{1:NUMERICAL:=1:0}} x1 (cart)")
    model = tmp_path / "m.toml"
    model.write_text(text, encoding="utf-8")
    status, _, err = run_cli(["exercise", model, "--variants", 2, "--seed", 5, "-o",
                              tmp_path / "out", "--format", "moodle,html", "--no-plots"])
    assert status == 0, err
    root = ET.parse(tmp_path / "out" / "moodle.xml").getroot()
    q = root.findall("question")[1]
    body = q.find("questiontext/text").text  # type: ignore[union-attr]
    assert "<script>" not in body and "&lt;script&gt;" in body
    assert len(CLOZE.findall(body)) == 20  # the injected one is not a sub-question
    assert "<script>" not in (tmp_path / "out" / "1" / "statement.html").read_text()


def test_moodle_with_figures(tmp_path: Path) -> None:
    exercise(tmp_path / "p", "--format", "moodle", count=2)
    root = ET.parse(tmp_path / "p" / "moodle.xml").getroot()
    q = root.findall("question")[1]
    files_ = q.findall("generalfeedback/file")
    assert files_ and all(f.get("encoding") == "base64" for f in files_)
    text = q.find("generalfeedback/text").text  # type: ignore[union-attr]
    assert "@@PLUGINFILE@@/" + files_[0].get("name", "") in text


def test_plots_are_reproducible(tmp_path: Path) -> None:
    exercise(tmp_path / "a", "--format", "html,md", count=2, seed=7)
    exercise(tmp_path / "b", "--format", "html,md", count=2, seed=7)
    a, b = files(tmp_path / "a"), files(tmp_path / "b")
    assert a == b
    assert any(name.endswith(".svg") for name in a)


# -- grading ---------------------------------------------------------------------------------

def test_grade(runs: dict[str, Path], tmp_path: Path) -> None:
    variant = key(runs["a"])["variants"][4]
    answers = {name: a["value"] for name, a in variant["answers"].items()}
    right = tmp_path / "right.json"
    right.write_text(json.dumps(answers))
    status, out, _ = run_cli(["grade", runs["a"] / "key.json", "--variant", 5, right, "--json"])
    assert status == 0
    result = json.loads(out)
    assert result["score"] == 100 and result["right"] == len(answers)
    answers["amplitude:x2"] *= 1.05
    wrong = tmp_path / "wrong.json"
    wrong.write_text(json.dumps(answers))
    status, out, _ = run_cli(["grade", runs["a"] / "key.json", "--variant", 5, wrong, "--json"])
    result = json.loads(out)
    marked = [r["answer"] for r in result["answers"] if r["status"] != "right"]
    assert marked == ["amplitude:x2"]
    entry = next(r for r in result["answers"] if r["answer"] == "amplitude:x2")
    assert math.isclose(entry["relative_error"], 0.05, rel_tol=1e-9)
    status, text, _ = run_cli(["grade", runs["a"] / "key.json", "--variant", 5, wrong])
    assert status == 0 and "amplitude:x2" in text and "wrong" in text


def test_grade_matrix_entry_by_entry_and_missing(runs: dict[str, Path], tmp_path: Path) -> None:
    variant = key(runs["a"])["variants"][0]
    answers = {name: a["value"] for name, a in variant["answers"].items()}
    answers["M"][1][0] *= 1.1
    del answers["C"]
    path = tmp_path / "a.json"
    path.write_text(json.dumps(answers))
    status, out, _ = run_cli(["grade", runs["a"] / "key.json", "--variant", 1, path, "--json"])
    result = json.loads(out)
    by = {r["answer"]: r for r in result["answers"]}
    assert by["C"]["status"] == "missing"
    assert by["M"]["status"] == "wrong" and by["M"]["score"] == 0.75
    assert [w["entry"] for w in by["M"]["wrong_entries"]] == ["[2,1]"]
    assert result["score"] < 100


@pytest.mark.parametrize("content", [
    "not json", "[1, 2]", '{"M": "three"}', '{"M": [[1, 2], [3]]}', '{"amplitude:x2": NaN}',
    '{"M": true}', "[" * 100000])
def test_grade_untrusted_answers(runs: dict[str, Path], tmp_path: Path, content: str) -> None:
    path = tmp_path / "bad.json"
    path.write_text(content)
    status, out, err = run_cli(["grade", runs["a"] / "key.json", "--variant", 1, path])
    assert status in (0, 2), err
    assert "Traceback" not in err and "internal error" not in err
    if status == 0:  # a malformed answer is graded wrong, never crashes
        assert "wrong" in out


def test_grade_bad_key_and_variant(runs: dict[str, Path], tmp_path: Path) -> None:
    answers = tmp_path / "a.json"
    answers.write_text("{}")
    for bad in ("{}", '{"format": "resonant-exercise-key", "variants": 3}', "x"):
        path = tmp_path / "key.json"
        path.write_text(bad)
        status, _, err = run_cli(["grade", path, "--variant", 1, answers])
        assert status == 2 and err.startswith("error:"), err
    status, _, err = run_cli(["grade", runs["a"] / "key.json", "--variant", 99, answers])
    assert status == 2 and "no variant 99" in err
    big = tmp_path / "big.json"
    big.write_bytes(b" " * 3_000_000)
    status, _, err = run_cli(["grade", runs["a"] / "key.json", "--variant", 1, big])
    assert status == 2 and "larger than" in err


# -- validation of the sections ---------------------------------------------------------------

BASE = MODEL.read_text(encoding="utf-8")


@pytest.mark.parametrize(("old", "new", "where"), [
    ("m1 = [1, 1.5, 2, 2.5, 3]", "mass = [1, 2]", "[variants] mass"),
    ("m1 = [1, 1.5, 2, 2.5, 3]", "m1 = []", "[variants] m1"),
    ("step = 10 }", "step = 0 }", "[variants] k"),
    ("step = 10 }", "step = -1 }", "[variants] k"),
    ('"natural_frequencies"]', '"natural_frequencies", "amplitude:zz"]', "[exercise] answers[8]"),
    ('"natural_frequencies"]', '"natural_frequencies", "energy"]', "[exercise] answers[8]"),
    ("mass m1 = {m1}", "mass m1 = {m3}", "[exercise] statement"),
    ("tolerance = 0.01", "tolerance = 2", "[exercise] tolerance"),
    ("m1 = [1, 1.5, 2, 2.5, 3]", 'm1 = "heavy"', "[variants] m1"),
])
def test_validation(tmp_path: Path, old: str, new: str, where: str) -> None:
    assert old in BASE
    path = tmp_path / "m.toml"
    path.write_text(BASE.replace(old, new, 1), encoding="utf-8")
    status, _, err = run_cli(["check", path])
    assert status == 2, err
    assert str(path) in err and where in err, err


def test_exercise_needs_the_section(tmp_path: Path) -> None:
    status, _, err = run_cli(["exercise", EXAMPLES / "cart_pendulum.toml", "--variants", 2,
                              "-o", tmp_path / "x"])
    assert status == 2 and "[exercise]" in err
    status, _, err = run_cli(["exercise", MODEL, "--variants", 2, "-o", tmp_path / "y",
                              "--format", "pdf"])
    assert status == 2 and "unknown format" in err
    status, _, err = run_cli(["exercise", MODEL, "--variants", 10 ** 6, "-o", tmp_path / "z"])
    assert status == 2


def test_too_few_value_sets(tmp_path: Path) -> None:
    text = re.sub(r"\[variants\].*", "[variants]\nm1 = [1, 2]\n", BASE, flags=re.S)
    path = tmp_path / "m.toml"
    path.write_text(text, encoding="utf-8")
    status, _, err = run_cli(["exercise", path, "--variants", 3, "-o", tmp_path / "x"])
    assert status == 2 and "only 2 distinct value sets" in err
