#!/usr/bin/env python3
"""Renders Mitsuba 3's built-in Cornell box (mi.cornell_box(): 256x256, path integrator,
max_depth 8) with a given spp and thread count, times the render alone, and writes an EXR.

The timed part is mi.render() plus reading the image back (which, in the llvm variants, is
where the kernel runs). Scene loading and JIT compilation are not timed: before the timed
render the script renders once untimed with the same settings and another seed, so the
llvm kernels are compiled and cached (Dr.Jit's kernel cache is keyed by the IR, which
contains the wavefront size and spp) and the scalar variant has touched all its data.

The spp may be split into passes (--pass-spp) with different seeds; the image is their
mean, and with 2 or more passes the EXR also gets variance.R/G/B channels (the variance of
that mean, estimated from the spread of the passes) so `tex compare` can run its Z-test.

Prints a human line and one machine-readable line:
    RESULT variant=<v> spp=<n> threads=<t> seconds=<s> paths_per_s=<p> cpu_utilisation=<u>
(paths = width * height * spp camera paths; cpu_utilisation = process CPU seconds / wall
seconds during the timed render, about equal to the thread count when all threads work).
"""
import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_common import Passes, add_render_arguments, load_scene, pass_count, start_mitsuba  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_render_arguments(ap)
    ap.add_argument("--box-filter", action="store_true", help="box pixel filter instead of cornell_box()'s gaussian")
    args = ap.parse_args()
    dr, mi, np = start_mitsuba(args)

    desc = mi.cornell_box()
    desc["integrator"]["max_depth"] = args.max_depth
    desc["integrator"]["rr_depth"] = args.rr_depth
    if args.box_filter:
        desc["sensor"]["film"]["rfilter"] = {"type": "box"}
    scene, width, height, load_s = load_scene(mi, desc)

    # Warm-up: same settings as a timed pass (so the llvm kernels are compiled), another seed.
    pass_spp, _ = pass_count(args)
    t0 = time.perf_counter()
    warm_spp = pass_spp if args.variant.startswith("llvm") else 1
    np.array(mi.render(scene, spp=warm_spp, seed=10**6 + args.seed))
    warm_s = time.perf_counter() - t0

    passes = Passes(mi, np, scene, args)
    mean, seconds, cpu = passes.mean, passes.seconds, passes.cpu
    paths = width * height * args.spp
    paths_per_s = paths / seconds
    print(f"mitsuba {mi.__version__} {args.variant}: {width}x{height}, {args.spp} spp "
          f"({passes.count} pass(es) of {pass_spp}), max_depth {args.max_depth}, rr_depth {args.rr_depth}, {args.threads} threads: "
          f"{seconds:.2f} s, {paths_per_s / 1e6:.3f} M paths/s "
          f"(scene load {load_s:.2f} s, warm-up {warm_s:.2f} s untimed; CPU {cpu / seconds:.2f}x wall); "
          f"mean RGB {mean[..., 0].mean():.5f} {mean[..., 1].mean():.5f} {mean[..., 2].mean():.5f}")
    print(f"RESULT variant={args.variant} spp={args.spp} threads={args.threads} seconds={seconds:.4f} "
          f"paths_per_s={paths_per_s:.1f} cpu_utilisation={cpu / seconds:.3f}")
    if args.output:
        passes.write_exr(mi, np, args.output)


if __name__ == "__main__":
    main()
