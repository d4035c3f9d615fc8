#!/usr/bin/env bash
# Accuracy of a bake against the reference path tracer (issue 4's bars):
# bakes frames 3, 7 and 11 of the bundled sample at 128x128 with the default
# settings, then `firelook bench` draws 7 random looks per frame (21 in all),
# path-traces each at 1024 spp and splits the error by source. Alpha is judged
# against 8x8 exact rays per pixel. References are kept in out/bench/references
# (REFERENCES=dir to move them), which the speed-vs-error sweep shares.
#   scripts/bench/accuracy.sh [out-dir]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="${1:-$root/out/bench/accuracy}"
"$root/scripts/build.sh" release firelook >/dev/null
firelook="$root/build/release/baker/cli/firelook"
mkdir -p "$out"
"$firelook" bake "$root/samples/data/explosion" --up z --size 128x128 --frames 3,7,11 \
  -o "$out/bench128.firelook" | tee "$out/bake.txt"
"$firelook" bench "$root/samples/data/explosion" --package "$out/bench128.firelook" --frames 3,7,11 \
  --looks 7 --spp 1024 --split --json "$out/accuracy.json" \
  --reference-cache "${REFERENCES:-$root/out/bench/references}" | tee "$out/summary.json"
