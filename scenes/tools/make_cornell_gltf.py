#!/usr/bin/env python3
"""Writes scenes/cornell-box.gltf: the Cornell box geometry as published by the Cornell Program
of Computer Graphics ("Cornell Box Data", https://www.graphics.cornell.edu/online/box/data.html),
converted from millimetres to metres, with one glTF material per surface kind ("white", "red",
"green", "light") so that scene files can bind .tex materials to them by name, and the
published camera (position (278, 273, -800) mm looking along +z, 35 mm lens, 25 mm film:
vertical field of view 2 atan(12.5 / 35) = 39.31 degrees).

The data's x axis points left as seen from the camera; glTF is right-handed with the camera
looking down its -z, so the camera node is rotated 180 degrees about y. Quads are split into
two triangles whose winding faces the inside of the box (front = counter-clockwise).

Run: python3 scenes/tools/make_cornell_gltf.py   (no dependencies)
"""
import base64, json, math, struct, os

MM = 0.001
# (material, [quad corners in mm]) in the published order; blocks are listed face by face.
QUADS = [
    ("white", [(552.8, 0, 0), (0, 0, 0), (0, 0, 559.2), (549.6, 0, 559.2)]),            # floor
    ("light", [(343, 548.7, 227), (343, 548.7, 332), (213, 548.7, 332), (213, 548.7, 227)]),  # light, 0.1 mm below the ceiling
    ("white", [(556, 548.8, 0), (556, 548.8, 559.2), (0, 548.8, 559.2), (0, 548.8, 0)]),  # ceiling
    ("white", [(549.6, 0, 559.2), (0, 0, 559.2), (0, 548.8, 559.2), (556, 548.8, 559.2)]),  # back wall
    ("green", [(0, 0, 559.2), (0, 0, 0), (0, 548.8, 0), (0, 548.8, 559.2)]),            # right wall
    ("red", [(552.8, 0, 0), (549.6, 0, 559.2), (556, 548.8, 559.2), (556, 548.8, 0)]),  # left wall
    # short block
    ("white", [(130, 165, 65), (82, 165, 225), (240, 165, 272), (290, 165, 114)]),
    ("white", [(290, 0, 114), (290, 165, 114), (240, 165, 272), (240, 0, 272)]),
    ("white", [(130, 0, 65), (130, 165, 65), (290, 165, 114), (290, 0, 114)]),
    ("white", [(82, 0, 225), (82, 165, 225), (130, 165, 65), (130, 0, 65)]),
    ("white", [(240, 0, 272), (240, 165, 272), (82, 165, 225), (82, 0, 225)]),
    # tall block
    ("white", [(423, 330, 247), (265, 330, 296), (314, 330, 456), (472, 330, 406)]),
    ("white", [(423, 0, 247), (423, 330, 247), (472, 330, 406), (472, 0, 406)]),
    ("white", [(472, 0, 406), (472, 330, 406), (314, 330, 456), (314, 0, 456)]),
    ("white", [(314, 0, 456), (314, 330, 456), (265, 330, 296), (265, 0, 296)]),
    ("white", [(265, 0, 296), (265, 330, 296), (423, 330, 247), (423, 0, 247)]),
]
CENTRE = (278.0, 274.4, 279.6)  # inside the box: every face must face this point (blocks: away from their own centre)
BLOCK_CENTRES = [(186, 82.5, 168.5), (368.5, 165, 351.5)]


def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def dot(a, b): return sum(x * y for x, y in zip(a, b))


def oriented(quad, index):
    """The quad's corners ordered so that its normal points into the open space."""
    n = cross(sub(quad[1], quad[0]), sub(quad[2], quad[0]))
    centroid = tuple(sum(c[k] for c in quad) / 4 for k in range(3))
    if index >= 6:  # block faces point away from their block's centre
        block = BLOCK_CENTRES[0 if index < 11 else 1]
        outward = sub(centroid, block)
    else:           # room faces point toward the room's centre
        outward = sub(CENTRE, centroid)
    return quad if dot(n, outward) > 0 else list(reversed(quad))


def main():
    materials = ["white", "red", "green", "light"]
    per_material = {m: ([], []) for m in materials}  # positions, indices
    for i, (mat, quad) in enumerate(QUADS):
        pos, idx = per_material[mat]
        q = oriented(quad, i)
        base = len(pos)
        pos.extend((x * MM, y * MM, z * MM) for x, y, z in q)
        idx.extend([base, base + 1, base + 2, base, base + 2, base + 3])
    blob = b""
    buffer_views, accessors, primitives = [], [], []
    for m in materials:
        pos, idx = per_material[m]
        if not pos: continue
        # Flat normals per quad (every 4 vertices share one).
        normals = []
        for q in range(0, len(pos), 4):
            n = cross(sub(pos[q + 1], pos[q]), sub(pos[q + 2], pos[q]))
            l = math.sqrt(dot(n, n))
            normals.extend([tuple(c / l for c in n)] * 4)
        for data, fmt, target, comp, typ, count, mm in (
            (pos, "3f", 34962, 5126, "VEC3", len(pos), True),
            (normals, "3f", 34962, 5126, "VEC3", len(normals), False),
            (idx, "I", 34963, 5125, "SCALAR", len(idx), False),
        ):
            while len(blob) % 4: blob += b"\0"
            start = len(blob)
            for item in data:
                blob += struct.pack("<" + fmt, *(item if isinstance(item, tuple) else (item,)))
            buffer_views.append({"buffer": 0, "byteOffset": start, "byteLength": len(blob) - start, "target": target})
            acc = {"bufferView": len(buffer_views) - 1, "componentType": comp, "count": count, "type": typ}
            if mm:
                acc["min"] = [min(p[k] for p in pos) for k in range(3)]
                acc["max"] = [max(p[k] for p in pos) for k in range(3)]
            accessors.append(acc)
        a = len(accessors)
        primitives.append({"attributes": {"POSITION": a - 3, "NORMAL": a - 2}, "indices": a - 1, "material": materials.index(m)})
    fov = 2 * math.atan(12.5 / 35.0)
    gltf = {
        "asset": {"version": "2.0", "generator": "tex scenes/tools/make_cornell_gltf.py",
                  "copyright": "Geometry: Cornell Program of Computer Graphics, Cornell Box Data"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"name": "CornellBox", "mesh": 0},
            {"name": "Camera", "camera": 0, "translation": [0.278, 0.273, -0.8], "rotation": [0, 1, 0, 0]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": fov, "aspectRatio": 1.0, "znear": 0.01}}],
        "meshes": [{"name": "CornellBox", "primitives": primitives}],
        "materials": [{"name": m, "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.75, 0.75, 1], "metallicFactor": 0}} for m in materials],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": buffer_views,
        "accessors": accessors,
    }
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "cornell-box.gltf")
    with open(out, "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")
    print("wrote", os.path.normpath(out))


if __name__ == "__main__":
    main()
