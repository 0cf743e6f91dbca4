#!/usr/bin/env python3
"""Writes the sphere meshes of scenes/specular-mitsuba.json (bench/specular_vs_mitsuba.sh):

    scenes/specular_spheres.gltf       glTF 2.0, one mesh per sphere, POSITION + NORMAL (smooth)
    scenes/specular_spheres_flat.gltf  the same triangles without NORMAL (flat shading)
    scenes/specular_spheres.bin        the buffer both share

Each sphere is a UV sphere about +y (S segments around, R rings from pole to pole: one vertex per
pole, R - 1 rows of S vertices, 2 S (R - 1) triangles, counter-clockwise seen from outside; 64 x 32,
the emitter inside the water sphere 32 x 16), baked into world space in float32 so that tex (which reads the glTF) and Mitsuba
(bench/mitsuba_specular.py reads the same buffer and hands it over as a PLY) trace exactly the
same triangles. Vertex normals are the exact sphere normals (unit length in float32).

The glTF materials are named after the sphere; scenes/specular-mitsuba.json binds .tex materials
to these names, bench/mitsuba_specular.py gives Mitsuba the matching BSDFs (SPHERES below is the
one place that lists them; the Mitsuba script imports it).

Usage: python3 bench/gen_specular_spheres.py [--check]   (--check: exit 1 if the files are stale)
"""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gltf_mesh_io import GltfMeshes, report_stale, update_files  # noqa: E402

SEGMENTS = 64
RINGS = 32

# name, centre, radius, segments, rings. Mitsuba's Cornell box spans [-1, 1]^3, floor at y = -1,
# camera at z = 3.9.
SPHERES = [
    ("glass", (0.42, -0.665, 0.10), 0.33, SEGMENTS, RINGS),    # smooth dielectric, IOR 1.5 inside, 1.0 outside
    ("metal", (-0.42, -0.635, -0.25), 0.36, SEGMENTS, RINGS),  # smooth conductor, eta 0.2 + i 3.0 (constant)
    ("water", (-0.05, -0.835, 0.55), 0.16, SEGMENTS, RINGS),   # smooth dielectric, IOR 1.33 inside, 1.0 outside
    # An emitter inside the water sphere (black, emitting outwards): seen through the water, its
    # radiance is scaled by (1 / 1.33)^2, the factor a closed dielectric cancels on every other path.
    ("core", (-0.05, -0.835, 0.55), 0.06, SEGMENTS // 2, RINGS // 2),
]

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.join(HERE, "..", "scenes")
BIN_NAME = "specular_spheres.bin"


def sphere(center, radius, segments, rings):
    """Positions, normals (lists of float32-representable tuples) and triangle indices."""
    import math

    def f32(x):
        return struct.unpack("<f", struct.pack("<f", x))[0]

    dirs = [(0.0, 1.0, 0.0)]
    for r in range(1, rings):
        theta = math.pi * r / rings
        for s in range(segments):
            phi = 2.0 * math.pi * s / segments
            dirs.append((math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi)))
    dirs.append((0.0, -1.0, 0.0))
    normals = [tuple(f32(c) for c in d) for d in dirs]
    positions = [tuple(f32(center[i] + radius * d[i]) for i in range(3)) for d in dirs]

    def row(r, s):  # vertex of ring row r (1..rings-1), segment s
        return 1 + (r - 1) * segments + s % segments

    south = len(dirs) - 1
    tris = []
    for s in range(segments):  # north fan
        tris.append((0, row(1, s), row(1, s + 1)))
    for r in range(1, rings - 1):
        for s in range(segments):
            a, b, c, d = row(r, s), row(r, s + 1), row(r + 1, s), row(r + 1, s + 1)
            tris.append((a, c, d))
            tris.append((a, d, b))
    for s in range(segments):  # south fan
        tris.append((south, row(rings - 1, s + 1), row(rings - 1, s)))
    return positions, normals, tris


def check_winding(positions, tris, center):
    # Counter-clockwise seen from outside: the face normal points away from the centre.
    for t in tris:
        p = [positions[i] for i in t]
        e1 = [p[1][k] - p[0][k] for k in range(3)]
        e2 = [p[2][k] - p[0][k] for k in range(3)]
        n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        c = [sum(q[k] for q in p) / 3 - center[k] for k in range(3)]
        assert sum(n[k] * c[k] for k in range(3)) > 0, "winding"


def build():
    meshes = []
    for name, center, radius, segments, rings in SPHERES:
        positions, normals, tris = sphere(center, radius, segments, rings)
        check_winding(positions, tris, center)
        meshes.append((name, positions, normals, tris))
    gltf = GltfMeshes(meshes)

    def document(flat):
        return gltf.document("bench/gen_specular_spheres.py", BIN_NAME, extras={"shading": "flat" if flat else "smooth"},
                             normals=not flat)

    files = {
        BIN_NAME: bytes(gltf.blob),
        "specular_spheres.gltf": document(False),
        "specular_spheres_flat.gltf": document(True),
    }
    return files


def main():
    check = "--check" in sys.argv[1:]
    stale = update_files(SCENES, build(), check)
    report_stale(stale, check, "run python3 bench/gen_specular_spheres.py")


if __name__ == "__main__":
    main()
