"""Triangle meshes written as a STEP file (ISO 10303-21, AP214): one named product per
part, each a closed B-rep of planar triangular faces in millimetres. For tests of reading
STEP assemblies (cascadio reads STEP but writes none). Every face is an ADVANCED_FACE on a
PLANE bounded by an EDGE_LOOP of straight EDGE_CURVEs shared with its neighbours."""

from __future__ import annotations

import numpy as np


def step_text(parts: list[tuple[str, object]]) -> str:
    """The STEP text of ``parts``: (name, trimesh.Trimesh in mm) pairs."""
    lines: list[str] = []

    def add(text: str) -> str:
        lines.append(f"#{len(lines) + 1}={text};")
        return f"#{len(lines)}"

    def point(v) -> str:
        return add(f"CARTESIAN_POINT('',({v[0]:.17g},{v[1]:.17g},{v[2]:.17g}))")

    def direction(v) -> str:
        return add(f"DIRECTION('',({v[0]:.17g},{v[1]:.17g},{v[2]:.17g}))")

    app = add("APPLICATION_CONTEXT('core data for automotive mechanical design processes')")
    add(f"APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,{app})")
    mechanical = add(f"MECHANICAL_CONTEXT('',{app},'mechanical')")
    definition = add(f"PRODUCT_DEFINITION_CONTEXT('part definition',{app},'design')")
    mm = add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))")
    rad = add("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))")
    sr = add("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())")
    eps = add(
        f"UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),{mm},'distance_accuracy_value','')"
    )
    context = add(
        f"(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT(({eps}))"
        f"GLOBAL_UNIT_ASSIGNED_CONTEXT(({mm},{rad},{sr}))REPRESENTATION_CONTEXT('',''))"
    )
    for name, mesh in parts:
        product = add(f"PRODUCT('{name}','{name}','',({mechanical}))")
        formation = add(f"PRODUCT_DEFINITION_FORMATION('','',{product})")
        pd = add(f"PRODUCT_DEFINITION('design','',{formation},{definition})")
        shape = add(f"PRODUCT_DEFINITION_SHAPE('','',{pd})")
        v = np.asarray(mesh.vertices, dtype=float)
        vertices = [add(f"VERTEX_POINT('',{point(p)})") for p in v]
        edges: dict[tuple[int, int], str] = {}

        def edge(a: int, b: int, v=v, edges=edges, vertices=vertices) -> str:
            key = (min(a, b), max(a, b))
            if key not in edges:
                d = v[key[1]] - v[key[0]]
                length = float(np.linalg.norm(d))
                vector = add(f"VECTOR('',{direction(d / length)},{length:.17g})")
                line = add(f"LINE('',{point(v[key[0]])},{vector})")
                ends = f"{vertices[key[0]]},{vertices[key[1]]}"
                edges[key] = add(f"EDGE_CURVE('',{ends},{line},.T.)")
            return add(f"ORIENTED_EDGE('',*,*,{edges[key]},{'.T.' if a < b else '.F.'})")

        faces = []
        for f, normal in zip(np.asarray(mesh.faces), np.asarray(mesh.face_normals), strict=True):
            loop = add(f"EDGE_LOOP('',({','.join(edge(f[i], f[(i + 1) % 3]) for i in range(3))}))")
            bound = add(f"FACE_OUTER_BOUND('',{loop},.T.)")
            x = (v[f[1]] - v[f[0]]) / np.linalg.norm(v[f[1]] - v[f[0]])
            frame = add(
                f"AXIS2_PLACEMENT_3D('',{point(v[f[0]])},{direction(normal)},{direction(x)})"
            )
            faces.append(
                add(f"ADVANCED_FACE('',({bound}),{add(f'PLANE({chr(39) * 2},{frame})')},.T.)")
            )
        shell = add(f"CLOSED_SHELL('',({','.join(faces)}))")
        brep = add(f"MANIFOLD_SOLID_BREP('{name}',{shell})")
        z, x = direction([0, 0, 1]), direction([1, 0, 0])
        origin = add(f"AXIS2_PLACEMENT_3D('',{point([0, 0, 0])},{z},{x})")
        rep = add(f"ADVANCED_BREP_SHAPE_REPRESENTATION('{name}',({brep},{origin}),{context})")
        add(f"SHAPE_DEFINITION_REPRESENTATION({shape},{rep})")
    head = (
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('kcheck test assembly'),'2;1');\n"
        "FILE_NAME('assembly.step','2026-11-25T00:00:00',(''),(''),'','','');\n"
        "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n"
    )
    return head + "\n".join(lines) + "\nENDSEC;\nEND-ISO-10303-21;\n"
