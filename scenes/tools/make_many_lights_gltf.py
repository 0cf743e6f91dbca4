#!/usr/bin/env python3
"""Writes scenes/many-lights.gltf: 1024 small square lamps (2048 emissive triangles) in a
32 x 32 grid over a 18 m x 18 m area, at heights 0.2 to 2.6 m, facing down (-y), with three
glTF materials "lamp_dim", "lamp_mid" and "lamp_bright" that scenes/many-lights.json binds to
emissions of radiance 1, 4 and 16. Sizes and heights come from a fixed linear congruential
sequence, so the file is reproducible. A scene where each floor point is lit by few of many
lights: the light BVH's case (docs/light-sampling.md).

Run: python3 scenes/tools/make_many_lights_gltf.py   (no dependencies)
"""
import base64, json, os, struct

SIDE = 32
AREA = 18.0


class Lcg:
    def __init__(self, seed): self.state = seed
    def next(self):
        self.state = (self.state * 6364136223846793005 + 1442695040888963407) % (1 << 64)
        return (self.state >> 40) / float(1 << 24)


def main():
    rng = Lcg(2026)
    materials = ["lamp_dim", "lamp_mid", "lamp_bright"]
    per_material = {m: ([], []) for m in materials}
    spacing = AREA / SIDE
    for j in range(SIDE):
        for i in range(SIDE):
            size = spacing * 0.25 * (0.5 + rng.next())
            height = 0.2 + 2.4 * rng.next()
            mat = materials[int(rng.next() * 3) % 3]
            x0 = -AREA / 2 + (i + 0.5) * spacing
            z0 = -AREA / 2 + (j + 0.5) * spacing
            pos, idx = per_material[mat]
            base = len(pos)
            # Counter-clockwise seen from below: the normal (edge1 x edge2) is -y.
            pos.extend([(x0, height, z0), (x0 + size, height, z0), (x0 + size, height, z0 + size), (x0, height, z0 + size)])
            idx.extend([base, base + 1, base + 2, base, base + 2, base + 3])
    blob = b""
    buffer_views, accessors, primitives = [], [], []
    for m in materials:
        pos, idx = per_material[m]
        for data, fmt, target, comp, typ, minmax in ((pos, "3f", 34962, 5126, "VEC3", True), (idx, "I", 34963, 5125, "SCALAR", False)):
            while len(blob) % 4: blob += b"\0"
            start = len(blob)
            for item in data:
                blob += struct.pack("<" + fmt, *(item if isinstance(item, tuple) else (item,)))
            buffer_views.append({"buffer": 0, "byteOffset": start, "byteLength": len(blob) - start, "target": target})
            acc = {"bufferView": len(buffer_views) - 1, "componentType": comp, "count": len(data), "type": typ}
            if minmax:
                acc["min"] = [min(p[k] for p in pos) for k in range(3)]
                acc["max"] = [max(p[k] for p in pos) for k in range(3)]
            accessors.append(acc)
        primitives.append({"attributes": {"POSITION": len(accessors) - 2}, "indices": len(accessors) - 1, "material": materials.index(m)})
    gltf = {
        "asset": {"version": "2.0", "generator": "tex scenes/tools/make_many_lights_gltf.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "Lamps", "mesh": 0}],
        "meshes": [{"name": "Lamps", "primitives": primitives}],
        "materials": [{"name": m, "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0}} for m in materials],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": buffer_views,
        "accessors": accessors,
    }
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "many-lights.gltf")
    with open(out, "w") as f:
        json.dump(gltf, f, separators=(",", ":"))
        f.write("\n")
    print("wrote", os.path.normpath(out))


if __name__ == "__main__":
    main()
