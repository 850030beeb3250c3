#!/usr/bin/env bash
# make docs-quality: one page per shared body (docs/quality/BODY.md) with `sweepctl check`'s
# tables — sweep, LBS and DQS per body region over the body's range of motion and over both CMU
# clips, as length ratios l / l_rest — and the contact sheet of its worst range-of-motion frames
# (BODY.png), then the index (docs/quality/README.md).
# Usage: docs/quality/make_pages.sh SWEEPCTL SHARED_DATA
set -euo pipefail
sweepctl=$1
data=$2
out=$(cd "$(dirname "$0")" && pwd)
bodies=(makehuman_male_cmu.glb RiggedFigure/RiggedFigure.gltf
        corpus/makehuman_child_mixamo_unity.glb corpus/makehuman_female_old_heavy_mixamo.glb
        corpus/makehuman_female_slim_openpose.glb corpus/makehuman_male_old_heavy_unreal.glb)
commit=$(git -C "$out" rev-parse --short HEAD 2>/dev/null || echo unknown)

# check exits 1 when the sweep is worse somewhere: that is a finding, not a failure here.
check() { "$sweepctl" check "$@" 2>/dev/null || [[ $? == 1 ]]; }

index="$out/README.md"
{
  echo "# Quality per body"
  echo
  echo "Made by \`make docs-quality\` at commit $commit: \`sweepctl check\` on every shared body"
  echo "(../../../shared/data/SOURCES.md), sweep against LBS and DQS, region by region. Edge"
  echo "stretch is the length ratio l / l_rest of the worst edge of a region; a sweep region is"
  echo "worse than skinning in a frame where its swept edges stretch more than 1.02x the better"
  echo "of LBS and DQS there (issue 47's gate). Each page has the tables and the contact sheet"
  echo "of the worst range-of-motion frames."
  echo
  echo "Per clip: the regions where the sweep is worse than skinning (of 11), then the worst"
  echo "stretch of any region with each method."
  echo
  echo "| body | range of motion | CMU 01_01 | CMU 01_03 |"
  echo "|---|---|---|---|"
} > "$index"
for body in "${bodies[@]}"; do
  name=$(basename "${body%.*}")
  model="$data/models/$body"
  [[ -f "$model" ]] || { echo "make_pages: no $model" >&2; exit 1; }
  echo "docs-quality: $name" >&2
  page="$out/$name.md"
  rom=$(check "$model" --markdown --sheet "$out/$name.png")
  clip1=$(check "$model" --bvh "$data/motion/cmu_01_01.bvh" --markdown)
  clip3=$(check "$model" --bvh "$data/motion/cmu_01_03.bvh" --markdown)
  {
    echo "# $name: sweep, LBS and DQS"
    echo
    echo "\`sweepctl check $body\` (made by \`make docs-quality\` at commit $commit)."
    echo
    echo "## Range of motion (every 5th frame: each move's peak and the way there)"
    echo
    echo "$rom"
    echo
    echo "![the worst range-of-motion frames: sweep, LBS, DQS, coloured by stretch]($name.png)"
    echo
    echo "## CMU 01_01 (every 10th frame)"
    echo
    echo "$clip1"
    echo
    echo "## CMU 01_03 (every 10th frame)"
    echo
    echo "$clip3"
  } > "$page"
  # "9 regions worse; worst: sweep 5.03, lbs 9.09, dqs 11.79"
  verdict() {
    local regions worst
    regions=$(tail -1 <<< "$1" | sed -E 's/.* in ([0-9]+) regions?.*/\1 worse/; s/.*nowhere worse.*/none worse/')
    worst=$(grep '^worst over every region:' <<< "$1" | sed 's/worst over every region: //')
    echo "$regions; worst $worst"
  }
  echo "| [$name]($name.md) | $(verdict "$rom") | $(verdict "$clip1") | $(verdict "$clip3") |" >> "$index"
done
echo "wrote $index and one page per body" >&2
