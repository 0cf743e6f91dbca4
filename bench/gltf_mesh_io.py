"""Triangle meshes between the bench generators and the Mitsuba scripts: writing them as glTF 2.0
+ one .bin buffer (bench/gen_specular_spheres.py, bench/gen_envmap_check.py), updating generated
files only when their bytes change (or, with --check, saying which are stale), reading the glTF
back and handing each mesh to Mitsuba as a binary PLY file (bench/mitsuba_specular.py,
bench/mitsuba_envmap.py), so that tex and Mitsuba trace the same float32 triangles.

Only what the generators write is supported: one primitive per mesh, float32 VEC3 POSITION and
(optional) NORMAL, tightly packed, unsigned short (or, when reading, unsigned int) indices, one
material per mesh named after the mesh."""
import json
import os
import struct
import sys

ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
FLOAT, UNSIGNED_SHORT = 5126, 5123


class GltfMeshes:
    """The buffer (blob), accessors, buffer views, meshes, materials and nodes of a list of
    (name, positions, normals, triangles) meshes: per mesh three accessors (POSITION with min/max,
    NORMAL, indices), each in its own 4-byte aligned buffer view."""

    def __init__(self, meshes):
        self.blob = bytearray()
        self.accessors, self.views, self.meshes, self.materials, self.nodes = [], [], [], [], []
        for index, (name, positions, normals, tris) in enumerate(meshes):
            pos = b"".join(struct.pack("<3f", *p) for p in positions)
            nrm = b"".join(struct.pack("<3f", *n) for n in normals)
            idx = b"".join(struct.pack("<3H", *t) for t in tris)
            lo = [min(p[k] for p in positions) for k in range(3)]
            hi = [max(p[k] for p in positions) for k in range(3)]
            self.accessors.append({"bufferView": self._add_view(pos, ARRAY_BUFFER), "componentType": FLOAT,
                                   "count": len(positions), "type": "VEC3", "min": lo, "max": hi})
            self.accessors.append({"bufferView": self._add_view(nrm, ARRAY_BUFFER), "componentType": FLOAT,
                                   "count": len(normals), "type": "VEC3"})
            self.accessors.append({"bufferView": self._add_view(idx, ELEMENT_ARRAY_BUFFER),
                                   "componentType": UNSIGNED_SHORT, "count": 3 * len(tris), "type": "SCALAR"})
            self.materials.append({"name": name})
            self.meshes.append({"name": name, "primitives": [{"attributes": {"POSITION": 3 * index,
                                                                             "NORMAL": 3 * index + 1},
                                                              "indices": 3 * index + 2, "material": index}]})
            self.nodes.append({"name": name, "mesh": index})

    def _add_view(self, data, target):
        while len(self.blob) % 4:
            self.blob.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data), "target": target})
        self.blob.extend(data)
        return len(self.views) - 1

    def document(self, generator, bin_name, extras=None, normals=True):
        """The glTF file's bytes (JSON, indent 1, newline-terminated) referring to the buffer as
        bin_name; normals=False leaves NORMAL out of every primitive (flat shading; the buffer keeps
        the normals, so both documents can share it)."""
        meshes = json.loads(json.dumps(self.meshes))
        if not normals:
            for m in meshes:
                del m["primitives"][0]["attributes"]["NORMAL"]
        doc = {"asset": {"version": "2.0", "generator": generator}}
        if extras is not None:
            doc["extras"] = extras
        doc.update({
            "scene": 0, "scenes": [{"nodes": list(range(len(self.nodes)))}], "nodes": self.nodes, "meshes": meshes,
            "materials": self.materials, "accessors": self.accessors, "bufferViews": self.views,
            "buffers": [{"uri": bin_name, "byteLength": len(self.blob)}],
        })
        return (json.dumps(doc, indent=1) + "\n").encode()


def update_files(directory, files, check):
    """files: {name: bytes}. Writes those whose content differs from directory/name (unless check)
    and returns their names (the stale ones)."""
    stale = []
    for name, data in files.items():
        path = os.path.join(directory, name)
        old = open(path, "rb").read() if os.path.exists(path) else None
        if old != data:
            stale.append(name)
            if not check:
                with open(path, "wb") as f:
                    f.write(data)
    return stale


def report_stale(stale, check, regenerate):
    """The generators' last words: with check, exit 1 naming the stale files (regenerate: how to
    bring them up to date); else (or when nothing is stale) print what was written."""
    if check and stale:
        sys.exit("stale: " + ", ".join(stale) + f" ({regenerate})")
    print(("stale: " if check else "wrote: ") + (", ".join(stale) if stale else "nothing (up to date)"))


def read_gltf_meshes(path):
    """(name, positions bytes, normals bytes or None, indices as uint32 bytes, vertex count,
    triangle count) of every mesh primitive in the glTF file. Only what the generator writes is
    supported: float VEC3 attributes, tightly packed, unsigned short or int indices."""
    doc = json.load(open(path))
    base = os.path.dirname(path)
    buffers = [open(os.path.join(base, b["uri"]), "rb").read() for b in doc["buffers"]]

    def accessor_bytes(i, element_size):
        a = doc["accessors"][i]
        v = doc["bufferViews"][a["bufferView"]]
        if v.get("byteStride", element_size) != element_size:
            sys.exit(f"{path}: strided accessor {i} not supported")
        start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        return buffers[v["buffer"]][start:start + a["count"] * element_size], a

    meshes = []
    for mesh in doc["meshes"]:
        for prim in mesh["primitives"]:
            name = doc["materials"][prim["material"]]["name"]
            pos, a = accessor_bytes(prim["attributes"]["POSITION"], 12)
            assert a["componentType"] == 5126 and a["type"] == "VEC3"
            count = a["count"]
            nrm = None
            if "NORMAL" in prim["attributes"]:
                nrm, a = accessor_bytes(prim["attributes"]["NORMAL"], 12)
                assert a["componentType"] == 5126 and a["count"] == count
            ia = doc["accessors"][prim["indices"]]
            size = {5123: 2, 5125: 4}[ia["componentType"]]
            raw, _ = accessor_bytes(prim["indices"], size)
            idx = struct.unpack("<%d%s" % (ia["count"], "H" if size == 2 else "I"), raw)
            meshes.append((name, pos, nrm, idx, count, ia["count"] // 3))
    return meshes


def write_ply(path, pos, nrm, idx, vertex_count, face_count):
    """A binary little-endian PLY file (Mitsuba's `ply` shape) of one mesh as read_gltf_meshes
    returns it: float x y z (and nx ny nz when nrm is not None), triangles as uchar/int lists."""
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {vertex_count}",
              "property float x", "property float y", "property float z"]
    if nrm is not None:
        header += ["property float nx", "property float ny", "property float nz"]
    header += [f"element face {face_count}", "property list uchar int vertex_indices", "end_header"]
    with open(path, "wb") as f:
        f.write(("\n".join(header) + "\n").encode())
        for v in range(vertex_count):
            f.write(pos[12 * v:12 * v + 12])
            if nrm is not None:
                f.write(nrm[12 * v:12 * v + 12])
        for t in range(face_count):
            f.write(struct.pack("<B3i", 3, *idx[3 * t:3 * t + 3]))


def gltf_to_ply(gltf, directory):
    """Every mesh of the glTF file as directory/<name>.ply (write_ply), in the file's order:
    yields (material name, PLY path, whether it has vertex normals)."""
    for name, pos, nrm, idx, nv, nf in read_gltf_meshes(gltf):
        ply = os.path.join(directory, name + ".ply")
        write_ply(ply, pos, nrm, idx, nv, nf)
        yield name, ply, nrm is not None
