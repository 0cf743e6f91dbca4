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
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gltf_mesh_io import gltf_to_ply  # noqa: E402
from mitsuba_common import (add_analyse_arguments, add_render_arguments, analyse_regions, load_scene,  # noqa: E402
                            render_and_report, start_mitsuba)

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
    for name, ply, has_normals in gltf_to_ply(gltf, tmp.name):
        if has_normals != (args.shading == "smooth"):
            sys.exit(f"{gltf}: mesh {name} has{'' if has_normals else ' no'} normals")
        desc["sphere-" + name] = {"type": "ply", "filename": ply, "face_normals": args.shading == "flat",
                                  "bsdf": dict(BSDFS[name])}
        if name in EMITTERS:
            desc["sphere-" + name]["emitter"] = dict(EMITTERS[name])
    scene, width, height, load_s = load_scene(mi, desc)

    render_and_report(mi, np, scene, args, width, height, load_s, f"{args.shading} shading")


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


def analyse(argv):
    ap = argparse.ArgumentParser(prog="mitsuba_specular.py analyse",
                                 description="image and region means, per-pixel Z-tests, verdict")
    add_analyse_arguments(ap)
    args = ap.parse_args(argv)
    colours = {"glass sphere": (0.2, 0.5, 1.0), "metal sphere": (0.8, 0.8, 0.8), "water sphere": (0.2, 1.0, 0.6),
               "core through water": (1.0, 0.3, 0.1), "glass caustic floor": (1.0, 0.8, 0.1), "rest": (0.1, 0.1, 0.1)}
    return analyse_regions(args, region_masks, colours,
                           "all region means within the bound, Z-tests comparable to the control")


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "analyse":
        sys.exit(analyse(sys.argv[2:]))
    main()
