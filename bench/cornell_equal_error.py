#!/usr/bin/env python3
"""The Cornell box at equal error: how long tex and Mitsuba 3 take to reach the same noise.

Paths per second (bench/cornell_vs_mitsuba.sh) compare the cost of a sample; what a user waits
for is an image with a given error, and samplers differ in the error of a sample: tex draws its
paths from Owen-scrambled Sobol points, mi.cornell_box() from Mitsuba's independent sampler.
Both renderers are unbiased here (the agreement section of cornell_vs_mitsuba.sh), so the mean
squared error of an image at N spp is its variance, measured directly: K renders with different
seeds (for tex, different Owen scramblings), the per-pixel sample variance across them,
averaged over pixels and R, G, B. No reference image is needed.

For each renderer and N: MSE(N), the render's wall seconds t(N) (best of the K; scene loading
and JIT compilation excluded as in cornell_vs_mitsuba.sh), and the efficiency 1 / (MSE t): the
ratio of two renderers' efficiencies is the ratio of the times they need for the same error,
when MSE falls as 1/N; Sobol's falls faster at low N, so the ratio is quoted per N.

Both sides: the scene of cornell_vs_mitsuba.sh (scenes/cornell-box-mitsuba.json = mi.cornell_box()),
256x256, box pixel filter (a wider filter lowers the variance; the box is the same on both
sides), Mitsuba max_depth 8 = tex max depth 7, Russian roulette after 5 events, 4 wavelengths
a path, 2 threads. Mitsuba runs llvm_ad_spectral with its default independent sampler and with
its stratified samplers (multijitter, ldsampler), so tex's sampler is compared with Mitsuba's best.
tex also runs with --sampler random (its independent sampler) to separate sampler and speed.

Usage: cornell_equal_error.py --tex build/bin/tex [--spp 16,64,256] [--seeds 8] [--threads 2] [--out DIR]
Prints a table and RESULT lines:
    RESULT renderer=<r> spp=<n> mse=<m> seconds=<t> efficiency=<e> tex_over_it=<x>
"""
import argparse
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_common import find_libllvm  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "scenes", "cornell-box-mitsuba.json")
MI_DEPTH = 8  # Mitsuba counts path vertices after the camera, tex scattering events: 8 there is 7 here
RR_DEPTH = 5
MI_SAMPLERS = ("independent", "multijitter", "ldsampler")
SUMMARY = re.compile(r": (\d+) samples \([^)]*\) in ([0-9.]+) s,")


def variance_mse(images, np):
    """Mean over pixels and channels of the unbiased per-pixel variance across the images."""
    stack = np.stack(images).astype(np.float64)
    return float(stack.var(axis=0, ddof=1).mean())


def render_tex(args, mi, np, sampler, spp, seed):
    out = os.path.join(args.out, f"tex_{sampler}_{spp}_{seed}.exr")
    cmd = [args.tex, "render", SCENE, "-o", out, "--spp", str(spp), "--seed", str(seed), "--sampler", sampler,
           "--filter", "box", "--res", "256x256", "--threads", str(args.threads), "--wavelengths", "4",
           "--max-depth", str(MI_DEPTH - 1), "--roulette-depth", str(RR_DEPTH), "-q"]
    log = subprocess.run(cmd, check=True, capture_output=True, text=True)
    m = SUMMARY.search(log.stdout + log.stderr)
    if not m:
        raise SystemExit("no summary line from tex:\n" + log.stdout + log.stderr)
    bitmap = mi.Bitmap(out)
    rgb = np.array(bitmap, dtype=np.float64)[..., :3]
    os.remove(out)
    return rgb, float(m.group(2))


def mitsuba_scene(mi, sampler):
    desc = mi.cornell_box()
    desc["integrator"]["max_depth"] = MI_DEPTH
    desc["integrator"]["rr_depth"] = RR_DEPTH
    desc["sensor"]["film"]["rfilter"] = {"type": "box"}
    desc["sensor"]["sampler"] = {"type": sampler, "sample_count": 16}
    return mi.load_dict(desc)


def render_mitsuba(mi, np, scene, spp, seed):
    t0 = time.perf_counter()
    img = np.array(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)
    return img[..., :3], time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tex", required=True, help="tex binary")
    ap.add_argument("--spp", default="16,64,256", help="comma-separated sample counts")
    ap.add_argument("--seeds", type=int, default=8, help="renders per renderer and sample count")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "bench-equal-error"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.seeds < 2:
        raise SystemExit("--seeds must be at least 2 (the variance needs two renders)")
    spps = [int(s) for s in args.spp.split(",")]

    find_libllvm()
    import drjit as dr
    import mitsuba as mi
    import numpy as np
    mi.set_variant("llvm_ad_spectral")
    mi.set_log_level(mi.LogLevel.Warn)
    dr.set_thread_count(args.threads)

    rows = {}  # (renderer, spp) -> (mse, seconds)
    for spp in spps:
        for sampler in ("sobol", "random"):
            images, times = [], []
            for k in range(args.seeds):
                img, t = render_tex(args, mi, np, sampler, spp, 1 + k)
                images.append(img)
                times.append(t)
            rows[(f"tex {sampler}", spp)] = (variance_mse(images, np), min(times))
        for sampler in MI_SAMPLERS:
            scene = mitsuba_scene(mi, sampler)
            render_mitsuba(mi, np, scene, spp, 10**6)  # untimed: compiles this spp's kernels
            images, times = [], []
            for k in range(args.seeds):
                img, t = render_mitsuba(mi, np, scene, spp, 1 + k)
                images.append(img)
                times.append(t)
            rows[(f"mitsuba llvm {sampler}", spp)] = (variance_mse(images, np), min(times))
        print(f"   {spp} spp done", flush=True)

    print(f"== Cornell box at equal error: 256x256, box filter, {args.threads} threads, {args.seeds} seeds per row")
    print(f"   {'renderer':<28} {'spp':>5} {'MSE':>11} {'seconds':>8} {'1/(MSE s)':>11} {'tex sobol / it':>15}")
    for spp in spps:
        tex_mse, tex_s = rows[("tex sobol", spp)]
        tex_eff = 1.0 / (tex_mse * tex_s)
        for (name, n), (mse, seconds) in rows.items():
            if n != spp:
                continue
            eff = 1.0 / (mse * seconds)
            print(f"   {name:<28} {n:>5} {mse:>11.4e} {seconds:>8.3f} {eff:>11.4g} {tex_eff / eff:>15.3f}")
            print(f"RESULT renderer={name.replace(' ', '_')} spp={n} mse={mse:.6e} seconds={seconds:.4f} "
                  f"efficiency={eff:.6g} tex_over_it={tex_eff / eff:.4f}")


if __name__ == "__main__":
    main()
