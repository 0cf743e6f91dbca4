# Sourced by the scripts that run tex beside Mitsuba 3 (cornell_vs_mitsuba.sh, envmap_vs_mitsuba.sh,
# specular_vs_mitsuba.sh), from the repository's root: sets TEX (building tex with .ci/build
# unless TEX names a binary) and PY (the Python of VENV, a venv with mitsuba and numpy, created
# and filled if missing; idempotent), and defines compare_pairs.
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
