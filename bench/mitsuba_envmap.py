#!/usr/bin/env python3
"""Renders the image-based lighting scene of bench/envmap_vs_mitsuba.sh with Mitsuba 3 (the tex side
is scenes/envmap-mitsuba.json): 256x192, path integrator (max_depth 8, rr_depth 5), box pixel
filter, perspective camera from (0, 1.2, 6.5) to (0, 0.8, 0), vertical fov 40 deg, lit only by an
`envmap` emitter; writes an EXR (with variance channels when rendered in 2 or more passes).

Geometry: the ground quad and the three spheres of scenes/envmap_check.gltf (written by
bench/gen_envmap_check.py), the same float32 triangles and vertex normals handed to Mitsuba as
binary PLY files. BSDFs (the .tex counterparts are in scenes/envmap_mitsuba.tex):

    ground  diffuse, reflectance rgb (0.5, 0.5, 0.5)
    white   diffuse, reflectance rgb (0.8, 0.8, 0.8)
    orange  diffuse, reflectance rgb (0.85, 0.4, 0.1)
    metal   conductor, eta 0.2, k 3.0 (floats: uniform spectra), specular_reflectance 1

The environment map. tex's map (scenes/envmap_check.exr, W x H) is piecewise constant: pixel (x, y)
covers u in [x, x+1) / W, v in [y, y+1) / H. Mitsuba's envmap (3.9) uses the same direction <-> (u, v)
formulas (u = atan2(d.x, -d.z) / 2pi, v = acos(d.y) / pi, so to_world = our transform), but its
image is a grid of nodes interpolated bilinearly: node (x, y) of a W' x H' image sits at
u = (x + 0.5) / W', v = y / (H' - 1), periodic in u (`probe` below checks this against Mitsuba's own
envmap). Given tex's map unchanged, Mitsuba would stretch it vertically by up to half a pixel
(rows at y / (H-1) instead of (y + 0.5) / H) and blur it. Instead this script hands Mitsuba a node
grid resampled from tex's map (mitsuba_map): W' = F W, H' = F H + 1 (F = --map-factor, default 4),
each node the value of tex's map at its position, the mean of the two (four) sides when it lies on
a pixel edge (every horizontal edge of tex's map falls on a node row; every vertical edge midway
between two node columns). Its bilinear interpolation is then tex's map exactly, except in bands of
1 / (F W) in u and 2 / (F H) in v centred on each colour edge, where the difference is
antisymmetric about the edge: it integrates to zero to first order under any smooth weight (a
diffuse surface's cosine), so only pixels that see an edge sharply (the sky seen directly, mirror
reflections) show it. One more difference in those bands: Mitsuba's spectral variants interpolate a
pixel's spectral shape and its scale (2 max(rgb)) separately and multiply them, which is not linear
across an edge between different chromaticities (gen_envmap_check.py puts a halo of the sun's own
chromaticity around the sun for this reason).

Prints a human line and one machine-readable line:
    RESULT variant=<v> spp=<n> threads=<t> seconds=<s> paths_per_s=<p>

Subcommands: `probe` (Mitsuba's envmap mapping and to_world against the node model, and the
resampled map against tex's map; exits 1 on a mismatch), `analyse TEX.exr SCALAR.exr LLVM.exr`
(region means, per-pixel Z-tests, verdict; exits 1 on disagreement).
"""
import argparse
import math
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from gltf_mesh_io import gltf_to_ply  # noqa: E402
from mitsuba_common import (add_analyse_arguments, add_render_arguments, analyse_regions, load_scene,  # noqa: E402
                            render_and_report, start_mitsuba)

ROOT = os.path.join(HERE, "..")
MAP = os.path.join(ROOT, "scenes", "envmap_check.exr")
GLTF = os.path.join(ROOT, "scenes", "envmap_check.gltf")

