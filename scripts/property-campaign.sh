#!/usr/bin/env bash
# A long property campaign: runs the rapidcheck properties of tests/properties with many
# cases from several seeds (CI runs a bounded number from one fixed seed). A failure prints
# the shrunk scene spec; store it in fixtures/regressions/<name>.json to replay it for ever.
# Usage: scripts/property-campaign.sh [CASES] [SEEDS...]   (default 500 cases, seeds 1 2 3)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cases="${1:-500}"
shift || true
seeds=("$@")
(( ${#seeds[@]} )) || seeds=(1 2 3)
"$root/scripts/setup.sh" --target property_tests >/dev/null
build="${MBEST_BUILD:-$root/build}"
failed=0
for seed in "${seeds[@]}"; do
  echo "== seed $seed, $cases cases per property"
  if ! RC_PARAMS="seed=$seed max_success=$cases" "$build/tests/properties/property_tests" \
      > "$build/property-campaign-$seed.log" 2>&1; then
    failed=1
    grep -E "^\{|^\[  FAILED|Falsifiable|^[A-Za-z].*(wrong|DICE|DLO|end|disagree)|^[0-9].* after (rot|flip)" \
      "$build/property-campaign-$seed.log" || true
  fi
  grep "^\[property\]" "$build/property-campaign-$seed.log"
done
exit "$failed"
