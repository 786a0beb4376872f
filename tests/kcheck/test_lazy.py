"""Lean start-up: heavy modules are imported only where a scene needs them."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

from tests.conftest import PLANAR_SCENE

HEAVY = ("trimesh", "scipy", "matplotlib", "clarabel", "mujoco")

# Scenes run in this process (no worker), so the modules they import are seen here.
PROBE = """
import json, sys
import kcheck.gate.pool
kcheck.gate.pool.available = lambda: False
from kcheck.cli import main
code = main(sys.argv[1:])
heavy = sorted(m for m in HEAVY if m in sys.modules)
print(json.dumps({"code": code, "heavy": heavy}), file=sys.stderr)
"""


def _imported(*args: str) -> dict:
    proc = subprocess.run(
        [sys.executable, "-c", f"HEAVY = {HEAVY!r}\n{PROBE}", *args],
        capture_output=True,
        text=True,
    )
    return json.loads(proc.stderr.strip().splitlines()[-1])


def test_schema_and_plugins_import_nothing_heavy():
    assert _imported("schema")["heavy"] == []
    assert _imported("plugins")["heavy"] == []


def test_geometry_only_scene_reads_no_mesh(write_scene, tmp_path):
    # No body: the analytical checks are skipped, maxwell needs geometry only, and the mesh
    # library is never imported.
    text = PLANAR_SCENE.replace(
        "body:\n  mass: 1\n  center_of_mass: [50, 30, 0]\n  inertia: 0.001\n", ""
    )
    result = _imported("check", str(write_scene(text)), "--format", "json")
    assert result == {"code": 0, "heavy": []}


def test_explicit_mass_needs_no_mesh_library(write_scene):
    # Explicit mass properties and no design direction: no trimesh (no mesh), no scipy
    # (the limiting friction is only computed at a design direction).
    text = PLANAR_SCENE.replace("  angle: 225\n", "")
    assert _imported("check", str(write_scene(text)), "--format", "json")["heavy"] == []


def test_mesh_scene_imports_trimesh_but_not_matplotlib(tmp_path):
    from tests.conftest import FIXTURES

    scene = FIXTURES / "planar-block" / "block.kcheck.yaml"
    heavy = _imported("check", str(scene), "--format", "json")["heavy"]
    assert "trimesh" in heavy and "matplotlib" not in heavy


def test_conic_solver_only_for_spatial_jamming():
    from tests.conftest import FIXTURES

    planar = _imported("check", str(FIXTURES / "planar-block" / "block.kcheck.yaml"))["heavy"]
    assert "clarabel" not in planar
    spatial = _imported("check", str(FIXTURES / "three-groove" / "coupling.kcheck.yaml"))["heavy"]
    assert "clarabel" in spatial


MODULES_PROBE = """
import json, sys
import kcheck.gate.pool
kcheck.gate.pool.available = lambda: False
from kcheck.cli import main
code = main(sys.argv[1:])
print(json.dumps({"code": code, "modules": sorted(sys.modules)}), file=sys.stderr)
"""


def test_json_run_on_a_planar_scene_imports_only_what_it_needs(write_scene):
    # A planar scene with explicit mass properties and no design direction, reported as JSON:
    # no terminal machinery (rich), no other report format, no mesh library, no solver, no
    # plotting, no process pools, no git. (scipy: only at a design direction, for now.)
    text = PLANAR_SCENE.replace("  angle: 225\n", "")
    proc = subprocess.run(
        [sys.executable, "-c", MODULES_PROBE, "check", str(write_scene(text)), "--format", "json"],
        capture_output=True,
        text=True,
    )
    result = json.loads(proc.stderr.strip().splitlines()[-1])
    assert result["code"] == 0
    modules = set(result["modules"])
    unwanted = {
        "rich",
        "trimesh",
        "scipy",
        "matplotlib",
        "networkx",
        "PIL",
        "multiprocessing",
        "concurrent.futures",
        "xml.etree",
        "kcheck.report.text",
        "kcheck.report.junit",
        "kcheck.report.sarif",
        "kcheck.report.markdown",
        "kcheck.gate.vcs",
        "kcheck.report.github",
        "numpy.ma",  # np.unique imports it; kcheck.numerics.arrays does without
        "numpy.polynomial",  # friction ranges only
        # entry points and versions are read without importlib.metadata (kcheck.plugin.dist_info;
        # pydantic's plugin loader is skipped while its plugins are disabled)
        "importlib.metadata",
        "email",
        "zipfile",
        # "did you mean" for a misspelt key only (issue 24)
        "difflib",
        # spatial and Hertz computations: their checks do not apply to a planar scene
        "kcheck.mechanics.sphere",
        "kcheck.mechanics.caps",
        "kcheck.analysis.sphere_map",
        "kcheck.mechanics.tolerance",
        "kcheck.numerics.stats",
        "kcheck.mechanics.hertz",
        "kcheck.mechanics.seat",
        # an opt-in check's simulation, the plotting module (pictures only with --plots)
        "kcheck.analysis.reseat",
        "kcheck.pictures.plotting",
        # scene fields and check options are read without pydantic (issue 24)
        "kcheck.scene.models",
        # the mesh reader: explicit mass properties read no mesh (issue 24)
        "kcheck.body.meshio",
        "kcheck.body.mesh_edges",
        # the report's shared views: a JSON report of a scene without input errors needs none
        "kcheck.report.views",
        # the default cache folder on Linux is platformdirs' answer without importing it
        "platformdirs",
        # argparse asks for the terminal's width only to print help or usage (issue 24)
        "shutil",
        "bz2",
        "lzma",
        # the other commands' modules: only the command asked for is built (issue 24)
        "kcheck.cli.init",
        "kcheck.cli.contacts",
        "kcheck.cli.expand",
        "kcheck.cli.mass",
        "kcheck.cli.suggest",
        "kcheck.cli.suggest_report",
        "kcheck.cli.study",
        "kcheck.cli.info",
    }
    assert modules & unwanted == set()
    assert {"kcheck.report.json", "kcheck.gate.runner", "kcheck.gate.cache"} <= modules


def test_planar_scene_without_mesh_imports_no_heavy_library(write_scene):
    # Issue 24: checking a planar scene without a mesh (explicit mass properties, a design
    # direction) imports none of scipy, trimesh, matplotlib, clarabel.
    result = _imported("check", str(write_scene(PLANAR_SCENE)), "--format", "json")
    assert result["heavy"] == []


def test_planar_scene_without_mesh_imports_no_pydantic(write_scene):
    # Issue 24: a valid scene is read by kcheck.scene.accept and checks' default options are
    # built without pydantic (kcheck.plugin.options); pydantic only for a mistake or options.
    proc = subprocess.run(
        [sys.executable, "-c", MODULES_PROBE, "check", str(write_scene(PLANAR_SCENE))]
        + ["--format", "json"],
        capture_output=True,
        text=True,
    )
    modules = set(json.loads(proc.stderr.strip().splitlines()[-1])["modules"])
    assert {"pydantic", "pydantic_core"} & modules == set()


def test_dask_only_when_asked_for():
    """The Monte Carlo checks on their own, or with local sample workers: no Dask imported
    (it is behind the `dask` extra, imported only for --dask-local and --scheduler)."""
    from tests.conftest import FIXTURES

    scene = str(FIXTURES / "three-groove" / "coupling.kcheck.yaml")
    for extra in ([], ["--sample-jobs", "2"]):
        proc = subprocess.run(
            [sys.executable, "-c", MODULES_PROBE, "check", scene, "--select", "tolerances"]
            + ["--format", "json", *extra],
            capture_output=True,
            text=True,
        )
        result = json.loads(proc.stderr.strip().splitlines()[-1])
        assert result["code"] == 0
        modules = set(result["modules"])
        assert "kcheck.mechanics.tolerance" in modules
        assert modules & {"dask", "distributed", "kcheck.gate.samples"} == (
            {"kcheck.gate.samples"} if extra else set()
        )


def test_contacts_on_binary_stls_imports_no_trimesh(tmp_path):
    # `kcheck contacts` reads binary STLs itself (meshio.load_surface): no trimesh import.
    import trimesh

    base = trimesh.creation.box(extents=(20, 20, 4)).apply_translation([0, 0, -2])
    body = trimesh.creation.box(extents=(10, 10, 4)).apply_translation([0, 0, 2])
    base.export(tmp_path / "base.stl")
    body.export(tmp_path / "body.stl")
    paths = [str(tmp_path / "base.stl"), str(tmp_path / "body.stl")]
    result = _imported("contacts", *paths, "--units", "mm")
    # An area contact: found (exit 1, no scene), with scipy and without trimesh.
    assert result == {"code": 1, "heavy": ["scipy"]}


def _commands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    """The command parsers of a parser's subcommand action, by name."""
    (action,) = (a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def test_one_command_parser_reads_as_the_full_one():
    # Issue 24: `kcheck CMD ...` builds only CMD's parser; its usage line, and so every usage
    # error, is the one the parser of every command prints.
    import kcheck.cli as cli

    full = cli._parser()
    assert list(_commands(full)) == list(cli.COMMANDS)
    for name in cli.COMMANDS:
        one = cli._parser(name)
        assert one.format_usage() == full.format_usage()
        assert _commands(one)[name].format_help() == _commands(full)[name].format_help()


def test_check_restores_the_collector(write_scene, capsys):
    # Issue 24: `kcheck check` runs its start-up without the garbage collector and freezes
    # what start-up made before the scenes run (gc.freeze); called in-process, it leaves the
    # collector as it found it: on and nothing frozen, or the caller's own state.
    import gc

    from kcheck.cli import main

    scene = str(write_scene(PLANAR_SCENE))
    assert gc.isenabled() and gc.get_freeze_count() == 0
    assert main(["check", scene, "--format", "json", "--jobs", "1"]) == 0
    assert gc.isenabled() and gc.get_freeze_count() == 0
    gc.disable()
    gc.freeze()
    try:
        frozen = gc.get_freeze_count()
        assert main(["check", scene, "--format", "json", "--jobs", "1"]) == 0
        # still frozen (a frozen object that dies leaves the count, nothing else does)
        assert not gc.isenabled() and 0.99 * frozen < gc.get_freeze_count() <= frozen
    finally:
        gc.unfreeze()
        gc.enable()
    capsys.readouterr()


COMPILED_PROBE = """
import json, sys
import kcheck.gate.pool
kcheck.gate.pool.available = lambda: False
from kcheck.cli import main
code = main(sys.argv[1:])
import yaml
from kcheck.records import _FirstInit
classes = {
    "kcheck.result.CheckResult": sys.modules["kcheck.result"].CheckResult,
    "kcheck.mechanics.csc.Csc": sys.modules["kcheck.mechanics.csc"].Csc,
}
print(json.dumps({
    "code": code,
    "reader pattern": type(yaml.reader.Reader.NON_PRINTABLE).__name__,
    "libyaml": yaml.__with_libyaml__,
    "written": {k: not isinstance(c.__dict__["__init__"], _FirstInit) for k, c in classes.items()},
}), file=sys.stderr)
"""


def test_a_planar_run_compiles_only_what_it_uses(write_scene):
    # Issue 24: PyYAML's pure-Python reader's pattern is not compiled (kcheck reads through
    # libyaml), and a dataclass's __init__ is written at its first instance only
    # (kcheck.records): results are made, the conic solver's matrices (spatial jamming) not.
    proc = subprocess.run(
        [sys.executable, "-c", COMPILED_PROBE, "check", str(write_scene(PLANAR_SCENE))]
        + ["--format", "json"],
        capture_output=True,
        text=True,
    )
    result = json.loads(proc.stderr.strip().splitlines()[-1])
    assert result["code"] == 0
    assert result["reader pattern"] == ("_OnFirstUse" if result["libyaml"] else "Pattern")
    assert result["written"] == {
        "kcheck.result.CheckResult": True,
        "kcheck.mechanics.csc.Csc": False,
    }