BSDFS = {
    "ground": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.5, 0.5, 0.5]}},
    "white": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.8, 0.8, 0.8]}},
    "orange": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.85, 0.4, 0.1]}},
    "metal": {"type": "conductor", "eta": 0.2, "k": 3.0, "specular_reflectance": 1.0},
}
# Camera of scenes/envmap-mitsuba.json.
CAMERA_FROM = (0.0, 1.2, 6.5)
CAMERA_TO = (0.0, 0.8, 0.0)
CAMERA_UP = (0.0, 1.0, 0.0)
FOV_DEG = 40.0  # vertical
WIDTH, HEIGHT = 256, 192


def parse_rotate(text):
    """'ax,ay,az,deg' (tex's "rotate": [axis, angle_deg]) -> 4 floats, or None for ''."""
    if not text:
        return None
    v = [float(x) for x in text.split(",")]
    if len(v) != 4:
        raise SystemExit("--env-rotate wants ax,ay,az,deg")
    return v


def rotation_matrix(rot):
    """3x3 rotation (numpy) of tex's rotate [ax, ay, az, deg] (glm::rotate, right-handed)."""
    import numpy as np
    if rot is None:
        return np.eye(3)
    a = np.array(rot[:3], float)
    a /= np.linalg.norm(a)
    t = math.radians(rot[3])
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * (k @ k)


def direction_to_uv(d):
    """tex's directionToSphericalYUp (warp.h) = Mitsuba's envmap direction_to_uv, on arrays (..., 3)."""
    import numpy as np
    u = np.arctan2(d[..., 0], -d[..., 2]) / (2 * np.pi)
    u = np.where(u < 0, u + 1, u)
    v = np.arccos(np.clip(d[..., 1], -1, 1)) / np.pi
    return u, v


def uv_to_direction(u, v):
    import numpy as np
    phi, theta = 2 * np.pi * u, np.pi * v
    return np.stack([np.sin(phi) * np.sin(theta), np.cos(theta), -np.cos(phi) * np.sin(theta)], axis=-1)


def tex_lookup(img, u, v):
    """tex's ImageEnvironment: the pixel containing (u, v), nearest."""
    import numpy as np
    h, w = img.shape[:2]
    x = np.clip((u * w).astype(int), 0, w - 1)
    y = np.clip((v * h).astype(int), 0, h - 1)
    return img[y, x]


def mitsuba_map(img, factor):
    """The node grid (F H + 1, F W, 3) whose bilinear interpolation in Mitsuba's envmap is tex's
    piecewise-constant map up to antisymmetric bands at the edges (module docstring)."""
    import numpy as np
    h, w = img.shape[:2]
    wm, hm = factor * w, factor * h + 1
    u = (np.arange(wm) + 0.5) / wm
    v = np.arange(hm) / (hm - 1)
    uu, vv = np.meshgrid(u, v)
    # Mean over the node's neighbourhood: four points just off it (they differ only on edges).
    eps = 0.25 / (factor * max(w, h))
    acc = np.zeros((hm, wm, 3))
    for du in (-eps, eps):
        for dv in (-eps, eps):
            acc += tex_lookup(img, np.mod(uu + du, 1.0), np.clip(vv + dv, 0.0, 1.0))
    return (acc / 4).astype(np.float32)


def mitsuba_bilinear(nodes, u, v):
    """The node model of Mitsuba's envmap eval (RGB variants): bilinear between nodes at
    u = (x + 0.5) / W', v = y / (H' - 1), periodic in u."""
    import numpy as np
    hm, wm = nodes.shape[:2]
    x = u * wm - 0.5
    y = np.clip(v * (hm - 1), 0, hm - 1)
    x0 = np.floor(x).astype(int)
    y0 = np.minimum(np.floor(y).astype(int), hm - 2)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    xa, xb = np.mod(x0, wm), np.mod(x0 + 1, wm)
    return ((1 - fy) * ((1 - fx) * nodes[y0, xa] + fx * nodes[y0, xb]) +
            fy * ((1 - fx) * nodes[y0 + 1, xa] + fx * nodes[y0 + 1, xb]))


