"""kcheck's promise under fuzzing (issues 13 and 25): 295 generated inputs of every kind in
the normal run (a handful of kcheck processes: two mixed batches of about 150 scenes, a small
one, every report format, plus some command lines; about 30 s), and with ``pytest --fuzz-long
N`` a campaign of N inputs (docs/robustness.md). Every kcheck process runs with ``-W error``.

The seed of the normal run is fixed (``--fuzz-seed`` changes it), so the suite is the same
every time; every problem names its input (``kind-seed-index``), which
``python -m tests.fuzz.campaign --only kind-seed-index --keep DIR`` lays out and runs again.
The oracle itself is tested first: it must catch each broken promise it looks for.
"""

from __future__ import annotations

import sys
import time

import pytest

from tests.fuzz.baseline import baseline
from tests.fuzz.campaign import GENERATORS, SHARES, plan, run_campaign, summary
from tests.fuzz.contract import judge_number_field
from tests.fuzz.harness import Harness, Problem, Run, claim_matches, judge_cli, run_process
from tests.fuzz.model import Case, Expect, invalid
from tests.fuzz.mutate import fixture_copy, valid_case
from tests.fuzz.scenes import fixtures

SEED = 13
#: Inputs of the normal run, per kind (scene kinds batched; cli one process each).
NORMAL = {
    "mutation": 90,
    "extreme": 45,
    "yaml": 35,
    "fs": 20,
    "mesh": 25,
    "cli": 10,
    "v2": 25,
    "v2mutation": 45,
}
#: Further reports of the normal run's batches (two large batches, then a small one of the
#: inputs that need an unprivileged process): every format is written and read back. The
#: HTML page draws every scene's pictures (about a second each), so only the small batch
#: has one here; the campaign draws them for every fourth batch.
REPORTS = (
    {"r.sarif": "sarif", "r.xml": "junit", "r.md": "markdown"},
    {"r.text": "text", "r.txt": "github", "r.c": "concise"},
    {"r.html": "html"},
)
#: Per input, in the suite, s: a hang, not a speed test (the suite may share a loaded
#: machine; the campaign keeps INPUT_TIME_LIMIT_S).
SUITE_TIME_LIMIT_S = 30.0


@pytest.fixture
def seed(request: pytest.FixtureRequest) -> int:
    chosen = request.config.getoption("--fuzz-seed")
    return SEED if chosen is None else chosen


def _report(problems: list[Problem]) -> str:
    lines = [f"{len(problems)} problem(s); regenerate one with"]
    lines.append("  python -m tests.fuzz.campaign --only <input> --keep DIR")
    lines += [f"{p.klass}: {p.case}: {p.detail[:400]}" for p in problems[:30]]
    return "\n".join(lines)


# --- the oracle catches what it looks for -----------------------------------------------------


def test_the_contract_judges_numbers_from_the_documented_ranges():
    data = {"units": "mm", "load": {"magnitude": 5e-7}, "supports": [{"normal": [0, 0, 0]}]}
    assert judge_number_field(data, ("load", "magnitude")).outcome == "invalid"  # < 1 µN
    data["load"]["magnitude"] = 0.0
    assert judge_number_field(data, ("load", "magnitude")).outcome == "any"  # no load
    assert judge_number_field(data, ("supports", 0, "normal", 1)).claims[0].field == (
        "supports[0].normal"
    )
    data = {"units": "mm", "supports": [{"position": [1e6, 0, 0]}]}  # exactly 1000 m: the edge
    assert judge_number_field(data, ("supports", 0, "position", 0)).outcome == "any"
    data["supports"][0]["position"][0] = 1.1e6
    assert judge_number_field(data, ("supports", 0, "position", 0)).outcome == "invalid"
    inertia = [[1.0, 0.5, 0], [0.0, 1.0, 0], [0, 0, 1.0]]  # not symmetric
    assert judge_number_field({"body": {"inertia": inertia}}, ("body", "inertia", 0, 1)).claims


def test_an_error_matches_a_claim_at_its_field_or_the_field_holding_it():
    assert claim_matches("gravity[1]", "gravity")
    assert claim_matches("supports[2].normal", "supports[2].normal[0]")
    assert not claim_matches("supports[2].normal", "supports[2]")
    assert not claim_matches("load.magnitude", "load.angle")
    assert claim_matches(None, None)


