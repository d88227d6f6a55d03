#!/usr/bin/env bash
# Regenerates fixtures/gallery/synth-gallery.png: two scenes of each synth preset
# (s1, s2, s3, cables, stress), each beside its colour-coded label image.
# Usage: scripts/synth-gallery.sh [BUILD_DIR]   (default: build)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
cmake --build "$build" -j2 --target mbest synth_gallery >/dev/null
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
dirs=()
seed=2024
for preset in s1 s2 s3 cables stress; do
  seed=$((seed + 1))  # a seed per preset: the s presets would otherwise share their first rods
  "$build/mbest" synth --preset "$preset" --count 2 --seed "$seed" --out "$tmp/$preset" --quiet
  dirs+=("$tmp/$preset/train")
done
mkdir -p "$root/fixtures/gallery"
"$(find "$build" -name synth_gallery -type f -perm -u+x | head -1)" \
  "$root/fixtures/gallery/synth-gallery.png" 224 "${dirs[@]}"
ls -l "$root/fixtures/gallery/synth-gallery.png"
