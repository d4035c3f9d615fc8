#!/usr/bin/env bash
# Reference path tracer: time and noise for one frame of the bundled sample at
# 256x256, 64 and 256 samples per pixel. Noise is measured as the relative RMSE
# between two renders with different seeds (each has sqrt(2) less error than
# their difference, if independent), beside the tracer's own estimate.
#   scripts/bench/reference_noise.sh [frame] [out-dir]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
frame="${1:-6}"
out="${2:-$root/out/bench/reference}"
"$root/scripts/build.sh" release firelook >/dev/null
firelook="$root/build/release/baker/cli/firelook"
mkdir -p "$out"
for spp in 64 256; do
  for seed in 1 2; do
    "$firelook" reference "$root/samples/data/explosion" --up z --frame "$frame" --size 256x256 \
      --spp "$spp" --seed "$seed" --out "$out/ref_${spp}_s${seed}.exr" 2>/dev/null
  done
  echo "spp $spp, seed 1 vs seed 2: $("$firelook" compare "$out/ref_${spp}_s1.exr" "$out/ref_${spp}_s2.exr")"
done