def test_the_harness_catches_broken_promises(tmp_path):
    # Mislabelled on purpose: a valid fixture claimed invalid, a broken file claimed valid, a
    # fixture claimed to have another fixture's verdict. Each must be reported.
    fx = fixtures()[0]
    failing = next(f for f in fixtures() if baseline()[f.name][0] == "fail")
    lies = [
        Case("lie", 0, 0, "valid, claimed invalid", {**fx.files, fx.scene: fx.text.encode()},
             (fx.scene,), {fx.scene: invalid("friction", "a lie")}),
        Case("lie", 0, 1, "broken, claimed valid", {"s.kcheck.yaml": b"version: ["},
             ("s.kcheck.yaml",), {"s.kcheck.yaml": Expect("valid", baseline=fx.name)}),
        Case("lie", 0, 2, "another verdict", {**fx.files, fx.scene: fx.text.encode()},
             (fx.scene,), {fx.scene: Expect("valid", baseline=failing.name)}),
        Case("lie", 0, 3, "lost", {}, (), {"nothing.kcheck.yaml": Expect("any")}),
    ]  # fmt: skip
    harness = Harness(tmp_path, baseline())
    found = {(p.klass, p.case) for p in harness.run_batch(lies)}
    assert found == {
        ("accepted-invalid", "lie-0-0"),
        ("rejected-valid", "lie-0-1"),
        ("wrong-verdict", "lie-0-2"),
        ("lost-scene", "lie-0-3"),
    }


def test_the_process_judge_catches_tracebacks_warnings_and_exit_codes():
    case = Case("cli", 0, 0, "x", argv=("check",), exit_codes=frozenset({2}))
    traceback = "Traceback (most recent call last):\n  File ...\nValueError: x\n"
    run = Run(1, "", traceback, 0.5, 100.0, [])
    classes = {p.klass for p in judge_cli(case, run)}
    assert {"traceback", "wrong-exit", "stray-output"} <= classes
    warning = "/x/y.py:3: RuntimeWarning: overflow encountered in square\n"
    run = Run(2, "", warning + "kcheck: error: bad\n", 0.5, 600.0, [])
    assert {p.klass for p in judge_cli(case, run)} == {"stray-output", "memory"}
    assert judge_cli(case, Run(2, "", "kcheck: error: bad\n", 0.5, 100.0, [])) == []
    assert [p.klass for p in judge_cli(case, Run(None, "", "", 61.0, 100.0, []))] == ["hang"]


def test_peak_memory_is_the_commands_own(tmp_path):
    # A fuzzer holding much memory must not lend it to its children: Linux counts a child's
    # resident set before its exec (the fuzzer's pages) in the child's maximum. The campaign
    # runner held 800 MB of inputs and judged every kcheck run as "peak 813 MB".
    held = bytearray(300 << 20)
    held[::4096] = b"\x01" * len(held[::4096])  # touched: resident
    small = run_process([sys.executable, "-c", "pass"], tmp_path, deadline_s=30)
    big = run_process(
        [sys.executable, "-c", "b = bytearray(200 << 20); b[::4096] = b'x' * len(b[::4096])"],
        tmp_path,
        deadline_s=30,
    )
    del held
    assert small.code == 0 and small.peak_mb < 100
    assert big.code == 0 and 200 < big.peak_mb < 300
    sleeper = [sys.executable, "-c", "import time; time.sleep(30)"]
    killed = run_process(sleeper, tmp_path, deadline_s=0.5)
    assert killed.code is None and killed.wall_s < 10


# --- the promise ----------------------------------------------------------------------------


@pytest.mark.slow
def test_fuzzed_inputs_keep_the_promise(tmp_path, seed):
    """Every kind of input, mixed batches of valid and invalid scenes, every command line:
    exit codes, located messages, no traceback, no check crash, no internal error, no lost
    scene, no stray output, bounded time and memory."""
    harness = Harness(tmp_path, baseline(), time_limit_s=SUITE_TIME_LIMIT_S)
    started = time.monotonic()
    run_campaign(harness, seed, NORMAL, batch_size=150, log=lambda _: None, reports=REPORTS)
    numbers = summary(harness, time.monotonic() - started, seed)
    assert not harness.problems, _report(harness.problems)
    for kind, n in NORMAL.items():
        assert numbers["inputs"][kind] == n  # every input was judged
    # Both outcomes occur among the scene kinds: the inputs are not all trivially rejected.
    assert numbers["accepted"]["mutation"] > 10 and numbers["rejected"]["mutation"] > 50
    assert numbers["rejected"]["yaml"] > 25 and numbers["rejected"]["mesh"] > 15
    # Generated designs of today's format are valid: every one gets a verdict; mutated, both.
    assert numbers["accepted"]["v2"] == NORMAL["v2"]
    assert numbers["accepted"]["v2mutation"] > 5 and numbers["rejected"]["v2mutation"] > 20
    # Errors were checked to sit at real fields of the format (the harness's `unreal-field`).
    real = numbers["errors at real fields"]
    assert real.get("mutation", 0) > 30 and real.get("v2mutation", 0) > 20, real


def test_a_batch_of_valid_rewrites_keeps_every_fixture_verdict(tmp_path, seed):
    """Rewritten fixtures (key order, style, comments, aliases, encodings, names, order of
    supports, direction lengths, units) in one batch: each the fixture's own verdict."""
    batch = [fixture_copy(f.name, i, seed) for i, f in enumerate(fixtures())]
    batch += [valid_case(seed, i) for i in range(20)]
    harness = Harness(tmp_path, baseline(), time_limit_s=SUITE_TIME_LIMIT_S)
    assert harness.run_batch(batch) == []
    assert harness.stats.accepted["valid"] == 20


