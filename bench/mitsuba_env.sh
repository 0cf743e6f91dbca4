# Sourced by the scripts that run tex beside Mitsuba 3 (cornell_vs_mitsuba.sh, envmap_vs_mitsuba.sh,
# specular_vs_mitsuba.sh), from the repository's root, after the script has set OUT: defaults
# THREADS (2) and VENV (build/bench-venv), makes OUT, sets TEX (building tex with .ci/build unless
# TEX names a binary) and PY (the Python of VENV, a venv with mitsuba and numpy, created and
# filled if missing; idempotent), and defines print_machine and compare_pairs, and for the
# region checks (specular, envmap) region_check_setup, render_tex, render_three and judge.
THREADS=${THREADS:-2}
VENV=${VENV:-build/bench-venv}
mkdir -p "$OUT"

if [[ -z "${TEX:-}" ]]; then
  echo "== building tex (bash .ci/build)"
  bash .ci/build
  TEX=build/bin/tex
fi
[[ -x "$TEX" ]] || { echo "no tex binary at $TEX" >&2; exit 1; }

if [[ ! -x "$VENV/bin/python" ]]; then
  echo "== creating $VENV"
  python3 -m venv "$VENV"
fi
if ! "$VENV/bin/python" -c 'import mitsuba, numpy' 2>/dev/null; then
  echo "== installing mitsuba and numpy into $VENV"
  "$VENV/bin/pip" install --quiet mitsuba numpy
fi
PY="$VENV/bin/python"

# print_machine: the first line of every check (cores, load, Mitsuba's version).
print_machine() {
  echo "== machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); $("$PY" -c 'import mitsuba; print("mitsuba", mitsuba.__version__)')"
}

# compare_pairs DIR "A.exr B.exr" ...: tex compare --json of each pair of images in DIR.
compare_pairs() {
  local dir=$1 pair
  shift
  for pair in "$@"; do
    set -- $pair
    echo "   tex compare $1 $2:"
    "$TEX" compare --json "$dir/$1" "$dir/$2" | sed 's/^/     /'
  done
}

# region_check_setup RES MITSUBA_SCRIPT (after SPP and THREADS are set): TEX_FLAGS, tex's render
# flags (RES, SPP, box filter, 4 wavelengths, max depth 7, roulette after 5), and MI, the Mitsuba
# script's command at SPP in 16 passes (max_depth 8, rr_depth 5): like for like.
region_check_setup() {
  local mi_depth=8                   # Mitsuba: path vertices after the camera
  local tex_depth=$((mi_depth - 1))  # tex: scattering events (scenes/cornell-box-mitsuba.json, _comment)
  local rr_depth=5
  TEX_FLAGS=(--res "$1" --threads "$THREADS" --wavelengths 4 --max-depth "$tex_depth" --roulette-depth "$rr_depth"
             --filter box --spp "$SPP" -q)
  MI=("$PY" "$2" --spp "$SPP" --pass-spp $((SPP / 16)) --threads "$THREADS" --max-depth "$mi_depth"
      --rr-depth "$rr_depth")
}

# render_tex SCENE DIR SEED: tex renders SCENE (TEX_FLAGS) to DIR/tex.exr and DIR/tex.png, timed.
render_tex() {
  SECONDS=0
  "$TEX" render "$1" -o "$2/tex.exr" -o "$2/tex.png" "${TEX_FLAGS[@]}" --seed "$3" | sed 's/^/   /'
  echo "   ($SECONDS s)"
}

# render_three SCENE DIR MODE [MITSUBA ARGS...]: render_tex with seed MODE, then Mitsuba's
# scalar_spectral and llvm_ad_spectral (MI, MITSUBA ARGS added; seeds (1 + 2 MODE) 1000 and
# (2 + 2 MODE) 1000, so that every image is an independent sample) to DIR/mitsuba_<variant>.exr,
# each timed; then tex compare of tex / llvm, tex / scalar and llvm / scalar (the control).
render_three() {
  local scene=$1 dir=$2 mode=$3 v seed
  shift 3
  render_tex "$scene" "$dir" "$mode"
  for v in scalar_spectral llvm_ad_spectral; do
    SECONDS=0
    seed=$(( ($([[ $v == scalar_spectral ]] && echo 1 || echo 2) + 2 * mode) * 1000 ))
    "${MI[@]}" --variant "$v" "$@" --seed "$seed" -o "$dir/mitsuba_$v.exr" | grep -v '^RESULT' | sed 's/^/   /'
    echo "   ($SECONDS s)"
  done
  compare_pairs "$dir" "tex.exr mitsuba_llvm_ad_spectral.exr" "tex.exr mitsuba_scalar_spectral.exr" \
    "mitsuba_llvm_ad_spectral.exr mitsuba_scalar_spectral.exr"
}

# judge LABEL SCRIPT DIR [ANALYSE ARGS...]: `SCRIPT analyse` of DIR's three images (render_three;
# region masks to DIR/regions.png); appends "LABEL: agree" to summary, or "LABEL: DISAGREE" and
# sets status=1.
judge() {
  local label=$1 script=$2 dir=$3
  shift 3
  if "$PY" "$script" analyse "$dir/tex.exr" "$dir/mitsuba_scalar_spectral.exr" "$dir/mitsuba_llvm_ad_spectral.exr" \
       "$@" --masks-out "$dir/regions.png"; then
    summary+=("$label: agree")
  else
    summary+=("$label: DISAGREE")
    status=1
  fi
}
