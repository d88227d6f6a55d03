#!/usr/bin/env bash
# Scores the detector on an mbest-real-layout data set and prints the per-tier table.
# Usage: scripts/eval-real.sh DATASET [PRED_DIR] [-- extra `mbest eval` options, e.g. --report DIR]
#   DATASET   e.g. ../shared/datasets/mbest-real (DATASET/<tier>/images, DATASET/<tier>/labels)
#   PRED_DIR  a `mbest detect DATASET --out PRED_DIR` folder; without it, detection runs now
#             into a temporary folder.
# Exits non-zero when any tier's strict matched DICE is below MIN_DICE (default 98.5 %),
# or on bad input. The build folder is build/ (env MBEST_BUILD overrides); it must hold mbest.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${MBEST_BUILD:-$root/build}"
min_dice="${MIN_DICE:-98.5}"
if [[ $# -lt 1 || "$1" == -h || "$1" == --help ]]; then
  sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'
  exit 1
fi
dataset="$1"
shift
pred=""
if [[ $# -gt 0 && "$1" != -- ]]; then
  pred="$1"
  shift
fi
[[ $# -gt 0 && "$1" == -- ]] && shift
mbest="$build/mbest"
if [[ ! -x "$mbest" ]]; then
  echo "eval-real.sh: $mbest not found: build it first (cmake --build $build --target mbest)" >&2
  exit 1
fi
if [[ -z "$pred" ]]; then
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  pred="$tmp/pred"
  "$mbest" detect "$dataset" --out "$pred" --quiet
fi
"$mbest" eval "$dataset" --pred "$pred" --min-dice "$min_dice" "$@"
