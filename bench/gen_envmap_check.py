#!/usr/bin/env python3
"""Writes the inputs of the image-based lighting check against Mitsuba 3 (bench/envmap_vs_mitsuba.sh,
scenes/envmap-mitsuba.json):

    scenes/envmap_check.exr   the environment map, 256 x 128 float RGB, latitude-longitude with tex's
                              mapping (docs/scene-format.md): pixel (x, y) covers u in [x, x+1) / 256,
                              v in [y, y+1) / 128, u = azimuth / 2pi as warp.h's sphericalDirectionYUp
                              (direction (sin phi sin theta, cos theta, -cos phi sin theta)), v = polar
                              angle from +y / pi; row 0 is the top (straight up)
    scenes/envmap_check.gltf  a ground quad and three spheres (UV spheres of 64 x 32 segments, as
    scenes/envmap_check.bin   bench/gen_specular_spheres.py writes them, baked into world space,
                              float32, smooth vertex normals); the glTF material names are the
                              binding names of the scene (MESHES below)

The map is deliberately asymmetric, so that a mirrored, flipped or rotated mapping changes the image:
the upper hemisphere has four azimuth quadrants of different colours (u in [0, .25) blue, [.25, .5)
green, [.5, .75) magenta, [.75, 1) warm white), three elevation bands (darker zenith cap, base,
brighter horizon band), a red marker stripe in the blue quadrant at u in [8, 16) / 256, and a warm
sun of 3 x 3 pixels (4.2 degrees) centred at u = 0.3 (azimuth 108 deg), 35 deg above the horizon,
inside a 1-pixel halo of the sun's own chromaticity (see mitsuba_envmap.py: Mitsuba interpolates a
pixel's spectral shape and its scale separately, which is exact across an edge only when the two
sides share a chromaticity; the halo keeps the 75x brightness step of the sun's edge free of that);
the lower hemisphere is brown ground for u < 0.5 and dark blue-grey for u >= 0.5.

Every pixel is constant over its patch (as tex treats it); Mitsuba's bilinear envmap gets a node grid
resampled from this file (mitsuba_envmap.py, mitsuba_map), which defines the same radiance except in
thin bands along colour edges where the error is antisymmetric.

Usage: build-bench/venv/bin/python bench/gen_envmap_check.py [--check]
       (needs numpy and mitsuba, for EXR I/O; --check: exit 1 if the files are stale)
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from gen_specular_spheres import check_winding, sphere  # noqa: E402
from gltf_mesh_io import GltfMeshes, report_stale, update_files  # noqa: E402

SCENES = os.path.join(HERE, "..", "scenes")
MAP_NAME = "envmap_check.exr"
GLTF_NAME = "envmap_check.gltf"
BIN_NAME = "envmap_check.bin"

WIDTH, HEIGHT = 256, 128

# Upper-hemisphere colours per azimuth quadrant (u in [q/4, (q+1)/4)).
QUADRANTS = [(0.25, 0.45, 1.0), (0.35, 0.85, 0.25), (0.9, 0.3, 0.75), (0.95, 0.9, 0.8)]
# Elevation bands (rows; 64 rows = the upper hemisphere): zenith cap, base, horizon band.
BANDS = [(0, 16, 0.6), (16, 56, 1.0), (56, 64, 1.4)]
MARKER = ((8, 16), (20, 50), (2.0, 0.1, 0.1))  # columns, rows, colour
SUN_COLOUR = (1.0, 0.9, 0.7)
SUN = ((76, 79), (38, 41), 150.0)  # columns, rows (3 x 3 pixels), radiance scale of SUN_COLOUR
HALO_SCALE = 2.0                   # the 1-pixel ring around the sun
GROUND = [(0.35, 0.25, 0.15), (0.15, 0.15, 0.2)]  # lower hemisphere, u < 0.5 and u >= 0.5

# name, centre, radius (spheres stand on the ground y = 0). Materials: scenes/envmap_mitsuba.tex.
SPHERES = [
    ("white", (-2.0, 0.8, 0.3), 0.8),    # diffuse 0.8 grey
    ("metal", (0.0, 0.8, -0.4), 0.8),    # smooth conductor, eta 0.2 + i 3.0 (constant): the map mirrored
    ("orange", (2.0, 0.8, 0.3), 0.8),    # diffuse orange
]
GROUND_HALF = 20.0  # the ground quad spans [-20, 20]^2 at y = 0, facing +y
SEGMENTS, RINGS = 64, 32


def environment_map():
    """The map as a float32 array (HEIGHT, WIDTH, 3)."""
    import numpy as np

    img = np.zeros((HEIGHT, WIDTH, 3), np.float32)
    for q, colour in enumerate(QUADRANTS):
        for y0, y1, k in BANDS:
            img[y0:y1, q * WIDTH // 4:(q + 1) * WIDTH // 4] = np.array(colour) * k
    (x0, x1), (y0, y1), colour = MARKER
    img[y0:y1, x0:x1] = colour
    (x0, x1), (y0, y1), scale = SUN
    img[y0 - 1:y1 + 1, x0 - 1:x1 + 1] = np.array(SUN_COLOUR) * HALO_SCALE
    img[y0:y1, x0:x1] = np.array(SUN_COLOUR) * scale
    img[HEIGHT // 2:, :WIDTH // 2] = GROUND[0]
    img[HEIGHT // 2:, WIDTH // 2:] = GROUND[1]
    return img


def meshes():
    """(name, positions, normals, triangles) of the ground and the spheres."""
    h = GROUND_HALF
    ground = ([(-h, 0.0, -h), (-h, 0.0, h), (h, 0.0, h), (h, 0.0, -h)], [(0.0, 1.0, 0.0)] * 4, [(0, 1, 2), (0, 2, 3)])
    out = [("ground",) + ground]
    for name, center, radius in SPHERES:
        positions, normals, tris = sphere(center, radius, SEGMENTS, RINGS)
        check_winding(positions, tris, center)
        out.append((name, positions, normals, tris))
    return out


def build_gltf():
    gltf = GltfMeshes(meshes())
    return {BIN_NAME: bytes(gltf.blob), GLTF_NAME: gltf.document("bench/gen_envmap_check.py", BIN_NAME)}


def read_exr_rgb(path):
    import mitsuba as mi
    import numpy as np
    if mi.variant() is None:
        mi.set_variant("scalar_rgb")
    bitmap = mi.Bitmap(path)
    names = [bitmap.struct_()[i].name for i in range(bitmap.channel_count())]
    data = np.array(bitmap, dtype=np.float32)
    return np.stack([data[..., names.index(c)] for c in "RGB"], axis=-1)


def write_exr_rgb(path, img):
    import mitsuba as mi
    import numpy as np
    if mi.variant() is None:
        mi.set_variant("scalar_rgb")
    mi.Bitmap(np.ascontiguousarray(img, dtype=np.float32), mi.Bitmap.PixelFormat.RGB).write(path)


def main():
    import numpy as np
    check = "--check" in sys.argv[1:]
    stale = update_files(SCENES, build_gltf(), check)
    img = environment_map()
    path = os.path.join(SCENES, MAP_NAME)
    if not os.path.exists(path) or not np.array_equal(read_exr_rgb(path), img):
        stale.append(MAP_NAME)
        if not check:
            write_exr_rgb(path, img)
    report_stale(stale, check, "run bench/gen_envmap_check.py with the bench venv's python")


if __name__ == "__main__":
    main()
