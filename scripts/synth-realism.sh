#!/usr/bin/env bash
# Realism check of the s3 preset: the colour filter's semantic DICE and the detector's
# strict matched DICE on a generated s3 set, beside the same figures on the real S3 tier.
# Usage: scripts/synth-realism.sh [REAL_S3_DIR] [SYNTH_OUT]
#   REAL_S3_DIR  default ../shared/datasets/mbest-real/S3 (images/*.jpg, labels/*.png)
#   SYNTH_OUT    default a temporary folder; generated with
#                `mbest synth --preset s3 --count $COUNT --seed $SEED --out SYNTH_OUT --jobs 2`
#                unless it already holds the set (an interrupted run resumes)
# Env: MBEST_BUILD (default build/; must hold mbest and synth/synth_realism), COUNT (100),
# SEED (1). Columns: filter DICE = mean per image of the colour filter against labels > 0;
# "inner" = the same without the pixels within 1 px of the labels' edges; detector DICE =
# `mbest eval --run --colour-filter` strict (and lenient) matched DICE.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${MBEST_BUILD:-$root/build}"
real="${1:-$root/../shared/datasets/mbest-real/S3}"
count="${COUNT:-100}"
seed="${SEED:-1}"
mbest="$build/mbest"
realism="$build/synth/synth_realism"
for tool in "$mbest" "$realism"; do
  if [[ ! -x "$tool" ]]; then
    echo "synth-realism.sh: $tool not found: build it (cmake --build $build --target mbest synth_realism)" >&2
    exit 1
  fi
done
[[ -d "$real/images" && -d "$real/labels" ]] || { echo "synth-realism.sh: no images/ and labels/ in $real" >&2; exit 1; }
command -v jq > /dev/null || { echo "synth-realism.sh: jq is needed" >&2; exit 1; }

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
synth="${2:-$tmp/s3syn}"
"$mbest" synth --preset s3 --count "$count" --seed "$seed" --out "$synth" --jobs 2 > /dev/null 2> "$tmp/synth.log" ||
  { cat "$tmp/synth.log" >&2; exit 1; }

# mbest eval reads DATASET/<tier>/{images,labels}: give the real tier a folder of its own
# (a link, nothing is copied).
mkdir -p "$tmp/real"
ln -s "$(cd "$real" && pwd)" "$tmp/real/S3"

row() {  # name images_dir labels_dir eval_dataset
  read -r n filter _pooled inner < <("$realism" "$2" "$3")
  "$mbest" eval "$4" --run --colour-filter --json 2> /dev/null > "$tmp/eval.json" || true
  read -r strict lenient counts < <(jq -r '.tiers[0] | "\(.strict_dice_pct) \(.lenient_dice_pct) \(.count_errors)"' "$tmp/eval.json")
  printf '%-14s %7d %14.2f %14.2f %16.2f %16.2f %13d\n' "$1" "$n" "$filter" "$inner" "$strict" "$lenient" "$counts"
}
printf '%-14s %7s %14s %14s %16s %16s %13s\n' set images "filter DICE %" "filter inner %" "detect strict %" "detect lenient %" "count errors"
row "real S3" "$real/images" "$real/labels" "$tmp/real"
row "synth s3" "$synth/train/images" "$synth/train/labels" "$synth"
