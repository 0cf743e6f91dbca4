"""What bench/mitsuba_cornell.py, bench/mitsuba_specular.py and bench/mitsuba_envmap.py share: finding libLLVM for
Dr.Jit's llvm backend, the render options they take, starting Mitsuba with a variant and a thread
count, rendering in passes with different seeds (the image is their mean; with 2 or more passes
the spread of the passes gives the variance of that mean), and writing the result as an EXR
with variance.R/G/B channels for `tex compare`'s Z-test; for the specular and envmap checks also
the render-and-report step and their `analyse` (region means, per-pixel Z-tests, verdict)."""
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
        # Mitsuba 3.9's EXR writer waits on Dr.Jit's thread pool: with one thread (--threads 1)
        # write() never returned. The timing is over, so the pool may grow for the write.
        import drjit as dr
        if dr.thread_count() < 2:
            dr.set_thread_count(2)
        mi.Bitmap(data, mi.Bitmap.PixelFormat.MultiChannel, names).write(path)


def render_and_report(mi, np, scene, args, width, height, load_s, settings):
    """Renders the passes (Passes), prints a human line (settings: what to say about the scene
    after the thread count) and the machine-readable
        RESULT variant=<v> spp=<n> threads=<t> seconds=<s> paths_per_s=<p>
    and writes args.output (if given) with variance channels."""
    pass_spp, _ = pass_count(args)
    passes = Passes(mi, np, scene, args)
    mean, seconds = passes.mean, passes.seconds
    paths_per_s = width * height * args.spp / seconds
    print(f"mitsuba {mi.__version__} {args.variant}: {width}x{height}, {args.spp} spp "
          f"({passes.count} pass(es) of {pass_spp}), max_depth {args.max_depth}, rr_depth {args.rr_depth}, "
          f"{args.threads} threads, {settings}: {seconds:.1f} s (+ scene load {load_s:.2f} s), "
          f"{paths_per_s / 1e6:.3f} M paths/s; "
          f"mean RGB {mean[..., 0].mean():.5f} {mean[..., 1].mean():.5f} {mean[..., 2].mean():.5f}")
    print(f"RESULT variant={args.variant} spp={args.spp} threads={args.threads} seconds={seconds:.4f} "
          f"paths_per_s={paths_per_s:.1f}")
    if args.output:
        passes.write_exr(mi, np, args.output)


def load_exr_with_variance(path):
    """(mean, variance) of an EXR with R/G/B and variance.R/G/B channels (as tex and
    Passes.write_exr write them), both float64 arrays (height, width, 3). Needs a variant set."""
    import mitsuba as mi
    import numpy as np
    bitmap = mi.Bitmap(path)
    data = np.array(bitmap, dtype=np.float64)
    names = [bitmap.struct_()[i].name for i in range(bitmap.channel_count())]
    ch = {name: data[..., i] for i, name in enumerate(names)}
    mean = np.stack([ch[c] for c in "RGB"], axis=-1)
    var = np.stack([ch["variance." + c] for c in "RGB"], axis=-1)
    return mean, var


