#!/usr/bin/env python3
"""Renders the specular Cornell box of bench/specular_vs_mitsuba.sh with Mitsuba 3: its own
mi.cornell_box() (256x256, path integrator, max_depth 8, rr_depth 5, box pixel filter) with the
two boxes replaced by the three spheres of scenes/specular-mitsuba.json, and writes an EXR.

The spheres are read from the glTF file tex renders (scenes/specular_spheres.gltf and its .bin,
written by bench/gen_specular_spheres.py): the same float32 vertex positions, vertex normals and
triangles, handed to Mitsuba as binary PLY files (its `ply` shape, face_normals false; with
--shading flat, the normal-less scenes/specular_spheres_flat.gltf and face_normals true). BSDFs:

    glass  dielectric, int_ior 1.5,  ext_ior 1.0 (Mitsuba's default ext_ior is air, 1.000277)
    water  dielectric, int_ior 1.33, ext_ior 1.0
    metal  conductor, eta 0.2, k 3.0 (floats: uniform spectra), specular_reflectance 1
    core   (inside water) diffuse of reflectance 0 with an area emitter of RGB radiance (3, 1.5, 0.6)

The spp may be split into passes (--pass-spp) with seeds seed, seed + 1, ...; the image is their
mean, and with 2 or more passes the EXR also gets variance.R/G/B channels (the variance of that
mean, from the spread of the passes) for `tex compare`'s Z-test, as bench/mitsuba_cornell.py.

Prints a human line and one machine-readable line:
    RESULT variant=<v> spp=<n> threads=<t> seconds=<s> paths_per_s=<p>
"""
import argparse
import json
import os
import struct
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_common import Passes, add_render_arguments, load_scene, pass_count, start_mitsuba  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")

# The BSDF of each glTF material name (the .tex counterparts are in scenes/specular_mitsuba.tex).
BSDFS = {
    "glass": {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0},
    "water": {"type": "dielectric", "int_ior": 1.33, "ext_ior": 1.0},
    "metal": {"type": "conductor", "eta": 0.2, "k": 3.0, "specular_reflectance": 1.0},
    "core": {"type": "diffuse", "reflectance": 0.0},
}
# Emitters (one-sided, facing out of the mesh) by material name.
EMITTERS = {
    "core": {"type": "area", "radiance": {"type": "rgb", "value": [3.0, 1.5, 0.6]}},
}


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


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_render_arguments(ap)
    ap.add_argument("--shading", choices=("smooth", "flat"), default="smooth",
                    help="smooth: the spheres' vertex normals (default); flat: face normals")
    args = ap.parse_args()
    dr, mi, np = start_mitsuba(args)

    desc = mi.cornell_box()
    desc["integrator"]["max_depth"] = args.max_depth
    desc["integrator"]["rr_depth"] = args.rr_depth
    desc["sensor"]["film"]["rfilter"] = {"type": "box"}
    del desc["small-box"], desc["large-box"]

    gltf = os.path.join(ROOT, "scenes", "specular_spheres.gltf" if args.shading == "smooth" else "specular_spheres_flat.gltf")
    tmp = tempfile.TemporaryDirectory(prefix="mitsuba_specular_")
    for name, pos, nrm, idx, nv, nf in read_gltf_meshes(gltf):
        if (nrm is not None) != (args.shading == "smooth"):
            sys.exit(f"{gltf}: mesh {name} has{'' if nrm is not None else ' no'} normals")
        ply = os.path.join(tmp.name, name + ".ply")
        write_ply(ply, pos, nrm, idx, nv, nf)
        desc["sphere-" + name] = {"type": "ply", "filename": ply, "face_normals": args.shading == "flat",
                                  "bsdf": dict(BSDFS[name])}
        if name in EMITTERS:
            desc["sphere-" + name]["emitter"] = dict(EMITTERS[name])
    scene, width, height, load_s = load_scene(mi, desc)

    pass_spp, _ = pass_count(args)
    passes = Passes(mi, np, scene, args)
    mean, seconds = passes.mean, passes.seconds
    paths_per_s = width * height * args.spp / seconds
    print(f"mitsuba {mi.__version__} {args.variant}: {width}x{height}, {args.spp} spp "
          f"({passes.count} pass(es) of {pass_spp}), max_depth {args.max_depth}, rr_depth {args.rr_depth}, "
          f"{args.threads} threads, {args.shading} shading: {seconds:.1f} s (+ scene load {load_s:.2f} s), "
          f"{paths_per_s / 1e6:.3f} M paths/s; "
          f"mean RGB {mean[..., 0].mean():.5f} {mean[..., 1].mean():.5f} {mean[..., 2].mean():.5f}")
    print(f"RESULT variant={args.variant} spp={args.spp} threads={args.threads} seconds={seconds:.4f} "
          f"paths_per_s={paths_per_s:.1f}")
    if args.output:
        passes.write_exr(mi, np, args.output)


