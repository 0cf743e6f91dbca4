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
import glob
import os
import resource
import sys
import time


def find_libllvm():
    """Dr.Jit's llvm backend loads libLLVM at run time; Debian keeps it outside the default
    search path, so point DRJIT_LIBLLVM_PATH at one (newest first) unless it is set."""
    if os.environ.get("DRJIT_LIBLLVM_PATH"):
        return
    candidates = sorted(glob.glob("/usr/lib/llvm-*/lib/libLLVM.so*"), reverse=True)
    candidates += sorted(glob.glob("/usr/lib/x86_64-linux-gnu/libLLVM*.so*"), reverse=True)
    if candidates:
        os.environ["DRJIT_LIBLLVM_PATH"] = candidates[0]


def cpu_seconds():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--variant", default="scalar_spectral", help="Mitsuba variant (scalar_spectral, llvm_ad_spectral, ...)")
    ap.add_argument("--spp", type=int, default=64, help="samples per pixel (total over all passes)")
    ap.add_argument("--pass-spp", type=int, default=0, help="spp per pass (default: all in one pass)")
    ap.add_argument("--threads", type=int, default=2, help="worker threads")
    ap.add_argument("--seed", type=int, default=0, help="seed of the first pass (pass i uses seed + i)")
    ap.add_argument("--max-depth", type=int, default=8, help="Mitsuba max_depth (default 8, as mi.cornell_box())")
    ap.add_argument("--rr-depth", type=int, default=5, help="Mitsuba rr_depth (default 5, the path integrator's default)")
    ap.add_argument("--box-filter", action="store_true", help="box pixel filter instead of cornell_box()'s gaussian")
    ap.add_argument("-o", "--output", default="", help="EXR to write (optional)")
    args = ap.parse_args()

    if args.variant.startswith("llvm"):
        find_libllvm()
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    mi.set_log_level(mi.LogLevel.Warn)
    # Mitsuba 3 renders image blocks (scalar variants) and runs its llvm kernels on Dr.Jit's
    # thread pool; older releases also had mi.Thread.set_thread_count for the former.
    dr.set_thread_count(args.threads)
    if hasattr(mi.Thread, "set_thread_count"):
        mi.Thread.set_thread_count(args.threads)

    desc = mi.cornell_box()
    desc["integrator"]["max_depth"] = args.max_depth
    desc["integrator"]["rr_depth"] = args.rr_depth
    if args.box_filter:
        desc["sensor"]["film"]["rfilter"] = {"type": "box"}
    film = desc["sensor"]["film"]
    width, height = film["width"], film["height"]

    t0 = time.perf_counter()
    scene = mi.load_dict(desc)
    load_s = time.perf_counter() - t0

    pass_spp = args.pass_spp if args.pass_spp > 0 else args.spp
    if args.spp % pass_spp:
        sys.exit("--spp must be a multiple of --pass-spp")
    passes = args.spp // pass_spp

    # Warm-up: same settings as a timed pass (so the llvm kernels are compiled), another seed.
    t0 = time.perf_counter()
    warm_spp = pass_spp if args.variant.startswith("llvm") else 1
    np.array(mi.render(scene, spp=warm_spp, seed=10**6 + args.seed))
    warm_s = time.perf_counter() - t0

    total = None
    total_sq = None
    cpu0, t0 = cpu_seconds(), time.perf_counter()
    for i in range(passes):
        img = np.array(mi.render(scene, spp=pass_spp, seed=args.seed + i), dtype=np.float64)
        total = img if total is None else total + img
        sq = img * img
        total_sq = sq if total_sq is None else total_sq + sq
    seconds = time.perf_counter() - t0
    cpu = cpu_seconds() - cpu0

    mean = total / passes
    paths = width * height * args.spp
    paths_per_s = paths / seconds
    print(f"mitsuba {mi.__version__} {args.variant}: {width}x{height}, {args.spp} spp "
          f"({passes} pass(es) of {pass_spp}), max_depth {args.max_depth}, rr_depth {args.rr_depth}, {args.threads} threads: "
          f"{seconds:.2f} s, {paths_per_s / 1e6:.3f} M paths/s "
          f"(scene load {load_s:.2f} s, warm-up {warm_s:.2f} s untimed; CPU {cpu / seconds:.2f}x wall); "
          f"mean RGB {mean[..., 0].mean():.5f} {mean[..., 1].mean():.5f} {mean[..., 2].mean():.5f}")
    print(f"RESULT variant={args.variant} spp={args.spp} threads={args.threads} seconds={seconds:.4f} "
          f"paths_per_s={paths_per_s:.1f} cpu_utilisation={cpu / seconds:.3f}")

    if args.output:
        channels = [mean[..., 0], mean[..., 1], mean[..., 2]]
        names = ["R", "G", "B"]
        if passes >= 2:
            # Variance of the mean of `passes` independent pass images (unbiased sample variance / passes).
            var_pass = np.maximum(total_sq / passes - mean * mean, 0.0) * passes / (passes - 1)
            channels += [var_pass[..., k] / passes for k in range(3)]
            names += ["variance.R", "variance.G", "variance.B"]
        data = np.ascontiguousarray(np.stack(channels, axis=-1).astype(np.float32))
        bitmap = mi.Bitmap(data, mi.Bitmap.PixelFormat.MultiChannel, names)
        bitmap.write(args.output)


if __name__ == "__main__":
    main()
