#!/usr/bin/env bash
# The fire's point lights (runtime/basis/fire_lights.h): bakes frames of the bundled sample small
# (64x64: the lights do not depend on the image size) and measures, per frame, the fluence their
# 1, 2, 4 and 8 lights give at 26 points around the fire against the fluence probe of the full
# model, their bytes and the time of one evaluation (tests/bake/bench_fire_lights.cpp says how).
#   scripts/bench/fire_lights.sh [frames A-B] [looks] [paths per point] [box scale] [out-dir]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
frames="${1:-6-7}"
looks="${2:-5}"
samples="${3:-4096}"
scale="${4:-1.5}"
out="${5:-$root/out/bench/fire_lights}"
"$root/scripts/build.sh" release firelook bench_fire_lights >/dev/null
firelook="$root/build/release/baker/cli/firelook"
mkdir -p "$out"
"$firelook" bake "$root/samples/data/explosion" --up z --frames "$frames" --size 64x64 --fire-lights -o "$out/sample.firelook" >/dev/null
"$firelook" info "$out/sample.firelook" | grep -E "fire lights|by kind"
for f in $(seq "${frames%-*}" "${frames#*-}"); do
  "$root/build/release/tests/bake/bench_fire_lights" "$out/sample.firelook" "$root/samples/data/explosion" "$f" \
    "$looks" "$samples" "$scale" 2>/dev/null
done