# ---------------------------------------------------------------------------------------------
# Analysis: `mitsuba_specular.py analyse TEX.exr MITSUBA_SCALAR.exr MITSUBA_LLVM.exr`

# Camera of mi.cornell_box() (and scenes/specular-mitsuba.json): at (0, 0, 3.9) looking down -z,
# +y up, world +x on the right of the image, fov 39.3077 deg on the (square) image.
CAMERA_Z = 3.9
FOV_DEG = 39.3077
# Floor around the glass sphere's caustic: the focus of the light seen through the sphere lies
# on the line from the light's centre through the sphere's centre, which meets the floor here.
CAUSTIC_RADIUS = 0.4


def region_masks(width, height):
    """Masks over pixel centres by analytic ray casting against the exact spheres (the meshes'
    circumscribed spheres; a pixel on a silhouette goes to whichever its centre ray hits): the
    glass, metal and water spheres, the emitter seen through the water (the camera ray refracted
    at the exact water sphere hits the core), the floor around the glass sphere's caustic, the rest."""
    import numpy as np
    from gen_specular_spheres import SPHERES

    spheres = {name: (np.array(c), r) for name, c, r, _, _ in SPHERES}
    t = np.tan(np.radians(FOV_DEG) / 2)
    i = (np.arange(width) + 0.5) / width * 2 - 1
    j = 1 - (np.arange(height) + 0.5) / height * 2
    dx, dy = np.meshgrid(i * t * width / height, j * t)
    d = np.stack([dx, dy, -np.ones_like(dx)], axis=-1)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    o = np.array([0.0, 0.0, CAMERA_Z])

    def hit_sphere(o, d, name):  # distance to the first hit from outside, inf if none
        c, r = spheres[name]
        oc = o - c
        b = np.sum(d * oc, axis=-1)
        disc = b * b - (np.sum(oc * oc, axis=-1) - r * r)
        tt = -b - np.sqrt(np.maximum(disc, 0))
        return np.where((disc > 0) & (tt > 0), tt, np.inf)

    best = np.full(dx.shape, np.inf)
    which = np.full(dx.shape, "", dtype=object)
    for name in ("glass", "metal", "water"):
        tt = hit_sphere(o, d, name)
        hit = tt < best
        best[hit], which[hit] = tt[hit], name
    # Refract into the water (IOR 1.33) and look for the core.
    cw, _ = spheres["water"]
    p = o + np.where(np.isfinite(best), best, 0)[..., None] * d
    n = (p - cw) / np.linalg.norm(p - cw, axis=-1, keepdims=True)
    cos_i = -np.sum(d * n, axis=-1)
    eta = 1 / 1.33
    k = 1 - eta * eta * (1 - cos_i * cos_i)
    dt = eta * d + (eta * cos_i - np.sqrt(np.maximum(k, 0)))[..., None] * n
    core = (which == "water") & np.isfinite(hit_sphere(p, dt, "core"))
    # The floor, y = -1.
    tf = (-1 - o[1]) / np.where(d[..., 1] < 0, d[..., 1], -1e-30)
    pf = o + tf[..., None] * d
    light = np.array([0.0, 0.99, 0.01])
    g, _ = spheres["glass"]
    focus = light + (g - light) * (-1 - light[1]) / (g[1] - light[1])
    floor_hit = (tf > 0) & (tf < best) & (np.abs(pf[..., 0]) <= 1) & (np.abs(pf[..., 2]) <= 1)
    near = np.hypot(pf[..., 0] - focus[0], pf[..., 2] - focus[2]) < CAUSTIC_RADIUS
    masks = {"all": np.ones(dx.shape, bool)}
    for name in ("glass", "metal", "water"):
        masks[name + " sphere"] = which == name
    masks["core through water"] = core
    masks["glass caustic floor"] = floor_hit & near
    masks["rest"] = (which == "") & ~masks["glass caustic floor"]
    return masks


def load_exr(path):
    import mitsuba as mi
    import numpy as np
    bitmap = mi.Bitmap(path)
    data = np.array(bitmap, dtype=np.float64)
    names = [bitmap.struct_()[i].name for i in range(bitmap.channel_count())]
    ch = {name: data[..., i] for i, name in enumerate(names)}
    mean = np.stack([ch[c] for c in "RGB"], axis=-1)
    var = np.stack([ch["variance." + c] for c in "RGB"], axis=-1)
    return mean, var