def envmap_desc(mi, nodes, rot, filename):
    mi.Bitmap(nodes, mi.Bitmap.PixelFormat.RGB).write(filename)
    desc = {"type": "envmap", "filename": filename}
    if rot is not None:
        # Mitsuba's Transform4f.rotate takes the axis as given (a non-unit axis gives a matrix that
        # is no rotation, silently); tex normalises it (glm::rotate), so normalise here.
        n = math.sqrt(sum(a * a for a in rot[:3]))
        desc["to_world"] = mi.ScalarTransform4f().rotate(axis=[a / n for a in rot[:3]], angle=rot[3])
    return desc


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_render_arguments(ap)
    ap.add_argument("--map", default=MAP, help="tex's environment map (default scenes/envmap_check.exr)")
    ap.add_argument("--map-factor", type=int, default=4, help="node grid resolution factor F (default 4)")
    ap.add_argument("--env-rotate", default="", help="environment rotation ax,ay,az,deg (tex's rotate; default none)")
    args = ap.parse_args()
    rot = parse_rotate(args.env_rotate)
    dr, mi, np = start_mitsuba(args)
    from gen_envmap_check import read_exr_rgb

    tmp = tempfile.TemporaryDirectory(prefix="mitsuba_envmap_")
    nodes = mitsuba_map(read_exr_rgb(args.map), args.map_factor)
    desc = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": args.max_depth, "rr_depth": args.rr_depth},
        "sensor": {
            "type": "perspective", "fov_axis": "y", "fov": FOV_DEG,
            "to_world": mi.ScalarTransform4f().look_at(origin=CAMERA_FROM, target=CAMERA_TO, up=CAMERA_UP),
            "sampler": {"type": "independent", "sample_count": 64},
            "film": {"type": "hdrfilm", "width": WIDTH, "height": HEIGHT, "rfilter": {"type": "box"},
                     "pixel_format": "rgb", "component_format": "float32"},
        },
        "sky": envmap_desc(mi, nodes, rot, os.path.join(tmp.name, "envmap.exr")),
    }
    for name, ply, _ in gltf_to_ply(GLTF, tmp.name):
        desc["shape-" + name] = {"type": "ply", "filename": ply, "face_normals": False, "bsdf": dict(BSDFS[name])}
    scene, width, height, load_s = load_scene(mi, desc)

    render_and_report(mi, np, scene, args, width, height, load_s,
                      f"map x{args.map_factor} ({nodes.shape[1]}x{nodes.shape[0]} nodes), env rotate {rot}")


# ---------------------------------------------------------------------------------------------
# `mitsuba_envmap.py probe`: the conventions this script relies on, checked against Mitsuba itself.

