#!/usr/bin/env bash
# The Cornell box, tex against Mitsuba 3, like for like (bench/README.md, "Cornell box against
# Mitsuba 3"): the same scene (scenes/cornell-box-mitsuba.json is mi.cornell_box()), 256x256,
# the same path lengths, 2 threads, spectral rendering (tex: 4 wavelengths per path; Mitsuba:
# its *_spectral variants, also 4), Gaussian pixel filter for timing (as mi.cornell_box()).
#
# 1. Timing: tex and Mitsuba's scalar_spectral and llvm_ad_spectral variants at SPP_TIME spp,
#    REPEAT times each, interleaved; the best of each is reported, in camera paths per second
#    (width * height * spp / seconds of rendering; scene loading and JIT compilation excluded),
#    with the ratios tex / Mitsuba.
# 3. Profile (PROFILE=1 and perf installed): tex's self time by component, from perf samples of
#    one timing render: Embree, material code (the JIT's code, the closure and material layer,
#    RGB upsampling), BSDFs, lights, the path loop, the sampler (samples and wavelength groups),
#    the rest.
# 2. Agreement: each renders SPP_CMP spp with a box pixel filter on both sides (FILTER_CMP;
#    tex's Gaussian has radius 1.5, Mitsuba's radius 2, which alone fails the per-pixel Z-test
#    at the image border and the light's edges); tex compare (RMSE, relative MSE, per-pixel
#    Z-test with both images' variance channels) and the image means per channel with their
#    standard errors. Mitsuba scalar against Mitsuba llvm is the noise-only control.
#
# Environment (all optional):
#   TEX       tex binary to use (default: build with `bash .ci/build`, use build/bin/tex)
#   VENV      Python venv with mitsuba + numpy (default build/bench-venv; created if missing)
#   OUT       output folder (default build/bench-cornell)
#   SPP_TIME  spp of the timing runs (default 64)     REPEAT  timing runs each (default 3)
#   SPP_CMP   spp of the comparison images (default 256)
#   FILTER_CMP  pixel filter of the comparison images: box (default) or gaussian
#   THREADS   threads (default 2)
#   RR_DEPTH  Russian roulette depth of both renderers (default 5, Mitsuba's rr_depth default)
#   PROFILE   1 (default): 3. where tex's time goes, by component (needs `perf`; skipped without)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
SCENE=scenes/cornell-box-mitsuba.json
SPP_TIME=${SPP_TIME:-64}
SPP_CMP=${SPP_CMP:-256}
REPEAT=${REPEAT:-3}
FILTER_CMP=${FILTER_CMP:-box}
OUT=${OUT:-build/bench-cornell}

# --- tex and Mitsuba 3 (a venv, idempotent); THREADS, VENV defaults ------------------
source bench/mitsuba_env.sh

# Mitsuba's max_depth counts path vertices after the camera (1 = emitters seen directly),
# tex's counts scattering events (0 = emitters seen directly): 8 there is 7 here.
MI_DEPTH=8
TEX_DEPTH=$((MI_DEPTH - 1))
# Russian roulette: Mitsuba's path integrator starts it after rr_depth scattering events (default
# 5), counted as tex's --roulette-depth; tex's own default is 3, which traces about a fifth fewer
# rays per path here. The headline uses Mitsuba's, so both sides trace paths of the same lengths.
RR_DEPTH=${RR_DEPTH:-5}
TEX_DEFAULT_RR_DEPTH=3
TEX_FLAGS=(--res 256x256 --threads "$THREADS" --wavelengths 4 --max-depth "$TEX_DEPTH" --roulette-depth "$RR_DEPTH" -q)
MI="$PY bench/mitsuba_cornell.py --rr-depth $RR_DEPTH"

# tex's summary: "... N samples (S spp) in T s, ..." -> paths/s (one camera path per sample).
tex_paths_per_s() {
  sed -nE 's/.*: ([0-9]+) samples \([^)]*\) in ([0-9.]+) s,.*/\1 \2/p' "$1" | awk '{ printf "%.1f\n", $1 / $2 }'
}
# CPU seconds / wall seconds of the whole tex process (bash's `time`; includes scene set-up).
# rays per camera path from the same summary line ("... S M samples/s, R M rays/s, ...").
tex_rays_per_path() {
  sed -nE 's/.* ([0-9.]+) ([kM]) samples\/s, ([0-9.]+) ([kM]) rays\/s.*/\1 \2 \3 \4/p' "$1" |
    awk '{ s = $1 * ($2 == "M" ? 1e6 : 1e3); r = $3 * ($4 == "M" ? 1e6 : 1e3); printf "%.2f\n", r / s }'
}
tex_cpu() { sed -nE 's/^TIME ([0-9.]+) ([0-9.]+) ([0-9.]+)$/\1 \2 \3/p' "$1" | awk '{ printf "%.3f\n", ($2 + $3) / $1 }'; }
mi_paths_per_s() { sed -nE 's/^RESULT .* paths_per_s=([0-9.]+).*/\1/p' "$1"; }
mi_cpu() { sed -nE 's/^RESULT .* cpu_utilisation=([0-9.]+).*/\1/p' "$1"; }
best() { sort -g | tail -1; }

