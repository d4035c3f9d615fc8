#!/usr/bin/env bash
# The README's first command: installs what is missing, builds the tools, bakes
# the bundled explosion (samples/data/explosion) at the default settings, and
# renders every frame with three looks keyed across the sequence (frames 1, 6
# and 12; linear in between) into out/sample/, with a contact sheet.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out/sample}"
"$root/scripts/setup.sh"
echo "== build"
"$root/scripts/build.sh" release firelook
firelook="$root/build/release/baker/cli/firelook"
mkdir -p "$out"
looks="$root/samples/looks"

echo "== bake (the bundled explosion, 12 frames at 256x256)"
"$firelook" bake "$root/samples/data/explosion" --up z -o "$out/explosion.firelook" | tee "$out/bake-report.txt"

echo "== render three keyed looks"
"$firelook" animate "$out/explosion.firelook" \
  --key "1:$looks/fireball.json" --key "6:$looks/inferno.json" --key "12:$looks/smoky.json" \
  --out-dir "$out/frames" --exr
echo
echo "package:       $out/explosion.firelook  (firelook info $out/explosion.firelook)"
echo "frames:        $out/frames/frame_NNNN.png (+ .exr, linear premultiplied)"
echo "contact sheet: $out/frames/contact_sheet.png"
echo "bake report:   $out/bake-report.txt"
