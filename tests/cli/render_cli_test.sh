#!/usr/bin/env bash
# End-to-end checks of `tex render` as a user runs it: 1 and 2 threads give identical files,
# the sample file develops to the same image, bad input gets a clear error and a non-zero exit
# (never a crash), and help works. Usage: render_cli_test.sh TEX SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
# expect_exit CODE DESCRIPTION CMD...: runs CMD, checks its exit status, keeps its output in $out
expect_exit() {
  local want=$1 what=$2
  shift 2
  out=$("$@" 2>&1)
  local rc=$?
  [ "$rc" = "$want" ] || fail "$what: exit $rc, expected $want: $(echo "$out" | tail -c 300)"
}

# expect_interrupted WHAT LOG IMAGE NOTE CMD...: runs CMD in the background, sends Ctrl-C (SIGINT)
# after 2 s, and checks it stops cleanly: exit 130, NOTE in its output (LOG), IMAGE written.
expect_interrupted() {
  local what=$1 log=$2 image=$3 note=$4
  shift 4
  "$@" > "$log" 2>&1 &
  local pid=$!
  sleep 2
  kill -INT "$pid"
  wait "$pid"
  local rc=$?
  [ "$rc" = 130 ] || fail "interrupted $what exited $rc, expected 130: $(cat "$log")"
  grep -q "$note" "$log" || fail "no interruption note from $what: $(cat "$log")"
  [ -s "$image" ] || fail "no partial image after Ctrl-C in $what"
}

