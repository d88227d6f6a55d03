#!/usr/bin/env bash
# Speed figures: the detector's median ms per frame, per tier and per stage, on a data set
# (default ../shared/datasets/mbest-real), single thread, mask in, labels and centerlines
# out; then the generator's scenes per second (Google Benchmark). Quote medians; the
# machines are shared and noisy.
# Usage: scripts/bench.sh [DATASET] [ROUNDS]   (ROUNDS runs of every frame, default 20)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
dataset="${1:-$root/../shared/datasets/mbest-real}"
rounds="${2:-20}"
"$root/scripts/setup.sh" --target mbest_bench --target synth_bench >/dev/null
build="${MBEST_BUILD:-$root/build}"
echo "== detector: $dataset, $rounds runs per frame"
"$build/mbest_bench" "$dataset" --rounds "$rounds" --json "$build/bench-detect.json"
bench="$(find "$build" -name synth_bench -type f -perm -u+x | head -1)"
if [[ -n "$bench" ]]; then
  echo "== generator"
  "$bench" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
fi