def probe(argv):
    ap = argparse.ArgumentParser(prog="mitsuba_envmap.py probe")
    ap.add_argument("--map", default=MAP)
    ap.add_argument("--map-factor", type=int, default=4)
    ap.add_argument("--env-rotate", default="0.3,1,0.2,130")
    args = ap.parse_args(argv)
    import drjit as dr
    import mitsuba as mi
    import numpy as np
    mi.set_variant("scalar_rgb")
    from gen_envmap_check import read_exr_rgb
    rng = np.random.default_rng(1)
    failures = []
    tmp = tempfile.TemporaryDirectory(prefix="mitsuba_envmap_probe_")

    def mitsuba_eval(emitter, dirs):
        out = np.zeros((len(dirs), 3))
        for i, d in enumerate(dirs):
            si = dr.zeros(mi.SurfaceInteraction3f)
            si.wi = -mi.Vector3f(*d)
            out[i] = np.array(emitter.eval(si))
        return out

    # 1. A random 12 x 7 node grid: Mitsuba's eval against the node model, at random directions,
    #    with the identity and with a rotation (to_world = our transform: local = R^T world).
    nodes = rng.uniform(0.1, 1.0, (7, 12, 3)).astype(np.float32)
    for rot in (None, parse_rotate(args.env_rotate)):
        em = mi.load_dict(envmap_desc(mi, nodes, rot, os.path.join(tmp.name, "probe.exr")))
        world = rng.normal(size=(400, 3))
        world /= np.linalg.norm(world, axis=1, keepdims=True)
        local = world @ rotation_matrix(rot)  # rows: R^T w
        u, v = direction_to_uv(local)
        err = np.abs(mitsuba_eval(em, world) - mitsuba_bilinear(nodes, u, v)).max()
        print(f"   node model vs Mitsuba envmap eval, rotate {rot}: max abs difference {err:.2e}")
        if err > 1e-4:
            failures.append(f"Mitsuba's envmap mapping is not the node model (rotate {rot}): {err:.3g}")
    # 2. The resampled map against tex's: equal away from edges (both functions at random directions).
    img = read_exr_rgb(args.map)
    nodes = mitsuba_map(img, args.map_factor)
    h, w = img.shape[:2]
    u, v = rng.uniform(size=200000), np.arccos(rng.uniform(-1, 1, 200000)) / np.pi
    a, b = tex_lookup(img, u, v), mitsuba_bilinear(nodes, u, v)
    # Distance to the nearest pixel edge, in node spacings.
    du = np.abs(u * w - np.round(u * w)) * args.map_factor
    dv = np.abs(v * h - np.round(v * h)) * args.map_factor
    far = (du > 0.51) & (dv > 1.01)
    err = np.abs(a - b)[far].max()
    band = np.any(np.abs(a - b) > 1e-6, axis=-1).mean()
    print(f"   resampled map (x{args.map_factor}) vs tex's map away from pixel edges: max abs difference {err:.2e}; "
          f"directions that differ at all (edge bands, uniform on the sphere): {100 * band:.2f} %")
    if err > 1e-5:
        failures.append(f"resampled map differs from tex's away from edges: {err:.3g}")
    # The luminance integral over the sphere (what a diffuse surface averages): tex exactly, Mitsuba's
    # interpolation by quadrature (RGB, i.e. without the spectral shape/scale product).
    lum = np.array([0.2126729, 0.7151522, 0.0721750])
    cos_edges = np.cos(np.pi * np.arange(h + 1) / h)
    tex_int = float(((img @ lum) * (cos_edges[:-1] - cos_edges[1:])[:, None]).sum() * 2 * np.pi / w)
    n = 4096
    uq = (np.arange(2 * n) + 0.5) / (2 * n)
    vq = (np.arange(n) + 0.5) / n
    U, V = np.meshgrid(uq, vq)
    mi_int = float((mitsuba_bilinear(nodes, U, V) @ lum * np.sin(np.pi * V)).sum() * (np.pi / n) * (2 * np.pi / (2 * n)))
    tex_q = float((tex_lookup(img, U, V) @ lum * np.sin(np.pi * V)).sum() * (np.pi / n) * (2 * np.pi / (2 * n)))
    print(f"   luminance integral over the sphere: tex exact {tex_int:.5f}, tex by quadrature {tex_q:.5f}, "
          f"Mitsuba node model by quadrature {mi_int:.5f} (ratio {mi_int / tex_q:.5f})")
    if failures:
        print("   PROBE FAILED:")
        for f in failures:
            print("     " + f)
        return 1
    return 0


# ---------------------------------------------------------------------------------------------
# Analysis: `mitsuba_envmap.py analyse TEX.exr MITSUBA_SCALAR.exr MITSUBA_LLVM.exr`

SPHERE_CENTRES = {"white": (-2.0, 0.8, 0.3), "metal": (0.0, 0.8, -0.4), "orange": (2.0, 0.8, 0.3)}
SPHERE_RADIUS = 0.8
GROUND_HALF = 20.0


def camera_rays(width, height, sub=(0.5, 0.5)):
    """Unit directions (height, width, 3) through the point `sub` of each pixel (tex's and Mitsuba's
    perspective camera: vertical fov, world +x on the right, row 0 at the top)."""
    import numpy as np
    o, t, up = (np.array(x, float) for x in (CAMERA_FROM, CAMERA_TO, CAMERA_UP))
    f = (t - o) / np.linalg.norm(t - o)
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    th = math.tan(math.radians(FOV_DEG) / 2)
    i = ((np.arange(width) + sub[0]) / width * 2 - 1) * th * width / height
    j = (1 - (np.arange(height) + sub[1]) / height * 2) * th
    di, dj = np.meshgrid(i, j)
    d = f + di[..., None] * r + dj[..., None] * u
    return o, d / np.linalg.norm(d, axis=-1, keepdims=True)


