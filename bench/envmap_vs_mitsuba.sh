#!/usr/bin/env bash
# Image-based lighting, tex against Mitsuba 3 (bench/README.md, "Environment map against Mitsuba 3"):
# an open scene lit only by an OpenEXR latitude-longitude map (scenes/envmap_check.exr, 256 x 128,
# asymmetric: four coloured azimuth quadrants, elevation bands, a marker stripe, a small warm sun,
# a two-coloured ground) with importance sampling: a grey ground quad, a white and an orange diffuse
# sphere and a smooth conductor sphere that shows the map mirrored. tex renders
# scenes/envmap-mitsuba.json, Mitsuba bench/mitsuba_envmap.py (same triangles as PLY; its envmap gets a
# node grid resampled from the map so that its bilinear interpolation is tex's piecewise-constant map
# up to antisymmetric bands at colour edges). 256x192, box pixel filter, spectral (4 wavelengths per
# path on both), Mitsuba max_depth 8 = tex max_depth 7, Russian roulette after 5 scattering events.
#
# For each configuration (CONFIGS: "identity", the map as stored; "rotated", the environment rotated
# by ROTATE = ax,ay,az,deg on both sides, tex's "transform" and Mitsuba's to_world) it renders tex at
# SPP and Mitsuba's scalar_spectral and llvm_ad_spectral at SPP in 16 passes (their spread gives
# Mitsuba's images variance channels), then prints
#   - tex compare (RMSE, per-pixel Z-test) for tex / llvm, tex / scalar and llvm / scalar (the
#     noise-only control) over the whole image (the sky's colour edges included),
#   - region means per channel with standard errors, ratios tex / Mitsuba and deviations in sigma:
#     ground, each sphere, the sky seen directly where a pixel's footprint sees one map colour (with
#     a stated 0.2 % systematic tolerance: the two renderers' RGB round trips of a map colour differ
#     by up to 0.1 %), all but the sky's edges; and the sky pixels near colour edges (reported, not
#     judged: Mitsuba interpolates there, tex does not),
#   - the per-pixel Z-test (mean z^2, fraction of |z| > 3) per region and pair,
# and exits 1 when they disagree (bench/mitsuba_envmap.py analyse: a judged region mean of a tex pair
# off by more than the Sidak bound, family-wise false alarms 1 %, or a tex pair's Z-test clearly
# worse than the control's). Before rendering, `mitsuba_envmap.py probe` checks Mitsuba's envmap
# mapping (and to_world) against the node model the resampling assumes.
#
# SENSITIVITY (default "mirror rot90 sun"): after the configurations, renders tex with a deliberately
# wrong map against the identity configuration's Mitsuba images: "mirror" the map flipped left-right
# (u -> 1 - u), "rot90" the environment rotated 90 deg about +y on the tex side only, "flip" the map
# upside down, "scale" the whole map 2 % brighter, "sun" the sun (not its halo) 10 % brighter. Each
# must DISAGREE; one that passes makes the script exit 1 (the check would be blind to it). Needs
# "identity" in CONFIGS (or its images from an earlier run in OUT).
#
# Default run: about 6 minutes on 2 cores.
#
# Environment (all optional):
#   TEX          tex binary to use (default: build with `bash .ci/build`, use build/bin/tex)
#   VENV         Python venv with mitsuba + numpy (default build/bench-venv; created if missing)
#   OUT          output folder (default build/bench-envmap)
#   SPP          samples per pixel of every image (default 1024; a multiple of 16)
#   THREADS      threads (default 2)
#   CONFIGS      configurations (default "identity rotated"; "none" for only SENSITIVITY)
#   ROTATE       the rotated configuration's rotation (default 1,0.5,0,40)
#   SENSITIVITY  wrong-map renders of tex that must be caught (default "mirror rot90 sun"; "" for none)
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=scenes/envmap-mitsuba.json
SPP=${SPP:-1024}
OUT=${OUT:-build/bench-envmap}
CONFIGS=${CONFIGS:-identity rotated}
ROTATE=${ROTATE:-1,0.5,0,40}
SENSITIVITY=${SENSITIVITY-mirror rot90 sun}
(( SPP % 16 == 0 )) || { echo "SPP must be a multiple of 16" >&2; exit 2; }

# --- tex and Mitsuba 3 (a venv, idempotent); THREADS, VENV defaults ------------------
source bench/mitsuba_env.sh