def test_long_campaign(tmp_path, request):
    """``pytest tests/fuzz --fuzz-long 10000``: the issue's campaign (one core; about an
    hour), then one batch of 1000 valid rewrites."""
    total = request.config.getoption("--fuzz-long")
    if not total:
        pytest.skip("give --fuzz-long N to run a campaign of N inputs")
    chosen = request.config.getoption("--fuzz-seed")
    seed = chosen if chosen is not None else int(time.time()) % 100_000
    print(f"\nfuzz campaign: seed {seed}, {total} inputs")
    harness = Harness(tmp_path, baseline())
    run_campaign(harness, seed, plan(seed, total, SHARES), log=print)
    batch = [valid_case(seed, i) for i in range(1000)]
    harness.run_batch(batch)
    assert not harness.problems, _report(harness.problems)


def test_every_kind_regenerates_identically():
    for kind, generate in GENERATORS.items():
        a, b = generate(7, 3), generate(7, 3)
        assert (a.what, a.files, a.targets, a.argv) == (b.what, b.files, b.targets, b.argv), kind


# --- today's format (issue 25) ----------------------------------------------------------------


def test_generated_designs_use_every_feature_of_the_format():
    """200 designs hold every shorthand (on the body and on the base), explicit supports,
    friction in every form and at every level, preloads, tolerances, meshes, parts in their
    own units with every kind of transform, point masses, explicit mass properties (a planar
    I_zz alone too), a sweep plane, torques and every length unit."""
    from tests.fuzz.scenes import walk
    from tests.fuzz.schema import in_schema
    from tests.fuzz.v2 import v2_design

    seen: set[str] = set()
    for i in range(200):
        data, files = v2_design(SEED, i)
        for path, value in walk(data):
            assert in_schema(path, data), path  # every field it writes is a real one
            names = [p for p in path if isinstance(p, str)]
            if path[-1:] == ("type",):
                seen.add(value)
            if path[-1:] == ("ball_on",):
                seen.add(f"ball_on {value}")
            if names[-1:] == ["friction"] or names[-2:-1] == ["friction"]:
                where = names[0] if names[0] in ("supports", "couplings") else "scene"
                form = (
                    "number"
                    if not isinstance(value, dict)
                    else "pair"
                    if "static" in value
                    else "range"
                )
                if names[-1] == "friction":
                    seen.add(f"friction {form} in {where}")
                if names[-1] in ("static", "kinetic") and isinstance(value, dict):
                    seen.add("a pair of ranges")
            if path[-1:] == ("rotate",):
                seen.add("rotate matrix" if isinstance(value, list) else "rotate axis-angle")
            if path[-1:] in (("translate",), ("torque",), ("sweep",), ("point_masses",)):
                seen.add(path[-1])
            if path[-2:-1] == ("tolerances",):
                seen.add(f"tolerances.{path[-1]}")
        body = data["body"]
        seen.add(f"units {data['units']}")
        seen.update(
            k for k in ("mesh", "parts", "mass", "preloads", "supports") if k in body or k in data
        )
        if isinstance(body.get("inertia"), (int, float)):
            seen.add("I_zz alone")
        if any("units" in p for p in body.get("parts", [])):
            seen.add("a part in its own unit")
        assert data["body"] and files or "mass" in body
    wanted = {
        "ball-vee", "ball-cylinders", "ball-sphere", "ball-trihedral", "ball-cone", "ball-flat",
        "ball_on base", "ball_on body", "supports",
        "friction number in scene", "friction range in scene", "friction pair in scene",
        "friction number in supports", "friction range in couplings", "friction pair in couplings",
        "a pair of ranges", "preloads", "tolerances.position", "tolerances.normal",
        "tolerances.load_direction", "mesh", "parts", "rotate matrix", "rotate axis-angle",
        "translate", "a part in its own unit", "point_masses", "mass", "I_zz alone", "sweep",
        "torque", "units m", "units cm", "units mm", "units um", "units in",
    }  # fmt: skip
    assert wanted <= seen, sorted(wanted - seen)


def test_an_error_at_a_field_the_format_has_not_is_caught():
    from tests.fuzz.harness import _unreal

    vee = {"couplings": [{"type": "ball-vee", "groove": {"up": [0, 0, 1]}}]}
    assert _unreal({"field": "couplings[0].up", "message": "parallel"}, vee)
    assert _unreal({"field": "couplings[0].groove.up", "message": "parallel"}, vee) is None
    assert _unreal({"field": "couplings[0].up", "message": "unknown field"}, vee) is None
    assert _unreal({"field": "couplings[0].groove", "message": "unknown field"}, vee)
    assert _unreal({"field": "checks.maxwell.nope", "message": "unknown field"}, vee) is None