print_machine
echo "== timing: 256x256, $SPP_TIME spp, $THREADS threads, Mitsuba max_depth $MI_DEPTH = tex max_depth $TEX_DEPTH, rr_depth = roulette depth $RR_DEPTH, best of $REPEAT"
echo "   (paths/s; in brackets CPU seconds / wall seconds: below $THREADS means other processes took CPU time)"
for r in tex texrr scalar llvm; do : >"$OUT/${r}_rates"; : >"$OUT/${r}_per_cpu"; done
for ((i = 1; i <= REPEAT; ++i)); do
  TIMEFORMAT='TIME %R %U %S'
  { time "$TEX" render "$SCENE" -o "$OUT/tex_time.exr" --spp "$SPP_TIME" --filter gaussian "${TEX_FLAGS[@]}" ; } >"$OUT/tex_time.log" 2>&1
  tex_paths_per_s "$OUT/tex_time.log" >>"$OUT/tex_rates"
  tex_cpu "$OUT/tex_time.log" >"$OUT/tex_cpu"
  awk -v r="$(tail -1 "$OUT/tex_rates")" -v c="$(cat "$OUT/tex_cpu")" 'BEGIN { printf "%.1f\n", r / c }' >>"$OUT/tex_per_cpu"
  line="   run $i: tex $(awk -v r="$(tail -1 "$OUT/tex_rates")" 'BEGIN { printf "%.3f", r / 1e6 }') M ($(cat "$OUT/tex_cpu")x, $(tex_rays_per_path "$OUT/tex_time.log") rays/path)"
  # For reference only: tex with its own default roulette depth (shorter paths, more noise).
  "$TEX" render "$SCENE" -o "$OUT/tex_time_rr.exr" --spp "$SPP_TIME" --filter gaussian "${TEX_FLAGS[@]}" \
    --roulette-depth "$TEX_DEFAULT_RR_DEPTH" >"$OUT/texrr_time.log" 2>&1
  tex_paths_per_s "$OUT/texrr_time.log" >>"$OUT/texrr_rates"
  line+=", tex at roulette depth $TEX_DEFAULT_RR_DEPTH $(awk -v r="$(tail -1 "$OUT/texrr_rates")" 'BEGIN { printf "%.3f", r / 1e6 }') M ($(tex_rays_per_path "$OUT/texrr_time.log") rays/path)"
  for v in scalar llvm; do
    variant=$([[ $v == scalar ]] && echo scalar_spectral || echo llvm_ad_spectral)
    $MI --variant "$variant" --spp "$SPP_TIME" --threads "$THREADS" --max-depth "$MI_DEPTH" >"$OUT/${v}_time.log" 2>&1
    mi_paths_per_s "$OUT/${v}_time.log" >>"$OUT/${v}_rates"
    awk -v r="$(tail -1 "$OUT/${v}_rates")" -v c="$(mi_cpu "$OUT/${v}_time.log")" 'BEGIN { printf "%.1f\n", r / c }' >>"$OUT/${v}_per_cpu"
    line+=", mitsuba $variant $(awk -v r="$(tail -1 "$OUT/${v}_rates")" 'BEGIN { printf "%.3f", r / 1e6 }') M ($(mi_cpu "$OUT/${v}_time.log")x)"
  done
  echo "$line"
done
for m in rates per_cpu; do
  awk -v t="$(best <"$OUT/tex_$m")" -v s="$(best <"$OUT/scalar_$m")" -v l="$(best <"$OUT/llvm_$m")" -v m="$m" 'BEGIN {
    what = m == "rates" ? "paths/s          " : "paths/CPU-second "
    printf "   best %s tex %.3f M | mitsuba scalar_spectral %.3f M | llvm_ad_spectral %.3f M | tex/scalar %.3f | tex/llvm %.3f\n",
      what, t/1e6, s/1e6, l/1e6, t/s, t/l }'
done
awk -v t="$(best <"$OUT/texrr_rates")" -v l="$(best <"$OUT/llvm_rates")" -v d="$TEX_DEFAULT_RR_DEPTH" 'BEGIN {
  printf "   (not like for like: tex at its default roulette depth %d, shorter paths: %.3f M paths/s, tex/llvm %.3f)\n", d, t/1e6, t/l }'