def analyse(argv):
    ap = argparse.ArgumentParser(prog="mitsuba_specular.py analyse",
                                 description="image and region means, per-pixel Z-tests, verdict")
    ap.add_argument("tex")
    ap.add_argument("scalar")
    ap.add_argument("llvm")
    ap.add_argument("--alpha", type=float, default=0.01,
                    help="family-wise false-alarm rate of the region mean tests (Sidak-corrected; default 0.01)")
    ap.add_argument("--masks-out", default="", help="write the region masks as a PNG (optional)")
    args = ap.parse_args(argv)
    import mitsuba as mi
    import numpy as np
    mi.set_variant("scalar_rgb")
    from statistics import NormalDist

    images = {"tex": load_exr(args.tex), "scalar": load_exr(args.scalar), "llvm": load_exr(args.llvm)}
    h, w = images["tex"][0].shape[:2]
    masks = region_masks(w, h)
    if args.masks_out:
        colours = {"glass sphere": (0.2, 0.5, 1.0), "metal sphere": (0.8, 0.8, 0.8), "water sphere": (0.2, 1.0, 0.6),
                   "core through water": (1.0, 0.3, 0.1), "glass caustic floor": (1.0, 0.8, 0.1), "rest": (0.1, 0.1, 0.1)}
        img = np.zeros((h, w, 3), np.float32)
        for name, col in colours.items():
            img[masks[name]] = col
        mi.util.write_bitmap(args.masks_out, img)

    pairs = [("tex", "llvm"), ("tex", "scalar"), ("llvm", "scalar")]  # the last is the control
    regions = list(masks)
    tests = len(regions) * 3 * 2  # the region-channel mean tests of the two tex pairs
    z_crit = NormalDist().inv_cdf(1 - (1 - (1 - args.alpha) ** (1 / tests)) / 2)
    failures = []

    def mean_se(name, mask):
        m, v = images[name]
        n = mask.sum()
        return m[mask].mean(axis=0), np.sqrt(v[mask].sum(axis=0)) / n

    def ztest(a, b, mask):
        (ma, va), (mb, vb) = images[a], images[b]
        var = (va + vb)[mask]
        ok = var > 0
        z = ((ma - mb)[mask])[ok] / np.sqrt(var[ok])
        return float(np.mean(z * z)), float(np.mean(np.abs(z) > 3)), int(ok.sum())

    print("   region means (R G B) +- standard error; ratio tex / Mitsuba and its deviation in sigma")
    print(f"   (pass: every |deviation| of a tex pair <= {z_crit:.2f} sigma, the Sidak bound for {tests} tests "
          f"at family-wise {args.alpha:g})")
    for region in regions:
        mask = masks[region]
        print(f"   {region} ({mask.sum()} pixels):")
        stats = {k: mean_se(k, mask) for k in images}
        for k in images:
            m, se = stats[k]
            label = {"tex": "tex", "scalar": "mitsuba scalar_spectral", "llvm": "mitsuba llvm_ad_spectral"}[k]
            print("     %-24s %s" % (label, "  ".join("%.5f+-%.5f" % (a, s) for a, s in zip(m, se))))
        for a, b in pairs:
            (ma, sa), (mb, sb) = stats[a], stats[b]
            ratio = ma / mb
            dev = (ma - mb) / np.sqrt(sa * sa + sb * sb)
            rse = ratio * np.sqrt((sa / ma) ** 2 + (sb / mb) ** 2)
            control = a != "tex"
            bad = (not control) and bool(np.any(np.abs(dev) > z_crit))
            if bad:
                failures.append(f"{region}: {a}/{b} deviations {' '.join('%.1f' % x for x in dev)} sigma")
            print("       %-13s R %.4f  G %.4f  B %.4f  (+- %.4f %.4f %.4f)  deviation %5.1f %5.1f %5.1f sigma%s" %
                  ((f"{a}/{b}",) + tuple(ratio) + tuple(rse) + tuple(dev) +
                   ("  (control)" if control else "  FAIL" if bad else "",)))

    print("   per-pixel Z-test (z = difference / sqrt(sum of variances), every pixel channel):")
    print("     %-22s %-12s %s" % ("region", "pair", "mean z^2   |z|>3"))
    ztab = {}
    for region in regions:
        for a, b in pairs:
            zz, out, n = ztest(a, b, masks[region])
            ztab[(region, a, b)] = (zz, out)
            print("     %-22s %-12s %7.3f  %7.3f %%" % (region, f"{a}/{b}", zz, 100 * out))
    # Z-test verdict: a tex pair may not be worse than the Mitsuba-only control by more than
    # noise allows: mean z^2 within 1.25x (+0.1) of the control's, outliers at most twice (+0.5 %).
    for region in regions:
        czz, cout = ztab[(region, "llvm", "scalar")]
        for a, b in pairs[:2]:
            zz, out = ztab[(region, a, b)]
            if zz > 1.25 * czz + 0.1 or out > 2 * cout + 0.005:
                failures.append(f"{region}: Z-test {a}/{b} mean z^2 {zz:.3f}, |z|>3 {100 * out:.2f} % "
                                f"against the control's {czz:.3f}, {100 * cout:.2f} %")
    if failures:
        print("   DISAGREEMENT:")
        for f in failures:
            print("     " + f)
        return 1
    print("   agreement: all region means within the bound, Z-tests comparable to the control")
    return 0


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "analyse":
        sys.exit(analyse(sys.argv[2:]))
    main()
