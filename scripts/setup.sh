#!/usr/bin/env bash
# Installs the Debian packages mbest needs (only those missing, after an apt-get update)
# and configures and builds the project with CMake.
# Usage: scripts/setup.sh [--sanitize] [--target T]...
#   --sanitize   build with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/
#   --target T   build only target T (e.g. mbest); default: everything
# Environment: MBEST_BUILD overrides the build folder (default build/, or build-asan/).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
sanitize=OFF
targets=()
while (( $# )); do
  case "$1" in
    --sanitize) sanitize=ON ;;
    --target) [[ $# -ge 2 ]] || { echo "setup.sh: --target needs a name" >&2; exit 2; }
              targets+=(--target "$2"); shift ;;
    -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "setup.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done
build="${MBEST_BUILD:-$root/build}"
[[ $sanitize == ON && -z "${MBEST_BUILD:-}" ]] && build="$root/build-asan"

packages=(cmake g++ make pkg-config libopencv-dev libeigen3-dev libcairo2-dev
          nlohmann-json3-dev libgtest-dev librapidcheck-dev libbenchmark-dev libcli11-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if (( ${#missing[@]} )); then
  sudo=""
  [[ $(id -u) -ne 0 ]] && sudo=sudo
  echo "setup.sh: installing ${missing[*]}" >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi

build_type=Release
[[ $sanitize == ON ]] && build_type=RelWithDebInfo
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE="$build_type" -DMBEST_SANITIZE="$sanitize" \
  -DMBEST_BUILD_TESTS=ON -DMBEST_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j"$(nproc)" "${targets[@]}"
echo "setup.sh: built into $build" >&2