def compare_regions(images, masks, info_regions=(), alpha=0.01, tolerances=None):
    """Region means and per-pixel Z-tests of images {"tex", "scalar", "llvm"} -> (mean, variance)
    over masks {region name -> bool array}, printed, with the verdict of the specular check
    (bench/README.md): a region-channel mean of a tex pair (tex/llvm, tex/scalar) off by more than
    the Sidak bound for family-wise rate alpha, or a tex pair's per-pixel Z-test worse than the
    Mitsuba-only control (llvm/scalar) by more than noise allows (mean z^2 above 1.25 x + 0.1 of
    the control's, or more than 2 x + 0.5 % of pixel channels past 3 sigma), is a failure. Regions
    in info_regions are printed but neither counted in the bound nor judged. tolerances (optional,
    {region: relative tolerance}) adds a stated systematic allowance to a region's mean test: its
    deviations are in units of sqrt(se_a^2 + se_b^2 + (tolerance x mean_b)^2). Returns the failures
    (a list of strings; empty: agreement)."""
    import numpy as np
    from statistics import NormalDist

    pairs = [("tex", "llvm"), ("tex", "scalar"), ("llvm", "scalar")]  # the last is the control
    judged = [r for r in masks if r not in info_regions]
    tests = len(judged) * 3 * 2  # the region-channel mean tests of the two tex pairs
    z_crit = NormalDist().inv_cdf(1 - (1 - (1 - alpha) ** (1 / tests)) / 2)
    labels = {"tex": "tex", "scalar": "mitsuba scalar_spectral", "llvm": "mitsuba llvm_ad_spectral"}
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
        return float(np.mean(z * z)) if z.size else 0.0, float(np.mean(np.abs(z) > 3)) if z.size else 0.0

    print("   region means (R G B) +- standard error; ratio tex / Mitsuba and its deviation in sigma")
    info_note = "; regions marked 'info' are not judged" if info_regions else ""
    print(f"   (pass: every |deviation| of a tex pair <= {z_crit:.2f} sigma, the Sidak bound for {tests} tests "
          f"at family-wise {alpha:g}{info_note})")
    tolerances = tolerances or {}
    for region in masks:
        mask = masks[region]
        info = region in info_regions
        tol = tolerances.get(region, 0.0)
        print(f"   {region} ({mask.sum()} pixels){' (info)' if info else ''}"
              f"{f' (systematic tolerance {100 * tol:g} % in the deviations)' if tol else ''}:")
        if not mask.any():
            continue
        stats = {k: mean_se(k, mask) for k in images}
        for k in images:
            m, se = stats[k]
            print("     %-24s %s" % (labels[k], "  ".join("%.5f+-%.5f" % (a, s) for a, s in zip(m, se))))
        for a, b in pairs:
            (ma, sa), (mb, sb) = stats[a], stats[b]
            ratio = ma / mb
            dev = (ma - mb) / np.sqrt(sa * sa + sb * sb + (tol * mb) ** 2)
            rse = ratio * np.sqrt((sa / ma) ** 2 + (sb / mb) ** 2)
            control = a != "tex"
            bad = (not control) and (not info) and bool(np.any(np.abs(dev) > z_crit))
            if bad:
                failures.append(f"{region}: {a}/{b} deviations {' '.join('%.1f' % x for x in dev)} sigma")
            print("       %-13s R %.4f  G %.4f  B %.4f  (+- %.4f %.4f %.4f)  deviation %5.1f %5.1f %5.1f sigma%s" %
                  ((f"{a}/{b}",) + tuple(ratio) + tuple(rse) + tuple(dev) +
                   ("  (control)" if control else "  FAIL" if bad else "",)))

    print("   per-pixel Z-test (z = difference / sqrt(sum of variances), every pixel channel):")
    print("     %-26s %-12s %s" % ("region", "pair", "mean z^2   |z|>3"))
    ztab = {}
    for region in masks:
        for a, b in pairs:
            zz, out = ztest(a, b, masks[region])
            ztab[(region, a, b)] = (zz, out)
            print("     %-26s %-12s %7.3f  %7.3f %%%s" % (region, f"{a}/{b}", zz, 100 * out,
                                                       "  (info)" if region in info_regions else ""))
    for region in judged:
        czz, cout = ztab[(region, "llvm", "scalar")]
        for a, b in pairs[:2]:
            zz, out = ztab[(region, a, b)]
            if zz > 1.25 * czz + 0.1 or out > 2 * cout + 0.005:
                failures.append(f"{region}: Z-test {a}/{b} mean z^2 {zz:.3f}, |z|>3 {100 * out:.2f} % "
                                f"against the control's {czz:.3f}, {100 * cout:.2f} %")
    return failures


def add_analyse_arguments(ap):
    """The arguments every `analyse` takes: the three images, --alpha, --masks-out."""
    ap.add_argument("tex")
    ap.add_argument("scalar")
    ap.add_argument("llvm")
    ap.add_argument("--alpha", type=float, default=0.01,
                    help="family-wise false-alarm rate of the region mean tests (Sidak-corrected; default 0.01)")
    ap.add_argument("--masks-out", default="", help="write the region masks as a PNG (optional)")


def analyse_regions(args, region_masks, colours, agreement, **compare_args):
    """`analyse` of the specular and envmap checks: loads args.tex, args.scalar and args.llvm (EXRs
    with variance channels), takes the regions from region_masks(width, height) (called with the
    scalar_rgb variant set), writes them to args.masks_out (if given) as a PNG in colours
    ({region: RGB}; other regions black), runs compare_regions (compare_args: info_regions,
    tolerances) with args.alpha and prints the verdict (agreement: the line printed when there are
    no failures). Returns the exit status: 0 agreement, 1 disagreement."""
    import mitsuba as mi
    import numpy as np
    mi.set_variant("scalar_rgb")

    images = {k: load_exr_with_variance(getattr(args, k)) for k in ("tex", "scalar", "llvm")}
    h, w = images["tex"][0].shape[:2]
    masks = region_masks(w, h)
    if args.masks_out:
        img = np.zeros((h, w, 3), np.float32)
        for name, col in colours.items():
            img[masks[name]] = col
        mi.util.write_bitmap(args.masks_out, img)
    failures = compare_regions(images, masks, alpha=args.alpha, **compare_args)
    if failures:
        print("   DISAGREEMENT:")
        for f in failures:
            print("     " + f)
        return 1
    print("   agreement: " + agreement)
    return 0
