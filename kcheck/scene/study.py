"""Study files (``*.kcheck-study.yaml``): a base scene, parameters into it, a design.

A parameter names a dotted path into the scene file's data (``friction``, ``load.angle``,
``supports.x1.position``, ``couplings.*.groove.half_angle``): a mapping key, a list index,
the ``name`` of a list item, or ``*`` for every item of a list. Its levels are ``values``, a
``range`` (``[min, max]``, with ``steps`` on a grid) or a ``distribution`` (``uniform``,
``normal``, ``truncated-normal``). ``unit`` converts lengths (``m``, ``mm``, ...) to the
scene's ``units`` and ``rad`` to the degrees scene files write angles in.

Everything is checked before any variant runs, each error naming the study file, the field
and its line; a parameter whose levels leave the scene invalid is such an error too.
"""

from __future__ import annotations

import copy
import math
from dataclasses import field
from pathlib import Path
from typing import Any

import numpy as np

from kcheck.errors import FieldPath, SceneError
from kcheck.numerics.design import DESIGNS, grid_indices, quantiles, unit_points
from kcheck.records import dataclass
from kcheck.scene.units import LENGTH_TO_M
from kcheck.scene.validate import Problems
from kcheck.scene.yamlio import YamlDocument, read_yaml

__all__ = ["STUDY_SUFFIX", "Parameter", "Study", "load_study", "apply_values", "variant_document"]

STUDY_SUFFIX = ".kcheck-study.yaml"
DISTRIBUTIONS = {
    "uniform": ("min", "max"),
    "normal": ("mean", "sd"),
    "truncated-normal": ("mean", "sd", "min", "max"),
}
ANGLE_UNITS = {"deg": 1.0, "rad": 180.0 / math.pi}
STUDY_KEYS = ("version", "scene", "design", "parameters", "checks", "figures", "chunk")
PARAMETER_KEYS = ("name", "path", "values", "range", "steps", "distribution", "unit")
#: Figures collected when the study names none (beside every check's verdict).
DEFAULT_FIGURES = (
    "analytical-3d.design_margin_deg",
    "analytical-3d.limiting_friction",
    "analytical-2d.limiting_friction",
)


@dataclass(frozen=True)
class Parameter:
    """One varied field: ``levels`` (grid values) or a distribution, in the scene's units."""

    name: str
    path: tuple[str, ...]
    where: FieldPath
    levels: tuple[Any, ...] | None = None
    distribution: str | None = None
    params: dict[str, float] = field(default_factory=dict)
    scale: float = 1.0

    @property
    def numeric(self) -> bool:
        return self.levels is None or all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in self.levels
        )


@dataclass(frozen=True)
class Study:
    """A checked study file: the base scene's document and the variants' values."""

    path: Path
    scene_path: Path
    scene: YamlDocument
    parameters: tuple[Parameter, ...]
    design: str
    samples: int
    seed: int
    checks: tuple[str, ...] | None
    figures: tuple[str, ...]
    chunk: int
    lines: dict[FieldPath, int]

    def values(self) -> list[np.ndarray]:
        """Every variant's value of each parameter (one array per parameter, in the
        scene's units), in variant order."""
        if self.design == "grid":
            idx = grid_indices([len(p.levels or ()) for p in self.parameters])
            return [
                np.asarray(p.levels, dtype=float if p.numeric else object)[idx[:, j]]
                for j, p in enumerate(self.parameters)
            ]
        u = unit_points(self.design, self.samples, len(self.parameters), self.seed)
        out = []
        for j, p in enumerate(self.parameters):
            if p.levels is not None:  # a discrete choice, equally likely
                k = np.minimum((u[:, j] * len(p.levels)).astype(np.int64), len(p.levels) - 1)
                out.append(np.asarray(p.levels, dtype=float if p.numeric else object)[k])
            else:
                assert p.distribution is not None
                out.append(quantiles(p.distribution, u[:, j], p.params) * p.scale)
        return out


def _resolve(data: Any, path: tuple[str, ...]) -> list[tuple[Any, Any]]:
    """The (container, key) pairs a path names in the scene data; KeyError naming the part
    that is not there."""
    here: list[Any] = [data]
    for i, part in enumerate(path):
        last = i == len(path) - 1
        nxt: list[tuple[Any, Any]] = []
        for node in here:
            if isinstance(node, dict):
                if part not in node and not last:
                    raise KeyError(part)
                nxt.append((node, part))
            elif isinstance(node, list):
                if part == "*":
                    nxt.extend((node, k) for k in range(len(node)))
                elif part.lstrip("-").isdigit() and -len(node) <= int(part) < len(node):
                    nxt.append((node, int(part)))
                else:
                    named = [
                        k
                        for k, item in enumerate(node)
                        if isinstance(item, dict) and item.get("name") == part
                    ]
                    if not named:
                        raise KeyError(part)
                    nxt.extend((node, k) for k in named)
            else:
                raise KeyError(part)
        if last:
            return nxt
        here = [c[k] for c, k in nxt]
    return []