def first_hits(o, d):
    """(distance, name) of the first surface along each ray: the exact spheres (the meshes'
    circumscribed spheres) and the ground quad; '' and inf for the sky."""
    import numpy as np
    best = np.full(d.shape[:-1], np.inf)
    which = np.full(d.shape[:-1], "", dtype=object)
    for name, c in SPHERE_CENTRES.items():
        oc = o - np.array(c)
        b = np.sum(d * oc, axis=-1)
        disc = b * b - (np.sum(oc * oc) - SPHERE_RADIUS ** 2)
        tt = -b - np.sqrt(np.maximum(disc, 0))
        tt = np.where((disc > 0) & (tt > 0), tt, np.inf)
        hit = tt < best
        best[hit], which[hit] = tt[hit], name
    tg = -o[1] / np.where(d[..., 1] < 0, d[..., 1], -1e-30)
    p = o + tg[..., None] * d
    tg = np.where((tg > 0) & (np.abs(p[..., 0]) <= GROUND_HALF) & (np.abs(p[..., 2]) <= GROUND_HALF), tg, np.inf)
    hit = tg < best
    best[hit], which[hit] = tg[hit], "ground"
    return best, which


def region_masks(width, height, img, rot):
    """Ground, each sphere, and the sky seen directly split into pixels whose footprint (the pixel
    widened by 2 pixels on every side, 9 x 9 sample rays) sees one colour of the map ('sky, uniform')
    and the rest ('sky, edges': where Mitsuba's interpolation bands lie)."""
    import numpy as np
    o, d = camera_rays(width, height)
    _, which = first_hits(o, d)
    masks = {"all but sky edges": None}
    for name in ("ground", "white", "metal", "orange"):
        masks[name if name == "ground" else name + " sphere"] = which == name
    sky = which == ""
    R = rotation_matrix(rot)
    first = None
    uniform = np.ones(sky.shape, bool)
    for sx in np.linspace(-2, 3, 9):
        for sy in np.linspace(-2, 3, 9):
            _, ds = camera_rays(width, height, (sx, sy))
            u, v = direction_to_uv(ds @ R)
            c = tex_lookup(img, u, v)
            if first is None:
                first = c
            uniform &= np.all(c == first, axis=-1)
    masks["sky, uniform"] = sky & uniform
    masks["sky, edges"] = sky & ~uniform
    masks["all but sky edges"] = ~masks["sky, edges"]
    return masks


def analyse(argv):
    ap = argparse.ArgumentParser(prog="mitsuba_envmap.py analyse",
                                 description="image and region means, per-pixel Z-tests, verdict")
    add_analyse_arguments(ap)
    ap.add_argument("--map", default=MAP)
    ap.add_argument("--env-rotate", default="")
    ap.add_argument("--sky-tolerance", type=float, default=0.002,
                    help="relative systematic tolerance of the 'sky, uniform' means (default 0.002: the two "
                         "renderers' RGB -> spectrum -> RGB round trips of a map colour differ by up to 0.1 %%, "
                         "bench/README.md)")
    args = ap.parse_args(argv)
    from gen_envmap_check import read_exr_rgb

    colours = {"ground": (0.5, 0.5, 0.5), "white sphere": (1.0, 1.0, 1.0), "metal sphere": (0.3, 0.3, 0.9),
               "orange sphere": (1.0, 0.5, 0.1), "sky, uniform": (0.2, 0.8, 0.9), "sky, edges": (1.0, 0.0, 0.0)}

    def masks(width, height):
        return region_masks(width, height, read_exr_rgb(args.map), parse_rotate(args.env_rotate))

    return analyse_regions(args, masks, colours, "all judged region means within the bound, Z-tests comparable to the control",
                           info_regions=("sky, edges",), tolerances={"sky, uniform": args.sky_tolerance})


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "analyse":
        sys.exit(analyse(sys.argv[2:]))
    if len(sys.argv) > 1 and sys.argv[1] == "probe":
        sys.exit(probe(sys.argv[2:]))
    main()