echo "== agreement: $SPP_CMP spp each, $FILTER_CMP pixel filter"
"$TEX" render "$SCENE" -o "$OUT/tex.exr" --spp "$SPP_CMP" --filter "$FILTER_CMP" "${TEX_FLAGS[@]}" | sed 's/^/   /'
# 16 passes give Mitsuba's images a variance estimate (for the Z-test and the standard errors).
PASS_SPP=$((SPP_CMP >= 16 ? SPP_CMP / 16 : 1))
for v in scalar_spectral llvm_ad_spectral; do
  $MI --variant "$v" --spp "$SPP_CMP" --pass-spp "$PASS_SPP" --threads "$THREADS" --max-depth "$MI_DEPTH" \
    --seed 1000 $([[ $FILTER_CMP == box ]] && echo --box-filter) -o "$OUT/mitsuba_$v.exr" 2>&1 | grep -v '^RESULT' | sed 's/^/   /'
done
compare_pairs "$OUT" "tex.exr mitsuba_scalar_spectral.exr" "tex.exr mitsuba_llvm_ad_spectral.exr" \
  "mitsuba_llvm_ad_spectral.exr mitsuba_scalar_spectral.exr"

# Image means per channel, their standard errors (from the variance channels; neighbouring
# pixels share samples through the filter, so these are a little optimistic) and ratios.
"$PY" - "$OUT/tex.exr" "$OUT/mitsuba_scalar_spectral.exr" "$OUT/mitsuba_llvm_ad_spectral.exr" <<'EOF'
import sys
import mitsuba as mi
import numpy as np
mi.set_variant("scalar_rgb")

def load(path):
    bitmap = mi.Bitmap(path)
    data = np.array(bitmap, dtype=np.float64)
    names = [bitmap.struct_()[i].name for i in range(bitmap.channel_count())]
    channels = {name: data[..., i] for i, name in enumerate(names)}
    mean = np.array([channels[c].mean() for c in "RGB"])
    var = [channels.get("variance." + c) for c in "RGB"]
    se = np.array([np.sqrt(v.sum()) / v.size if v is not None else np.nan for v in var])
    return mean, se

tex, tex_se = load(sys.argv[1])
print("   image means (R G B) +- standard error:")
print("     tex                      %s" % "  ".join("%.5f+-%.5f" % (m, s) for m, s in zip(tex, tex_se)))
for path, name in ((sys.argv[2], "mitsuba scalar_spectral"), (sys.argv[3], "mitsuba llvm_ad_spectral")):
    m, se = load(path)
    ratio = tex / m
    ratio_se = ratio * np.sqrt((tex_se / tex) ** 2 + (se / m) ** 2)
    print("     %-24s %s" % (name, "  ".join("%.5f+-%.5f" % (a, s) for a, s in zip(m, se))))
    print("       tex / %-20s R %.4f  G %.4f  B %.4f  (+- %.4f %.4f %.4f; deviations %s sigma)" %
          ((name.split()[1],) + tuple(ratio) + tuple(ratio_se) +
           (" ".join("%.1f" % d for d in (ratio - 1) / ratio_se),)))
EOF

if [[ "${PROFILE:-1}" == 1 ]] && command -v perf >/dev/null; then
  echo "== profile: tex at $SPP_TIME spp, $THREADS threads (perf, share of self time)"
  if perf record -q -F 2000 -o "$OUT/perf.data" "$TEX" render "$SCENE" -o "$OUT/profile.exr" --spp "$SPP_TIME" \
       "${TEX_FLAGS[@]}" >/dev/null 2>&1; then
    perf report -i "$OUT/perf.data" --no-children --sort dso,sym -g none --stdio 2>/dev/null | awk '
      /^ *[0-9.]+%/ {
        share = $1 + 0
        if ($0 ~ /embree/) part = "Embree"
        else if ($0 ~ /\[JIT\]|Material|material|evaluateEntry|evaluateBinding|[Cc]losure|tex_rt_|Sigmoid|rgbTo|Upsampling|rgbIlluminant|d65Normalised/) part = "material code"
        else if ($0 ~ /Bsdf|[Ll]obe|fresnel|Fresnel|ggx|GGX|[Mm]icrofacet|[Gg]lossy|[Ss]heen|lambertian/) part = "BSDFs"
        else if ($0 ~ /Light|light/) part = "lights"
        else if ($0 ~ /PathTracer/) part = "path loop"
        else if ($0 ~ /sampling::|Sampler|Sobol|sobol|[Ww]avelengthGroup/) part = "sampler"
        else if ($0 ~ /Film|film|xyz|Xyz|cieXyz|Sink/) part = "film"
        else if ($0 ~ /SceneGeometry|fillHit|shadingPoint/) part = "hit geometry"
        else part = "other"
        total[part] += share
      }
      END {
        n = split("Embree,material code,BSDFs,lights,path loop,sampler,hit geometry,film,other", order, ",")
        for (i = 1; i <= n; ++i) printf "   %-14s %5.1f%%\n", order[i], total[order[i]]
      }'
  else
    echo "   perf record failed (perf_event_paranoid?): skipped"
  fi
fi
echo "== images in $OUT"
