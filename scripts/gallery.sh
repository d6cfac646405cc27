#!/usr/bin/env bash
# Regenerate the gallery of docs/guide.md (docs/gallery/) with the
# project's own commands: an animated GIF of each demo, drawn by
# `sprung render`, and the energy of the oscillator under every
# integrator, drawn by `sprung plot`.
# Run from anywhere: scripts/gallery.sh (takes a few minutes, release build).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p sprung-cli
sprung=target/release/sprung
gallery=docs/gallery
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$gallery"

# name, simulated seconds, pictures per second, extra render options
demos=(
  "ball2d 4 12"
  "ball3d 3 12"
  "pillow 2 8"
  "horse 2 8"
  "balloon 8 4"
  "flag 4 12"
  "billow 2 8"
  "drape 3 10"
  "poke 3 8"
  "cloth 4 10"
  "rope 3 12"
  "rope_one_sided 2 8"
  "jelly 2 12"
  "chain 6 10"
  "lattice2d 2 12"
  "pendulum 6 10"
  "double_pendulum 8 12"
  "spring_pendulum 12 8 --trace 1"
  "orbit 8 10"
  "walker 10 6"
  "dice 3 12"
)
for entry in "${demos[@]}"; do
  read -r name seconds rate extra <<<"$entry"
  echo "gallery: $name"
  scene="scenes/$name.toml"
  dt=$(sed -n 's/^dt *= *\([0-9.e-]*\).*/\1/p' "$scene" | head -1)
  every=$(python3 -c "print(max(1, round(1 / ($rate * $dt))))")
  "$sprung" render "$scene" --time "$seconds" --every "$every" --width 400 --height 300 \
    --gif --out "$work/$name" --quiet ${extra:-}
  cp "$work/$name/animation.gif" "$gallery/$name.gif"
done

echo "gallery: integrator comparison"
"$sprung" demo oscillator --out "$work/oscillator" --quiet
"$sprung" plot --compare "$work"/oscillator/{euler,symplectic_euler,midpoint,rk4,verlet} \
  --out "$work/compare" --width 900 --height 540 --quiet
cp "$work/compare/compare.png" "$gallery/integrators.png"
du -sh "$gallery"
