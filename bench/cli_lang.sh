#!/usr/bin/env bash
# Timed CLI runs for the language issue: `tex check` on a generated 10,000-line module and a
# piped REPL line, each as a whole process (median of 5). Run from the project root after building.
set -euo pipefail
tex=${TEX:-build/bin/tex}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
python3 - "$tmp/gen.tex" <<'PY'
import sys
lines = []
i = 0
while len(lines) < 10000:
    lines += [f"fn g{i}(x, s) =", f"  let y = x * s + {i}.0 in", "  if y > 1.0 { y - 1.0 } else { y * y }",
              f"export fn f{i}(h: Hit) -> Float =", f"  g{i}(h.uv.x, 2) + g{i}(h.uv.y, 0.5)"]
    i += 1
open(sys.argv[1], "w").write("\n".join(lines) + "\n")
PY
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
time_ms() { local s e; s=$(date +%s%N); "$@" >/dev/null 2>&1 || true; e=$(date +%s%N); echo $(( (e - s) / 1000000 )); }
check_ms=$(for i in 1 2 3 4 5; do time_ms "$tex" check "$tmp/gen.tex"; done | median)
repl_ms=$(for i in 1 2 3 4 5; do time_ms bash -c "echo '1 + 2' | $tex repl"; done | median)
repl_std_ms=$(for i in 1 2 3 4 5; do time_ms bash -c "printf 'import std.noise.{fbm, perlin}\nfbm(6, |q| abs(perlin(q)), hit.p * 4.0)\n' | $tex repl"; done | median)
echo "tex check, 10,000-line module (process):         ${check_ms} ms  (target < 200 ms)"
echo "echo '1 + 2' | tex repl (process):                ${repl_ms} ms  (target < 50 ms)"
echo "repl: import std.noise + fbm line (process):      ${repl_std_ms} ms"
