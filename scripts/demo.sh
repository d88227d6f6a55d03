#!/usr/bin/env bash
# The main job on a bundled default: set up, generate a small synthetic set of rods
# (preset s3: three tubes on black, like the real dev set, segmented by the built-in
# colour filter; and `cables`: thin cables on textured backgrounds, where a colour filter
# cannot work, segmented by the generator's semantic masks as a learned segmenter would),
# detect every DLO, and score the detections against the exact ground truth.
# Outputs go to out/demo/ (override with DEMO_OUT).
# Usage: scripts/demo.sh [COUNT]   (COUNT scenes per preset, default 12)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
count="${1:-12}"
out="${DEMO_OUT:-$root/out/demo}"
"$root/scripts/setup.sh" --target mbest
mbest="${MBEST_BUILD:-$root/build}/mbest"

rm -rf "$out"
for preset in s3 cables; do
  echo "== $preset: generating $count scenes" >&2
  "$mbest" synth --preset "$preset" --count "$count" --seed 2026 --out "$out/synth-$preset" --split demo --jobs "$(nproc)" --quiet
  echo "== $preset: detecting" >&2
  masks=()
  [[ $preset == cables ]] && masks=(--mask-sibling semantic)
  "$mbest" detect "$out/synth-$preset" "${masks[@]}" --out "$out/pred-$preset" --overlay \
    --timings "$out/pred-$preset/timings.json" --quiet
  echo "== $preset: scoring" >&2
  "$mbest" eval "$out/synth-$preset" --pred "$out/pred-$preset" --report "$out/report-$preset"
done
cat <<MSG

Look at:
  $out/pred-s3/demo/images/*.overlay.png     detections drawn over the pictures
  $out/report-s3/report.html                 accuracy report (also report.md, report.json)
  $out/pred-s3/timings.json                  detector milliseconds per image and stage
MSG
