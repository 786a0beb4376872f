"""Every numerical threshold is a named constant in one place (kcheck.numerics.thresholds),
and each says what it bounds, in which units and why (issue 20).

The source is read, not imported, where the claim is about the source: which modules compute
machine epsilon, define a threshold again instead of importing it, or import the module.
"""

from __future__ import annotations

import ast
import importlib
import io
import tokenize
from pathlib import Path

import numpy as np
import pytest

from kcheck.numerics import thresholds
from tests.conftest import ROOT

THRESHOLDS = ROOT / "kcheck" / "numerics" / "thresholds.py"
SOURCES = sorted(
    p for d in ("kcheck", "plugins") for p in (ROOT / d).rglob("*.py") if p != THRESHOLDS
)
# Words that say in which units a threshold is, or that it has none.
UNIT_WORDS = ("nondimensional", "(rad)", "(deg)", "(m)", "(m/s)", "(any unit)")


def _tree(path: Path) -> ast.Module:
    return ast.parse(path.read_text(encoding="utf-8"), filename=str(path))


def _machine_constants(tree: ast.AST) -> list[int]:
    """Lines that compute a machine constant: ``finfo(...).eps`` or ``.tiny`` (numpy), or
    ``sys.float_info.epsilon`` or ``.min``."""
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Attribute):
            continue
        inner = node.value
        if node.attr in ("eps", "tiny") and isinstance(inner, ast.Call):
            func = inner.func
            name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            if name == "finfo":
                found.append(node.lineno)
        if node.attr in ("epsilon", "min") and (
            isinstance(inner, ast.Attribute) and inner.attr == "float_info"
        ):
            found.append(node.lineno)
    return sorted(found)


def _public_assignments(tree: ast.Module) -> dict[str, int]:
    """Module-level ``NAME = ...`` / ``NAME: type = ...`` with an upper-case name: line."""
    out = {}
    for node in tree.body:
        targets = (
            node.targets
            if isinstance(node, ast.Assign)
            else [node.target]
            if isinstance(node, ast.AnnAssign)
            else []
        )
        for t in targets:
            if isinstance(t, ast.Name) and t.id.isupper() and not t.id.startswith("_"):
                out[t.id] = node.lineno
    return out


def _doc_comments() -> dict[int, str]:
    """The ``#:`` comment block ending on the line above each line of thresholds.py."""
    lines: dict[int, str] = {}
    source = THRESHOLDS.read_text(encoding="utf-8")
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.COMMENT and tok.string.startswith("#:"):
            lines[tok.start[0]] = tok.string[2:].strip()
    blocks: dict[int, str] = {}
    for line in sorted(lines):
        if line + 1 not in lines:  # last line of a block: it documents line + 1
            start = line
            while start - 1 in lines:
                start -= 1
            blocks[line + 1] = " ".join(lines[k] for k in range(start, line + 1))
    return blocks


def test_the_detector_finds_machine_constants() -> None:
    sample = (
        "import sys\nimport numpy as np\n"
        "a = float(np.finfo(float).eps)\nb = np.finfo(np.float64).tiny\n"
        "c = sys.float_info.epsilon\nd = np.finfo(float).max\n"
    )
    assert _machine_constants(ast.parse(sample)) == [3, 4, 5]


def test_only_thresholds_computes_machine_epsilon() -> None:
    assert len(SOURCES) > 50  # the scan sees the code base
    offenders = {
        str(p.relative_to(ROOT)): lines for p in SOURCES if (lines := _machine_constants(_tree(p)))
    }
    assert offenders == {}, "import EPS or TINY from kcheck.numerics.thresholds instead"
    assert _machine_constants(_tree(THRESHOLDS))  # ... which does compute them


def test_machine_constants_are_numpys() -> None:
    assert thresholds.EPS == float(np.finfo(float).eps) == 2.0**-52
    assert thresholds.TINY == float(np.finfo(float).tiny) == 2.0**-1022
    assert thresholds.ZERO_GUARD > thresholds.TINY  # a normal float: its reciprocal is finite
    assert np.isfinite(1.0 / thresholds.ZERO_GUARD)


def test_every_constant_is_listed_and_documented() -> None:
    assigned = _public_assignments(_tree(THRESHOLDS))
    assert sorted(assigned) == sorted(thresholds.__all__)
    docs = _doc_comments()
    for name, line in assigned.items():
        doc = docs.get(line, "")
        assert len(doc.split()) >= 12, f"{name}: a `#:` comment says what it bounds and why"
        assert any(word in doc for word in UNIT_WORDS), f"{name}: its comment names its units"
        value = getattr(thresholds, name)
        assert isinstance(value, (int, float)) and np.isfinite(value) and value > 0, name


def test_thresholds_imports_nothing_from_kcheck_nor_numpy() -> None:
    """The lowest layer: any module may import it, without numpy's import cost."""
    imported = set()
    for node in ast.walk(_tree(THRESHOLDS)):
        if isinstance(node, ast.Import):
            imported |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            imported.add((node.module or "").split(".")[0])
    assert imported <= {"__future__", "math", "sys"}


def _imports_from_thresholds() -> dict[str, set[str]]:
    users: dict[str, set[str]] = {}
    for p in SOURCES:
        for node in ast.walk(_tree(p)):
            if isinstance(node, ast.ImportFrom) and node.module == "kcheck.numerics.thresholds":
                for a in node.names:
                    users.setdefault(a.name, set()).add(str(p.relative_to(ROOT)))
    return users


def test_every_constant_is_used() -> None:
    """No dead thresholds: each is imported by some module of kcheck or the checks."""
    unused = sorted(set(thresholds.__all__) - set(_imports_from_thresholds()))
    assert unused == []


def test_no_module_defines_a_threshold_again() -> None:
    """A module that exports a threshold re-imports it; it does not assign its own copy."""
    names = set(thresholds.__all__)
    again = {
        f"{p.relative_to(ROOT)}:{line}": name
        for p in SOURCES
        for name, line in _public_assignments(_tree(p)).items()
        if name in names
    }
    assert again == {}


@pytest.mark.parametrize(
    ("module", "name"),
    [
        ("kcheck.mechanics.dynamics", "EPS"),
        ("kcheck.mechanics.dynamics", "TINY"),
        ("kcheck.mechanics.dynamics", "ILL_CONDITIONED"),
        ("kcheck.mechanics.dynamics", "SLIP_TOL"),
        ("kcheck.mechanics.dynamics", "UNDETERMINED"),
        ("kcheck.mechanics.kinematics", "RANK_RTOL"),
        ("kcheck.mechanics.cones", "FACET_TOL"),
        ("kcheck.mechanics.caps", "ON_BOUNDARY"),
        ("kcheck.mechanics.least_friction", "MU_FLOOR"),
        ("kcheck.analysis.jamming_cases", "UNDETERMINED"),
        ("kcheck.analysis.jamming_cases", "SLIVER"),
        ("kcheck.scene", "PLANAR_TOL"),
        ("kcheck.body.meshio", "MERGE_RTOL"),
        ("kcheck.body.mass", "MERGE_RTOL"),
        ("kcheck.fmt", "NOISE_RTOL"),
    ],
)
def test_names_other_code_imports_stay_importable(module: str, name: str) -> None:
    assert getattr(importlib.import_module(module), name) is getattr(thresholds, name)
