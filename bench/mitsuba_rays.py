#!/usr/bin/env python3
"""What Mitsuba 3's llvm_ad_spectral variant pays per ray on its own Cornell box
(mi.cornell_box()), for comparison with bench_embree and bench_renderer: rays from points inside
the box (the central 80 % of its bounds) in uniformly distributed directions, the same kind of
pool as those benchmarks use. Times scene.ray_intersect_preliminary (Embree's hit only),
scene.ray_intersect (plus the surface interaction) and scene.ray_test (shadow-ray style) over
2^20 rays, after a first untimed round that compiles the kernels; prints ns per ray and core.

    VENV=build/bench-venv; $VENV/bin/python bench/mitsuba_rays.py [--threads 2] [--rounds 4]
(the venv is the one bench/cornell_vs_mitsuba.sh creates).
"""
import argparse
import glob
import os
import time


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--rounds", type=int, default=4, help="timed rounds after the untimed first one")
    ap.add_argument("--rays", type=int, default=1 << 20)
    args = ap.parse_args()
    if not os.environ.get("DRJIT_LIBLLVM_PATH"):
        candidates = sorted(glob.glob("/usr/lib/llvm-*/lib/libLLVM.so*"), reverse=True)
        if candidates:
            os.environ["DRJIT_LIBLLVM_PATH"] = candidates[0]
    import drjit as dr
    import mitsuba as mi

    mi.set_variant("llvm_ad_spectral")
    dr.set_thread_count(args.threads)
    scene = mi.load_dict(mi.cornell_box())
    box = scene.bbox()
    n = args.rays
    for round_index in range(args.rounds + 1):
        rng = mi.PCG32(size=n, initstate=round_index + 1)
        t = mi.Point3f(rng.next_float32(), rng.next_float32(), rng.next_float32())
        origin = box.min + (box.max - box.min) * (0.1 + 0.8 * t)
        direction = mi.warp.square_to_uniform_sphere(mi.Point2f(rng.next_float32(), rng.next_float32()))
        dr.eval(origin, direction)
        dr.sync_thread()
        ray = mi.Ray3f(origin, direction)
        seconds = []
        for query in ("preliminary", "full", "test"):
            start = time.perf_counter()
            if query == "preliminary":
                dr.eval(scene.ray_intersect_preliminary(ray).t)
            elif query == "full":
                si = scene.ray_intersect(ray)
                dr.eval(si.p, si.n, si.sh_frame.n, si.uv)
            else:
                dr.eval(scene.ray_test(ray))
            dr.sync_thread()  # Dr.Jit launches kernels asynchronously
            seconds.append(time.perf_counter() - start)
        if round_index == 0:
            continue  # kernel compilation
        per_ray = [s / n * 1e9 * args.threads for s in seconds]
        print("round %d: ns per ray and core: ray_intersect_preliminary %.1f, ray_intersect %.1f, ray_test %.1f"
              % (round_index, *per_ray))


if __name__ == "__main__":
    main()
