# Shared setup of the CLI test scripts (sourced): the binary ($tex, the first argument), the
# source tree ($src, the second), a scratch directory ($tmp, removed on exit) and `fail`, which
# counts failures for the script's final verdict.
set -uo pipefail
tex=$1
src=$(cd "$2" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