# The map and meshes both renderers read must be what the generator writes.
"$PY" bench/gen_envmap_check.py --check >/dev/null
print_machine
echo "== Mitsuba's envmap mapping against the node model (mitsuba_envmap.py probe)"
"$PY" bench/mitsuba_envmap.py probe --env-rotate "$ROTATE"

region_check_setup 256x192 bench/mitsuba_envmap.py

# scene_with OUTFILE TRANSFORM_JSON [MAP]: the scene with absolute paths, the environment's
# "transform" (or none for "") and optionally another map.
scene_with() {
  local out=$1 transform=$2 map=${3:-$PWD/scenes/envmap_check.exr}
  "$PY" - "$SCENE" "$out" "$transform" "$map" "$PWD/scenes" <<'EOF'
import json, sys
src, out, transform, image, scenes = sys.argv[1:]
doc = json.load(open(src))
doc["gltf"] = [scenes + "/" + g for g in doc["gltf"]]
for m in doc["materials"]:
    m["file"] = scenes + "/" + m["file"]
light = doc["lights"][0]
light["image"] = image
if transform:
    light["transform"] = json.loads(transform)
json.dump(doc, open(out, "w"), indent=1)
EOF
}
rotate_json() { echo "{\"rotate\": [$1]}"; }

status=0
summary=()
for config in $CONFIGS; do
  case $config in
    none)     continue ;;
    identity) rot="" ;;
    rotated)  rot=$ROTATE ;;
    *) echo "unknown configuration $config (identity, rotated)" >&2; exit 2 ;;
  esac
  dir=$OUT/$config
  mkdir -p "$dir"
  scene=$dir/scene.json
  scene_with "$scene" "$([[ -n $rot ]] && rotate_json "$rot" || true)"
  mode=$([[ $config == identity ]] && echo 1 || echo 2)
  echo "== $config${rot:+ (environment rotate $rot)}: 256x192, $SPP spp each, box filter, $THREADS threads"
  render_three "$scene" "$dir" "$mode" --env-rotate "$rot"
  judge "$config" bench/mitsuba_envmap.py "$dir" --env-rotate "$rot"
done

# --- sensitivity: tex with a wrong map must disagree with the identity images -------------
for case in $SENSITIVITY; do
  ref=$OUT/identity
  [[ -f $ref/mitsuba_llvm_ad_spectral.exr && -f $ref/mitsuba_scalar_spectral.exr ]] ||
    { echo "SENSITIVITY needs the identity configuration's Mitsuba images in $ref" >&2; exit 2; }
  dir=$OUT/sensitivity-$case
  mkdir -p "$dir"
  transform="" map=""
  case $case in
    mirror|flip|scale|sun)
      map=$(cd "$dir" && pwd)/envmap.exr
      "$PY" - "$case" "$map" <<'EOF'
import sys
sys.path.insert(0, "bench")
from gen_envmap_check import SUN, environment_map, write_exr_rgb
case, out = sys.argv[1:]
img = environment_map()
if case == "sun":  # the sun (not its halo) 10 % brighter: what the diffuse regions see of the sampled sun
    (x0, x1), (y0, y1), _ = SUN
    img[y0:y1, x0:x1] *= 1.1
else:
    img = {"mirror": img[:, ::-1], "flip": img[::-1], "scale": img * 1.02}[case]
write_exr_rgb(out, img)
EOF
      ;;
    rot90) transform=$(rotate_json "0,1,0,90") ;;
    *) echo "unknown sensitivity case $case (mirror, rot90, flip, scale, sun)" >&2; exit 2 ;;
  esac
  scene_with "$dir/scene.json" "$transform" "${map:-}"
  echo "== sensitivity $case: tex with the wrong map against the identity configuration's Mitsuba images"
  render_tex "$dir/scene.json" "$dir" 3
  compare_pairs "$OUT" "sensitivity-$case/tex.exr identity/mitsuba_llvm_ad_spectral.exr"
  if "$PY" bench/mitsuba_envmap.py analyse "$dir/tex.exr" "$ref/mitsuba_scalar_spectral.exr" \
       "$ref/mitsuba_llvm_ad_spectral.exr"; then
    summary+=("sensitivity $case: NOT CAUGHT")
    status=1
  else
    summary+=("sensitivity $case: caught")
  fi
done
echo "== images in $OUT; verdict: ${summary[*]}"
exit $status
