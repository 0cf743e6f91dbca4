#!/usr/bin/env bash
# Specular transport, tex against Mitsuba 3 (bench/README.md, "Specular spheres against Mitsuba 3"):
# Mitsuba's mi.cornell_box() with its boxes replaced by a smooth glass sphere (IOR 1.5), a smooth
# conductor sphere (constant complex IOR 0.2 + 3.0i) and a small smooth glass sphere of IOR 1.33,
# rendered by both: tex from scenes/specular-mitsuba.json, Mitsuba by bench/mitsuba_specular.py
# from the same triangle meshes (scenes/specular_spheres.gltf + .bin; bench/gen_specular_spheres.py).
# 256x256, box pixel filter on both sides, spectral (4 wavelengths per path on both), Mitsuba
# max_depth 8 = tex max_depth 7, Russian roulette after 5 scattering events on both.
#
# For each shading mode (SHADINGS: the spheres' smooth vertex normals and flat face normals) it
# renders tex at SPP and Mitsuba's scalar_spectral and llvm_ad_spectral at SPP in 16 passes (their
# spread gives Mitsuba's images variance channels), then prints
#   - tex compare (RMSE, per-pixel Z-test) for tex / llvm, tex / scalar and llvm / scalar (the
#     noise-only control),
#   - image and region means per channel with standard errors, the ratios tex / Mitsuba and their
#     deviations in sigma, for the whole image, each sphere's pixels, the floor around the glass
#     sphere's caustic and the rest,
#   - the per-pixel Z-test (mean z^2, fraction of |z| > 3) per region and pair,
# and exits 1 when they disagree: a region mean of a tex pair off by more than the Sidak bound
# (family-wise false alarms 1 %), or a tex pair's Z-test clearly worse than the control's
# (bench/mitsuba_specular.py, analyse). Default run: about 8 minutes on 2 cores.
#
# Environment (all optional):
#   TEX       tex binary to use (default: build with `bash .ci/build`, use build/bin/tex)
#   VENV      Python venv with mitsuba + numpy (default build/bench-venv; created if missing)
#   OUT       output folder (default build/bench-specular)
#   SPP       samples per pixel of every image (default 1024; a multiple of 16)
#   THREADS   threads (default 2)
#   SHADINGS  shading modes to check (default "smooth flat")
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=scenes/specular-mitsuba.json
SPP=${SPP:-1024}
OUT=${OUT:-build/bench-specular}
SHADINGS=${SHADINGS:-smooth flat}
(( SPP % 16 == 0 )) || { echo "SPP must be a multiple of 16" >&2; exit 2; }

# --- tex and Mitsuba 3 (a venv, idempotent); THREADS, VENV defaults ------------------
source bench/mitsuba_env.sh

# The meshes both renderers read must be what the generator writes.
"$PY" bench/gen_specular_spheres.py --check >/dev/null
region_check_setup 256x256 bench/mitsuba_specular.py

print_machine
status=0
summary=()
for shading in $SHADINGS; do
  case $shading in
    smooth) scene=$SCENE ;;
    flat)   scene=$OUT/specular-mitsuba-flat.json
            # The same scene with the normal-less glTF (paths relative to scenes/).
            sed -e 's#"specular_spheres.gltf"#"'"$PWD"'/scenes/specular_spheres_flat.gltf"#' \
                -e 's#"specular_mitsuba.tex"#"'"$PWD"'/scenes/specular_mitsuba.tex"#' "$SCENE" >"$scene" ;;
    *) echo "unknown shading $shading (smooth, flat)" >&2; exit 2 ;;
  esac
  dir=$OUT/$shading
  mkdir -p "$dir"
  # Different seeds for the two modes, so that their images are independent samples (the rooms
  # are nearly the same image: with one seed their errors there would be the same).
  mode=$([[ $shading == smooth ]] && echo 1 || echo 2)
  echo "== $shading shading: 256x256, $SPP spp each, box filter, $THREADS threads"
  render_three "$scene" "$dir" "$mode" --shading "$shading"
  judge "$shading" bench/mitsuba_specular.py "$dir"
done
echo "== images in $OUT; verdict: ${summary[*]}"
exit $status