# quad_scene OUT.json TEX_FILE ENTRY [PARAMS]: a scene of one quad whose material is a .tex entry.
quad_scene() {
  local params=${4:+, \"params\": $4}
  cat > "$1" <<JSON
{"shapes": [{"type": "quad", "size": [2, 2], "material": "W"}],
 "materials": [{"match": {"material": "W"}, "file": "$2", "entry": "$3"$params}]}
JSON
}

scene=$src/scenes/cornell-box.json
expect_exit 0 "render 1 thread" "$tex" render "$scene" --spp 2 --res 32x32 --threads 1 --seed 3 -q -o "$tmp/a.exr"
expect_exit 0 "render 2 threads" "$tex" render "$scene" --spp 2 --res 32x32 --threads 2 --seed 3 -q -o "$tmp/b.exr" --samples-out "$tmp/s.samples"
cmp -s "$tmp/a.exr" "$tmp/b.exr" || fail "1 and 2 threads wrote different EXRs"
expect_exit 0 "develop" "$tex" develop "$tmp/s.samples" --res 32x32 -o "$tmp/d.exr"
expect_exit 0 "compare" "$tex" compare --json "$tmp/a.exr" "$tmp/d.exr"
echo "$out" | grep -q '"rmse": 0[,}]' || fail "the developed sample file differs from the render: $out"
# The image-mean test: the benchmark Cornell box one bounce short (max depth 6 instead of the
# scene's 7) is 0.9 % darker in R, inside every pixel's noise, and the mean test says so; two
# seeds of the same render are consistent.
mitsuba_box=$src/scenes/cornell-box-mitsuba.json
for run in 7:1 7:2 6:3; do
  depth=${run%:*} seed=${run#*:}
  expect_exit 0 "render depth $depth seed $seed" "$tex" render "$mitsuba_box" --spp 64 --res 96x96 --max-depth "$depth" --seed "$seed" -q -o "$tmp/mean$seed.exr"
done
expect_exit 0 "compare seeds" "$tex" compare "$tmp/mean1.exr" "$tmp/mean2.exr"
echo "$out" | grep -q "image means over 64 blocks: .*(consistent within noise)" || fail "two seeds of one render: $out"
expect_exit 0 "compare depths" "$tex" compare --json "$tmp/mean1.exr" "$tmp/mean3.exr"
echo "$out" | grep -q '"ztest": {[^}]*"pass": true' || fail "the per-pixel test was expected to miss the short depth: $out"
echo "$out" | grep -q '"meantest": {[^}]*"pass": false, "verdict": "image means differ: R ' || fail "the mean test missed a bounce: $out"
for mode in mis terminate single; do
  expect_exit 0 "spectral mode $mode" "$tex" render "$src/scenes/default.json" --spp 1 --res 16x16 --spectral-mode $mode -q -o "$tmp/m.png"
done
for selection in bvh power; do
  expect_exit 0 "light sampler $selection" "$tex" render "$src/scenes/cornell-box.json" --spp 1 --res 16x16 --light-sampler $selection -q -o "$tmp/m.exr"
  grep -aq "$selection" "$tmp/m.exr" || fail "the image's metadata does not name the light sampler $selection"
done
expect_exit 0 "help" "$tex" render --help
# A crop window: the output is the window's size and records where it came from; windows
# outside the image, malformed ones, and a crop with a sample file are refused.
expect_exit 0 "crop" "$tex" render "$scene" --spp 2 --res 32x32 --crop 8,4,16,12 -q -o "$tmp/crop.exr"
expect_exit 0 "compare crop" "$tex" compare --json "$tmp/crop.exr" "$tmp/crop.exr"
echo "$out" | grep -q '"width": 16, "height": 12' || fail "the cropped render is not 16x12: $out"
expect_exit 1 "crop outside" "$tex" render "$scene" --res 32x32 --crop 20,0,16,8 -q -o "$tmp/x.exr"
echo "$out" | grep -q "reaches outside the 32x32 image" || fail "crop outside: unclear error: $out"
expect_exit 2 "crop malformed" "$tex" render "$scene" --crop 1,2,3 -q -o "$tmp/x.exr"
expect_exit 2 "crop empty" "$tex" render "$scene" --crop 0,0,0,4 -q -o "$tmp/x.exr"
expect_exit 1 "crop with samples" "$tex" render "$scene" --res 32x32 --crop 0,0,8,8 --samples-out "$tmp/c.samples" -q -o "$tmp/x.exr"
# The roulette depth reaches the path tracer: later roulette, longer paths (more rays per
# sample, from the summary's samples/s and rays/s), and the EXR records it.
rays_per_sample() {
  echo "$1" | sed -nE 's/.* ([0-9.]+) ([kM]) samples\/s, ([0-9.]+) ([kM]) rays\/s.*/\1 \2 \3 \4/p' |
    awk '{ s = $1 * ($2 == "M" ? 1e6 : 1e3); r = $3 * ($4 == "M" ? 1e6 : 1e3); printf "%.3f\n", r / s }'
}
expect_exit 0 "roulette depth 1" "$tex" render "$scene" --spp 8 --res 32x32 --roulette-depth 1 -q -o "$tmp/r1.exr"
rays1=$(rays_per_sample "$out")
expect_exit 0 "roulette depth 8" "$tex" render "$scene" --spp 8 --res 32x32 --roulette-depth 8 -q -o "$tmp/r8.exr"
rays8=$(rays_per_sample "$out")
awk -v a="$rays1" -v b="$rays8" 'BEGIN { exit !(a > 0 && b > 1.2 * a) }' ||
  fail "roulette depth 8 should trace longer paths than 1: $rays8 vs $rays1 rays per sample"
grep -aq "rouletteDepth" "$tmp/r8.exr" || fail "the EXR does not record the roulette depth"
# A time budget stops a long render early and keeps what was done.
start=$(date +%s)
expect_exit 0 "time budget" "$tex" render "$scene" --spp 100000 --res 64x64 --time 1 -q -o "$tmp/t.exr"
echo "$out" | grep -q "time budget reached" || fail "no time-budget note in the summary: $out"
[ $(( $(date +%s) - start )) -lt 20 ] || fail "--time 1 ran far past its budget"
[ -s "$tmp/t.exr" ] || fail "no image after a time-budget stop"
# Ctrl-C (SIGINT) stops cleanly: the partial image is written and the exit status is 130.
expect_interrupted render "$tmp/i.log" "$tmp/i.exr" "interrupted: partial image" \
  "$tex" render "$scene" --spp 100000 --res 64x64 -q -o "$tmp/i.exr"

# Bad flags: usage errors (exit 2) that name the problem.
expect_exit 2 "unknown flag" "$tex" render "$scene" --bogus
echo "$out" | grep -q "unknown option '--bogus'" || fail "unknown flag not named: $out"
expect_exit 2 "bad spp" "$tex" render "$scene" --spp zero
expect_exit 2 "bad resolution" "$tex" render "$scene" --res 10by10
expect_exit 2 "bad output type" "$tex" render "$scene" -o out.jpg
expect_exit 2 "bad spectral mode" "$tex" render "$scene" --spectral-mode all
expect_exit 2 "bad light sampler" "$tex" render "$scene" --light-sampler uniform
echo "$out" | grep -q "light-sampler needs bvh or power" || fail "bad light sampler not named: $out"
expect_exit 2 "bad roulette depth" "$tex" render "$scene" --roulette-depth 0
echo "$out" | grep -q "roulette-depth needs" || fail "bad roulette depth not named: $out"
# The flags take the scene file's ranges: render.seed is any 64-bit value, roulette_depth 1..65536
# (the flags had stopped at 2^63 - 1 and 1000).
expect_exit 0 "largest seed" "$tex" render "$scene" --spp 1 --res 8x8 --seed 18446744073709551615 --roulette-depth 65536 -q -o "$tmp/seed.exr"
expect_exit 2 "seed beyond 64 bits" "$tex" render "$scene" --seed 18446744073709551616
expect_exit 2 "roulette depth beyond 65536" "$tex" render "$scene" --roulette-depth 65537
# Outputs never overwrite the scene's inputs (a --samples-out named like the .glb destroyed it,
# an image named like the environment map replaced the sky), and the demo's image and sample
# file cannot share a path.
mkdir -p "$tmp/inputs"
cp "$src/scenes/envmap-mitsuba.json" "$src/scenes/envmap_mitsuba.tex" "$src/scenes"/envmap_check.* "$tmp/inputs/"
sum_before=$(cd "$tmp/inputs" && md5sum * | md5sum)
expect_exit 1 "image over the environment map" "$tex" render "$tmp/inputs/envmap-mitsuba.json" --res 8x8 --spp 1 -q -o "$tmp/inputs/envmap_check.exr"
echo "$out" | grep -q "is an input of the scene" || fail "overwriting an input not named: $out"
expect_exit 1 "samples over the .tex file" "$tex" render "$tmp/inputs/envmap-mitsuba.json" --res 8x8 --spp 1 -q -o "$tmp/inputs/ok.exr" --samples-out "$tmp/inputs/./envmap_mitsuba.tex"
expect_exit 1 "samples over the scene" "$tex" render "$tmp/inputs/envmap-mitsuba.json" --res 8x8 --spp 1 -q -o "$tmp/inputs/ok.exr" --samples-out "$tmp/inputs/envmap-mitsuba.json"
[ "$(cd "$tmp/inputs" && rm -f ok.exr && md5sum * | md5sum)" = "$sum_before" ] || fail "a scene input was changed by a refused render"
expect_exit 2 "demo image and samples on one path" "$tex" demo analytic --samples 1k --res 8x8 -q -o "$tmp/same.exr" --samples-out "$tmp/./same.exr"
# Index ranges are exact 64-bit integers (they went through a double: above 2^53 other samples ran).
expect_exit 0 "demo range above 2^53" "$tex" demo analytic --res 8x8 -q --range 9007199254740993:9007199254741001 -o "$tmp/r53.exr"
echo "$out" | grep -qF "[9007199254740993, 9007199254741001)" || fail "demo range above 2^53 not exact: $out"
expect_exit 0 "demo range at the top of 64 bits" "$tex" demo analytic --res 8x8 -q --range 18446744073709551000:18446744073709551615 -o "$tmp/r64.exr"
# An empty threshold is a usage error, not 0 (an unset shell variable).
expect_exit 2 "compare --max-rmse ''" "$tex" compare "$tmp/r53.exr" "$tmp/r53.exr" --max-rmse ""
# The convergence demo needs two sample counts for its slope (--max-log2 11 printed nan).
expect_exit 2 "demo --max-log2 11" "$tex" demo convergence --image step --res 4x4 --max-log2 11
expect_exit 2 "no scene" "$tex" render

# Bad files: errors (exit 1) naming the file, no crash.
expect_exit 1 "missing scene" "$tex" render "$tmp/none.json" -o "$tmp/x.exr"
printf '{\n  "render": {"spp": 4,,}\n}\n' > "$tmp/bad.json"
expect_exit 1 "malformed JSON" "$tex" render "$tmp/bad.json" -o "$tmp/x.exr"
echo "$out" | grep -q "bad.json:2:" || fail "malformed JSON error has no line: $out"
printf 'export fn wall(h: Hit) -> Material = diffuse(rgb(1.0, 0.0))\n' > "$tmp/broken.tex"
quad_scene "$tmp/badtex.json" broken.tex wall
expect_exit 1 "broken .tex material" "$tex" render "$tmp/badtex.json" -o "$tmp/x.exr"
echo "$out" | grep -q "broken.tex:1:" || fail "material error has no file:line: $out"
head -c 3000 "$src/scenes/cornell-box.gltf" > "$tmp/trunc.gltf"
expect_exit 1 "truncated glTF" "$tex" render "$tmp/trunc.gltf" -o "$tmp/x.exr"
head -c 100 /dev/urandom > "$tmp/noise.glb"
expect_exit 1 "garbage glb" "$tex" render "$tmp/noise.glb" -o "$tmp/x.exr"

# Found by hunting (round 12): each was a crash, lost work or a silent wrong answer.
expect_exit 1 "output directory missing" "$tex" render "$scene" --spp 1000000 --res 32x32 -q -o "$tmp/nodir/x.exr"
echo "$out" | grep -q "does not exist" || fail "a missing output directory is not reported before rendering: $out"
expect_exit 1 "develop into a missing directory" "$tex" develop "$tmp/s.samples" --res 8x8 -o "$tmp/nodir/d.exr"
expect_exit 2 "develop to .jpg" "$tex" develop "$tmp/s.samples" --res 8x8 -o "$tmp/d.jpg"
expect_exit 1 "film too large for memory" "$tex" render "$scene" --spp 1 --res 65536x65536 -q -o "$tmp/huge.exr"
echo "$out" | grep -q "out of memory" || fail "a film too large for memory is not a clear error: $out"
printf ')\n1 + 2\n' > "$tmp/repl.in"
out=$("$tex" repl < "$tmp/repl.in" 2>&1)
rc=$?
[ "$rc" -lt 128 ] || fail "repl crashed (exit $rc) on input that does not parse: $out"
echo "$out" | grep -q "3 : Int" || fail "repl did not carry on after a syntax error: $out"
quad_scene "$tmp/boolparam.json" "$src/scenes/cornell.tex" wall '{"albedo": true}'
expect_exit 1 "Bool for a Spectrum parameter" "$tex" render "$tmp/boolparam.json" --spp 1 --res 8x8 -q -o "$tmp/x.exr"
echo "$out" | grep -q "a Spectrum is needed" || fail "a Bool Spectrum parameter is not an error: $out"

printf 'fn wall(h: Hit) -> Material = diffuse(rgb(0.5))\n' > "$tmp/private.tex"
quad_scene "$tmp/private.json" private.tex wall
expect_exit 1 "entry not exported" "$tex" render "$tmp/private.json" --spp 1 --res 8x8 -q -o "$tmp/x.exr"
echo "$out" | grep -q "private.tex' defines 'wall' but does not export it" || fail "a private entry is not named: $out"

printf 'export fn wall(h: Hit) -> Material = diffuse(spectrum(0.0 / 0.0))\n' > "$tmp/nanalbedo.tex"
quad_scene "$tmp/nanalbedo.json" nanalbedo.tex wall
expect_exit 0 "NaN albedo" "$tex" render "$tmp/nanalbedo.json" --spp 1 --res 8x8 -o "$tmp/x.exr"
echo "$out" | grep -q "material evaluation failures" || fail "a NaN albedo is not reported: $out"

printf 'export fn wall(h: Hit) -> Material = diffuse(rgb(0.5))\n' > "$tmp/grey.tex"
# --max-depth 0 overrides a scene's max_depth (0 is a depth: emitters seen directly).
cat > "$tmp/depth3.json" <<JSON
{"shapes": [{"type": "quad", "size": [2, 2], "material": "W"}],
 "materials": [{"match": {"material": "W"}, "file": "$tmp/grey.tex", "entry": "wall"}],
 "render": {"max_depth": 3}}
JSON
expect_exit 0 "--max-depth 0" "$tex" render "$tmp/depth3.json" --spp 1 --res 8x8 --max-depth 0 -o "$tmp/x.exr"
echo "$out" | grep -q "max depth 0;" || fail "--max-depth 0 did not override the scene's max_depth: $out"
# A camera aspect that the image's shape overrules draws a warning.
cat > "$tmp/aspect.json" <<JSON
{"shapes": [{"type": "quad", "size": [2, 2], "material": "W"}],
 "materials": [{"match": {"material": "W"}, "file": "$tmp/grey.tex", "entry": "wall"}],
 "camera": {"from": [0, 0, 3], "aspect": 2}, "render": {"spp": 1}}
JSON
expect_exit 0 "camera aspect" "$tex" render "$tmp/aspect.json" --res 16x16 -o "$tmp/x.exr"
echo "$out" | grep -q "aspect 2 is overruled by the image's 16x16" || fail "an overruled camera aspect is not reported: $out"
expect_exit 0 "camera aspect sets the height" "$tex" render "$tmp/aspect.json" -q -o "$tmp/aspect.exr"
expect_exit 0 "compare aspect" "$tex" compare --json "$tmp/aspect.exr" "$tmp/aspect.exr"
echo "$out" | grep -q '"width": 512, "height": 256' || fail "the camera aspect did not set the height with a render object: $out"

# Cameras and geometry beyond 1e15 units are errors (Embree aborted on their ray origins).
for cam in '"from": [1e19, 0, 0]' '"type": "thinlens", "from": [0, 0, 3], "lens_radius": 1e19' '"type": "orthographic", "from": [0, 0, 3], "ymag": 1e19'; do
  cat > "$tmp/far.json" <<JSON
{"shapes": [{"type": "quad", "size": [2, 2], "material": "W"}],
 "materials": [{"match": {"material": "W"}, "file": "$tmp/grey.tex", "entry": "wall"}],
 "camera": {$cam}}
JSON
  expect_exit 1 "camera beyond range ($cam)" "$tex" render "$tmp/far.json" --spp 1 --res 8x8 -q -o "$tmp/x.exr"
  echo "$out" | grep -q "beyond 1e15 units" || fail "a camera beyond range is not a clear error ($cam): $out"
done
cat > "$tmp/huge.json" <<JSON
{"shapes": [{"type": "quad", "size": [1e18, 1e18], "material": "W"}],
 "materials": [{"match": {"material": "W"}, "file": "$tmp/grey.tex", "entry": "wall"}]}
JSON
expect_exit 1 "geometry beyond range" "$tex" render "$tmp/huge.json" --spp 1 --res 8x8 -q -o "$tmp/x.exr"
echo "$out" | grep -q "geometry reaches beyond 1e15" || fail "geometry beyond range is not a clear error: $out"

# Outputs are checked before rendering: an existing directory, or one file named twice.
mkdir -p "$tmp/adir.exr"
expect_exit 1 "output is a directory" "$tex" render "$scene" --spp 1 --res 8x8 -q -o "$tmp/adir.exr"
echo "$out" | grep -q "is a directory" || fail "an output that is a directory is not refused up front: $out"
expect_exit 2 "image and sample file on one path" "$tex" render "$scene" --spp 1 --res 8x8 -q -o "$tmp/same.exr" --samples-out "$tmp/same.exr"
echo "$out" | grep -q "given twice" || fail "one path for the image and the sample file is not refused: $out"
# A sample file that cannot be written does not cost the image.
if [ -w /dev/full ]; then
  rm -f "$tmp/kept.exr"
  expect_exit 1 "sample file on a full disk" "$tex" render "$scene" --spp 1 --res 8x8 -q -o "$tmp/kept.exr" --samples-out /dev/full
  [ -s "$tmp/kept.exr" ] || fail "the image was lost when the sample file failed: $out"
fi

# A whole number for a Color parameter broadcasts like a Float (JSON writers print 1.0 as 1).
printf 'export fn paint(h: Hit, c: Color) -> Material = diffuse(c)\n' > "$tmp/paint.tex"
quad_scene "$tmp/intcolour.json" paint.tex paint '{"c": 1}'
expect_exit 0 "Int for a Color parameter" "$tex" render "$tmp/intcolour.json" --spp 1 --res 8x8 -q -o "$tmp/x.exr"

# develop's default resolution is the render's, as the sample file records it (a non-square
# render came out stretched to 512x512).
expect_exit 0 "render 40x24 with samples" "$tex" render "$scene" --spp 2 --res 40x24 -q -o "$tmp/r40.exr" --samples-out "$tmp/r40.tsp"
expect_exit 0 "develop at the recorded size" "$tex" develop "$tmp/r40.tsp" -o "$tmp/d40.exr"
expect_exit 0 "compare recorded size" "$tex" compare --json "$tmp/r40.exr" "$tmp/d40.exr"
echo "$out" | grep -q '"width": 40, "height": 24, "rmse": 0[,}]' || fail "develop did not default to the render's 40x24: $out"

# develop refuses to merge sample files of renders that differ in their sampler.
"$tex" demo analytic --range 0:20k --samples-out "$tmp/da.tsp" -o "$tmp/da.exr" > /dev/null 2>&1
"$tex" demo analytic --range 20k:40k --sampler random --samples-out "$tmp/dr.tsp" -o "$tmp/dr.exr" > /dev/null 2>&1
expect_exit 1 "develop of two samplers" "$tex" develop "$tmp/da.tsp" "$tmp/dr.tsp" -o "$tmp/mix.exr"
echo "$out" | grep -q "the sampler differs" || fail "sample files of two samplers were merged: $out"
# ... or in their size (the first file's size had been taken for both).
"$tex" demo analytic --range 20k:40k --res 128x128 --samples-out "$tmp/ds.tsp" -o "$tmp/ds.exr" > /dev/null 2>&1
expect_exit 1 "develop of two sizes" "$tex" develop "$tmp/da.tsp" "$tmp/ds.tsp" -o "$tmp/mix.exr"
echo "$out" | grep -q "the recorded image size differs" || fail "sample files of two sizes were merged: $out"

# tex eval: Ctrl-C keeps the partial image (exit 130), as tex render does.
expect_interrupted eval "$tmp/e.log" "$tmp/eval_part.png" "interrupted" \
  "$tex" eval "$src/scenes/marble.tex" --fn marble --size 8192x8192 -o "$tmp/eval_part.png"

# develop: outputs may not collide with each other or with an input (a thumbnail named like -o
# replaced the image; -o named like the input overwrote the sample file); a bad thumbnail path is
# refused before the work; a FIFO is refused at once (develop and compare hung on one).
expect_exit 2 "develop thumbnail = -o" "$tex" develop "$tmp/r40.tsp" -o "$tmp/same.exr" --thumbnail "$tmp/same.exr"
cp "$tmp/r40.tsp" "$tmp/samples.exr"  # a sample file named .exr, as develop's output may be
expect_exit 2 "develop -o = input" "$tex" develop "$tmp/samples.exr" -o "$tmp/samples.exr"
cmp -s "$tmp/r40.tsp" "$tmp/samples.exr" || fail "develop -o = input overwrote the sample file"
expect_exit 2 "develop thumbnail .jpg" "$tex" develop "$tmp/r40.tsp" -o "$tmp/thumbless.exr" --thumbnail "$tmp/t.jpg"
[ -e "$tmp/thumbless.exr" ] && fail "develop wrote its image before refusing the thumbnail path"
mkfifo "$tmp/fifo"
expect_exit 1 "develop of a FIFO" timeout 10 "$tex" develop "$tmp/fifo" -o "$tmp/f.exr"
expect_exit 1 "compare of a FIFO" timeout 10 "$tex" compare "$tmp/fifo" "$tmp/d40.exr"

# --time 0 is refused by demo as by render (demo had run the whole range).
expect_exit 2 "demo --time 0" "$tex" demo analytic --time 0 -o "$tmp/d0.exr"

# tex eval shows a flat spectrum as exact grey (its 32-point rule had shown white as
# (1.0002, 1.0003, 0.9981)): the same grey as a Color, to float rounding.
printf 'export fn s(h: Hit) -> Spectrum = spectrum(0.75)\nexport fn c(h: Hit) -> Color = rgb(0.75, 0.75, 0.75)\n' > "$tmp/grey.tex"
"$tex" eval "$tmp/grey.tex" --fn s --size 4x4 -o "$tmp/grey_s.exr" > /dev/null 2>&1
"$tex" eval "$tmp/grey.tex" --fn c --size 4x4 -o "$tmp/grey_c.exr" > /dev/null 2>&1
expect_exit 0 "eval of a flat spectrum is grey" "$tex" compare "$tmp/grey_s.exr" "$tmp/grey_c.exr" --max-rmse 1e-6

# A definition 8002 levels deep (the most the parser allows is 8192) evaluates with the
# interpreter on TBB's workers too: their default stacks overflowed at about 4600 levels.
chain=$(printf ' + 1.0%.0s' $(seq 4000))
echo "export fn f(h: Hit) -> Float = ((h.uv.x$chain)$chain)" > "$tmp/deep.tex"
expect_exit 0 "eval --interp of a deep definition" "$tex" eval "$tmp/deep.tex" --fn f --size 4x4 --interp -o "$tmp/deep.exr"
expect_exit 0 "eval of a deep definition" "$tex" eval "$tmp/deep.tex" --fn f --size 4x4 --no-cache -o "$tmp/deep.exr"

[ "$failures" = 0 ] && echo "ok: tex render CLI" || exit 1
