#!/usr/bin/env bash
# The main job, as far as the code goes today: generate the default model (the procedural
# mannequin), inspect it, bind it to its control sweeps, pose, render and position-map it with a
# CMU clip, and inspect the shared real model and motion clip when present.
# The daemon issue turns this into "start sweepd, stream poses to it".
set -euo pipefail
build=${1:-build/release}
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
sweepctl="$build/cli/sweepctl"
out=out/demo
mkdir -p "$out"

echo "== 1. default model: the procedural mannequin"
"$sweepctl" mannequin --vertices 20000 -o "$out/mannequin.glb"
"$sweepctl" inspect "$out/mannequin.glb" | head -n 14
echo
echo "== 2. bind it to its control sweeps (paper section 3)"
"$sweepctl" bind "$out/mannequin.glb" -o "$out/mannequin.sweepbind" | grep -E "^(bound|sweep|skinned|rest|wrote)"

shared=../shared/data
clip=$shared/motion/cmu_01_01.bvh
if [ -f "$clip" ]; then
  echo
  echo "== 3. pose it with a CMU clip (frame 600): sweeps, and LBS for comparison"
  "$sweepctl" pose "$out/mannequin.sweepbind" --bvh "$clip" --frame 600 -o "$out/frame600_sweep.glb"
  "$sweepctl" pose "$out/mannequin.sweepbind" --bvh "$clip" --frame 600 --method lbs -o "$out/frame600_lbs.glb"
  "$sweepctl" render "$out/mannequin.sweepbind" --bvh "$clip" --frame 600 --png "$out/frame600.png" --size 600
  "$sweepctl" positionmap "$out/mannequin.sweepbind" --bvh "$clip" --frame 600 --normals -o "$out/frame600.exr"
fi

if [ -f "$shared/models/makehuman_male_cmu.glb" ]; then
  echo
  echo "== 4. a real rigged human (shared data)"
  "$sweepctl" inspect "$shared/models/makehuman_male_cmu.glb" | head -n 14
  echo
  echo "== 5. a CMU motion clip (shared data)"
  "$sweepctl" inspect "$shared/motion/cmu_01_01.bvh" | head -n 7
else
  echo "(../shared/data not found: skipping the real model and clip)"
fi
echo
echo "demo done: outputs in $out/"
