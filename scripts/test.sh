#!/usr/bin/env bash
# Sets up (scripts/setup.sh), runs the GoogleTest and rapidcheck suites with CTest, and,
# where ../shared/datasets/mbest-real exists, the accuracy gate: strict matched DICE of
# every tier at least 98.5 %, no image below 95 %, no instance-count error.
# Usage: scripts/test.sh [--sanitize]   (--sanitize: the suites under ASan + UBSan)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh" "$@"
build="${MBEST_BUILD:-$root/build}"
[[ " $* " == *" --sanitize "* && -z "${MBEST_BUILD:-}" ]] && build="$root/build-asan"

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
(cd "$build" && ctest --output-on-failure -j"$(nproc)")

dataset="$root/../shared/datasets/mbest-real"
if [[ -d "$dataset" ]]; then
  echo "test.sh: accuracy gate on $dataset" >&2
  MBEST_BUILD="$build" MIN_DICE=98.5 "$root/scripts/eval-real.sh" "$dataset" -- \
    --max-below-95 0 --max-count-errors 0
else
  echo "test.sh: $dataset not found: accuracy gate skipped" >&2
fi
