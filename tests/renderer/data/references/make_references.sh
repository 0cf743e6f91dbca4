#!/usr/bin/env bash
# Renders the reference image of every shared glTF model (../shared/gltf, next to the
# repository) for tests/renderer/gltf_reference_test.cpp: 48x48, 256 spp, seed 1, max depth 6,
# 4 wavelengths, box filter, with variance channels. Re-run after a deliberate change to how
# glTF models render, look at the differences, and commit the new images with the change.
set -euo pipefail
cd "$(dirname "$0")"
root=../../../..
tex=${TEX:-$root/build/bin/tex}
shared=$root/../shared/gltf
for model in $(cd "$shared" && ls -d */ | tr -d /); do
  file=$(ls "$shared/$model"/glTF-Binary/*.glb "$shared/$model"/glTF/*.gltf "$shared/$model"/*.gltf 2>/dev/null | head -1 || true)
  [ -n "$file" ] || continue
  "$tex" render "$file" --res 48x48 --spp 256 --seed 1 --max-depth 6 --wavelengths 4 --filter box -q -o "$model.exr" >/dev/null 2>&1
  echo "$model.exr"
done