def _plain(value: Any) -> Any:
    """A numpy scalar as the plain Python value the scene reader would have produced."""
    return value.item() if isinstance(value, np.generic) else value


def apply_values(data: Any, parameters: tuple[Parameter, ...], values: list[Any]) -> Any:
    """A deep copy of scene data with each parameter's field set to its value."""
    out = copy.deepcopy(data)
    for p, v in zip(parameters, values, strict=True):
        for container, key in _resolve(out, p.path):
            container[key] = _plain(v)
    return out


def variant_document(study: Study, values: list[Any]) -> YamlDocument:
    """The base scene's document with one variant's values (lines kept for errors)."""
    base = study.scene
    return YamlDocument(apply_values(base.data, study.parameters, values), base.lines, base.columns)


def _number(p: Problems, where: FieldPath, value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        p.add(where, f"expected a finite number, got {value!r}")
        return None
    return float(value)


def _parameter(
    p: Problems, raw: Any, where: FieldPath, design: str, scene: Any, units: str
) -> Parameter | None:
    if not isinstance(raw, dict):
        p.add(where, "expected a mapping with `path` and `values`, `range` or `distribution`")
        return None
    for key in raw:
        if key not in PARAMETER_KEYS:
            p.add((*where, key), f"unknown field; expected one of {', '.join(PARAMETER_KEYS)}")
    text = raw.get("path")
    if not isinstance(text, str) or not text:
        p.add((*where, "path"), "expected a dotted path into the scene, e.g. `friction`")
        return None
    path = tuple(text.split("."))
    try:
        found = _resolve(scene, path)
    except KeyError as exc:
        p.add((*where, "path"), f"the scene has no field `{exc.args[0]}` on the path `{text}`")
        return None
    if not found:
        p.add((*where, "path"), f"`{text}` names no field of the scene")
        return None
    unit = raw.get("unit")
    scale = 1.0
    if unit is not None:
        if unit in LENGTH_TO_M:
            scale = LENGTH_TO_M[unit] / LENGTH_TO_M[units]
        elif unit in ANGLE_UNITS:
            scale = ANGLE_UNITS[unit]
        elif unit != "1":
            known = ", ".join([*LENGTH_TO_M, *ANGLE_UNITS, "1"])
            p.add((*where, "unit"), f"unknown unit {unit!r}; expected one of {known}")
    name = raw.get("name", text)
    kinds = [k for k in ("values", "range", "distribution") if k in raw]
    if len(kinds) != 1:
        p.add(where, "give exactly one of `values`, `range` or `distribution`")
        return None
    kind = kinds[0]
    if kind == "values":
        values = raw["values"]
        if not isinstance(values, list) or not values:
            p.add((*where, "values"), "expected a non-empty list")
            return None
        levels = tuple(v * scale if isinstance(v, (int, float)) else v for v in values)
        return Parameter(name, path, where, levels=levels, scale=scale)
    if kind == "range":
        r = raw["range"]
        if not isinstance(r, list) or len(r) != 2:
            p.add((*where, "range"), "expected [min, max]")
            return None
        lo, hi = (_number(p, (*where, "range", i), v) for i, v in enumerate(r))
        if lo is None or hi is None:
            return None
        if lo > hi:
            p.add((*where, "range"), f"min {lo:g} is greater than max {hi:g}")
            return None
        if design == "grid":
            steps = raw.get("steps")
            if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
                p.add((*where, "steps"), "a range on a grid needs `steps`, a whole number ≥ 1")
                return None
            levels = tuple(np.linspace(lo, hi, steps) * scale) if steps > 1 else (lo * scale,)
            return Parameter(name, path, where, levels=tuple(float(v) for v in levels))
        return Parameter(
            name, path, where, distribution="uniform", params={"min": lo, "max": hi}, scale=scale
        )
    dist = raw["distribution"]
    dwhere = (*where, "distribution")
    if design == "grid":
        p.add(
            dwhere,
            "a grid needs `values` or a `range` with `steps`; distributions are "
            "for latin-hypercube, sobol or monte-carlo designs",
        )
        return None
    if not isinstance(dist, dict) or dist.get("type") not in DISTRIBUTIONS:
        p.add(dwhere, f"expected a mapping with `type`: one of {', '.join(DISTRIBUTIONS)}")
        return None
    needed = DISTRIBUTIONS[dist["type"]]
    params: dict[str, float] = {}
    for key in needed:
        if key not in dist:
            p.add(dwhere, f"a {dist['type']} distribution needs `{key}` ({', '.join(needed)})")
            return None
        v = _number(p, (*dwhere, key), dist[key])
        if v is None:
            return None
        params[key] = v
    for key in dist:
        if key != "type" and key not in needed:
            p.add(
                (*dwhere, key),
                f"unknown field; a {dist['type']} distribution takes {', '.join(needed)}",
            )
    if "sd" in params and params["sd"] <= 0:
        p.add((*dwhere, "sd"), f"expected a positive standard deviation, got {params['sd']:g}")
        return None
    if "min" in params and params["min"] > params["max"]:
        p.add(dwhere, f"min {params['min']:g} is greater than max {params['max']:g}")
        return None
    return Parameter(name, path, where, distribution=dist["type"], params=params, scale=scale)


def load_study(path: Path | str) -> Study:
    """Read and check a study file and its base scene; SceneError(s) located in the study
    file (or the scene file, for an error of the base scene itself)."""
    from kcheck.scene.load import scene_from_document

    path = Path(path)
    doc = read_yaml(path)
    p = Problems(path, doc.lines, doc.columns)
    data = doc.data
    if not isinstance(data, dict):
        raise p.error((), "expected a mapping of study fields")
    for key in data:
        if key not in STUDY_KEYS:
            p.add((key,), f"unknown field; expected one of {', '.join(STUDY_KEYS)}")
    if data.get("version", 1) != 1:
        p.add(("version",), "expected 1")
    scene_text = data.get("scene")
    if not isinstance(scene_text, str):
        raise p.error(("scene",), "expected the path of the base scene file, relative to here")
    scene_path = path.parent / scene_text
    scene_doc = read_yaml(scene_path)
    scene_from_document(scene_path, scene_doc)  # the base scene must be valid itself
    units = scene_doc.data.get("units", "m") if isinstance(scene_doc.data, dict) else "m"
    units = units if units in LENGTH_TO_M else "m"
    design_raw = data.get("design", {"type": "grid"})
    if not isinstance(design_raw, dict):
        raise p.error(("design",), "expected a mapping with `type`")
    design = design_raw.get("type", "grid")
    if design not in DESIGNS:
        p.add(("design", "type"), f"expected one of {', '.join(DESIGNS)}, got {design!r}")
    samples, seed = design_raw.get("samples", 0), design_raw.get("seed", 0)
    if design != "grid" and (
        isinstance(samples, bool) or not isinstance(samples, int) or samples < 1
    ):
        p.add(("design", "samples"), "a sampled design needs `samples`, a whole number ≥ 1")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        p.add(("design", "seed"), "expected a whole number ≥ 0")
    raw_params = data.get("parameters")
    if not isinstance(raw_params, list) or not raw_params:
        raise p.error(("parameters",), "expected a non-empty list of parameters")
    params = [
        _parameter(p, raw, ("parameters", i), design, scene_doc.data, units)
        for i, raw in enumerate(raw_params)
    ]
    names = [q.name for q in params if q is not None]
    for q in params:
        if q is not None and names.count(q.name) > 1:
            p.add((*q.where, "name"), f"two parameters are named `{q.name}`; give each a name")
    checks = data.get("checks")
    if checks is not None and (
        not isinstance(checks, list) or not all(isinstance(c, str) for c in checks)
    ):
        p.add(("checks",), "expected a list of check ids")
    figures = data.get("figures", list(DEFAULT_FIGURES))
    if not isinstance(figures, list) or not all(isinstance(f, str) and "." in f for f in figures):
        p.add(("figures",), "expected a list of `CHECK.FIGURE` names")
    chunk = data.get("chunk", 64)
    if isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1:
        p.add(("chunk",), "expected a whole number of variants per chunk, ≥ 1")
    p.raise_if_any()
    study = Study(
        path,
        scene_path,
        scene_doc,
        tuple(q for q in params if q is not None),
        design,
        samples,
        seed,
        None if checks is None else tuple(checks),
        tuple(figures),
        chunk,
        doc.lines,
    )
    _levels_valid(study, p)
    return study


def _levels_valid(study: Study, p: Problems) -> None:
    """Each parameter at its extreme levels (the others at the base scene's values) must
    leave a valid scene: an error at the parameter's line otherwise."""
    from kcheck.scene.load import scene_from_document

    columns = study.values()
    for j, q in enumerate(study.parameters):
        col = columns[j]
        if q.numeric:
            finite = col[np.isfinite(col.astype(float))] if len(col) else col
            probes = sorted({float(finite.min()), float(finite.max())}) if len(finite) else []
        else:
            probes = list(dict.fromkeys(col.tolist()))
        for v in probes:
            data = apply_values(study.scene.data, (q,), [v])
            doc = YamlDocument(data, study.scene.lines, study.scene.columns)
            try:
                scene_from_document(study.scene_path, doc)
            except SceneError as exc:
                first = exc.all()[0]
                p.add(q.where, f"at `{'.'.join(q.path)}` = {v!r} the scene is invalid: {first}")
                break
    p.raise_if_any()
