"""What bench/mitsuba_cornell.py and bench/mitsuba_specular.py share: finding libLLVM for
Dr.Jit's llvm backend, the render options both take, starting Mitsuba with a variant and a thread
count, rendering in passes with different seeds (the image is their mean; with 2 or more passes
the spread of the passes gives the variance of that mean), and writing the result as an EXR
with variance.R/G/B channels for `tex compare`'s Z-test."""
import glob
import os
import resource
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


def add_render_arguments(ap):
    ap.add_argument("--variant", default="scalar_spectral", help="Mitsuba variant (scalar_spectral, llvm_ad_spectral, ...)")
    ap.add_argument("--spp", type=int, default=64, help="samples per pixel (total over all passes)")
    ap.add_argument("--pass-spp", type=int, default=0, help="spp per pass (default: all in one pass)")
    ap.add_argument("--threads", type=int, default=2, help="worker threads")
    ap.add_argument("--seed", type=int, default=0, help="seed of the first pass (pass i uses seed + i)")
    ap.add_argument("--max-depth", type=int, default=8, help="Mitsuba max_depth (default 8, as mi.cornell_box())")
    ap.add_argument("--rr-depth", type=int, default=5, help="Mitsuba rr_depth (default 5, the path integrator's default)")
    ap.add_argument("-o", "--output", default="", help="EXR to write (optional)")


def start_mitsuba(args):
    """Imports Mitsuba with args.variant and args.threads; returns (dr, mi, np)."""
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
    return dr, mi, np


def load_scene(mi, desc):
    """mi.load_dict(desc), timed: (scene, film width, film height, seconds)."""
    film = desc["sensor"]["film"]
    t0 = time.perf_counter()
    scene = mi.load_dict(desc)
    return scene, film["width"], film["height"], time.perf_counter() - t0


def pass_count(args):
    pass_spp = args.pass_spp if args.pass_spp > 0 else args.spp
    if args.spp % pass_spp:
        raise SystemExit("--spp must be a multiple of --pass-spp")
    return pass_spp, args.spp // pass_spp


class Passes:
    """The passes' sum and sum of squares (float64), their wall and CPU seconds."""

    def __init__(self, mi, np, scene, args):
        pass_spp, self.count = pass_count(args)
        self.pass_spp = pass_spp
        self.total = None
        self.total_sq = None
        cpu0, t0 = cpu_seconds(), time.perf_counter()
        for i in range(self.count):
            img = np.array(mi.render(scene, spp=pass_spp, seed=args.seed + i), dtype=np.float64)
            self.total = img if self.total is None else self.total + img
            sq = img * img
            self.total_sq = sq if self.total_sq is None else self.total_sq + sq
        self.seconds = time.perf_counter() - t0
        self.cpu = cpu_seconds() - cpu0
        self.mean = self.total / self.count

    def write_exr(self, mi, np, path):
        mean, passes = self.mean, self.count
        channels = [mean[..., 0], mean[..., 1], mean[..., 2]]
        names = ["R", "G", "B"]
        if passes >= 2:
            # Variance of the mean of `passes` independent pass images (unbiased sample variance / passes).
            var_pass = np.maximum(self.total_sq / passes - mean * mean, 0.0) * passes / (passes - 1)
            channels += [var_pass[..., k] / passes for k in range(3)]
            names += ["variance.R", "variance.G", "variance.B"]
        data = np.ascontiguousarray(np.stack(channels, axis=-1).astype(np.float32))
        mi.Bitmap(data, mi.Bitmap.PixelFormat.MultiChannel, names).write(path)
