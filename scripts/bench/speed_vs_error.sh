#!/usr/bin/env bash
# Speed against error (issue 7): bakes the sequence once per setting, varying one
# knob at a time from the defaults — SVD rank, photon budget, scattered-light cell
# size, march step, parameter-grid density per axis, image size, alpha footprint rays — and
# measures each package with `firelook bench` on the same random looks (references
# cached, so each look is path-traced once per image size). Output in OUT:
#   sweep.csv        one row per setting: bake s, peak MiB, package bytes,
#                    coefficient us, image ms, median/worst relative RMSE, max alpha error
#   *.png            error against runtime, package size and bake time (gnuplot)
#   pareto.txt       the settings on the Pareto front of each plot
#
#   scripts/bench/speed_vs_error.sh [SEQUENCE] [OUT]
# Environment: FRAMES (3,7,11), SIZE (128x128), LOOKS per frame (7), SPP (1024),
# REFERENCES (out/bench/references, shared with scripts/bench/accuracy.sh: same looks),
# UP (z), ONLY (space-separated labels to run, default all), QUICK=1 (tiny run for
# the test suite: 2 settings, 1 frame, 32x32, 2 looks, 64 spp).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
sequence="${1:-$root/samples/data/explosion}"
out="${2:-$root/out/bench/speed_vs_error}"
frames="${FRAMES:-3,7,11}"; size="${SIZE:-128x128}"; looks="${LOOKS:-7}"; spp="${SPP:-1024}"; up="${UP:-z}"
if [[ "${QUICK:-0}" == 1 ]]; then frames="${FRAMES:-6}"; size="${SIZE:-32x32}"; looks="${LOOKS:-2}"; spp="${SPP:-64}"; fi
firelook="${FIRELOOK:-$root/build/release/baker/cli/firelook}"
if [[ -z "${FIRELOOK:-}" ]]; then "$root/scripts/build.sh" release firelook >/dev/null; fi
mkdir -p "$out/packages" "$out/configs"
rm -f "$out/sweep.csv"

# Most telling first, so a sweep cut short still has the main knobs.
# label | bake.json fragment (merged into {"size", "up", "frames"}) [| reference spp: at 256x256 a
# quarter of the samples keeps the reference cost of one 128x128 image; its noise is in the row]
settings=(
  "baseline|{}"
  "rank-4|{\"compression\": {\"max_rank\": 4}}"
  "rank-8|{\"compression\": {\"max_rank\": 8}}"
  "rank-16|{\"compression\": {\"max_rank\": 16}}"
  "rank-32|{\"compression\": {\"max_rank\": 32}}"
  "photons-x0.25|{\"trace\": {\"photons_primary\": 65536, \"photons_per_order\": 32768, \"photon_noise_target\": 0}}"
  "photons-x0.5|{\"trace\": {\"photons_primary\": 131072, \"photons_per_order\": 65536, \"photon_noise_target\": 0}}"
  "Tc-3|{\"axes\": {\"temperature_threshold\": {\"min\": 1.0, \"max\": 2.0, \"count\": 3}}}"
  "ks-2|{\"axes\": {\"smoke_extinction\": [2, 16]}}"
  "kf-2|{\"axes\": {\"flame_extinction\": [0.5, 4]}}"
  "footprint-1|{\"trace\": {\"footprint_samples_per_axis\": 1}}"
  "footprint-2|{\"trace\": {\"footprint_samples_per_axis\": 2}}"
  "footprint-4|{\"trace\": {\"footprint_samples_per_axis\": 4}}"
  "step-0.5|{\"trace\": {\"step_voxels\": 0.5}}"
  "size-64|{\"size\": \"64x64\"}"
  "target-0.01|{\"compression\": {\"target_relative_error\": 0.01}}"
  "photons-x2|{\"trace\": {\"photons_primary\": 524288, \"photons_per_order\": 262144, \"photon_noise_target\": 0}}"
  "cells-8vox|{\"trace\": {\"cell_voxels\": 8}}"
  "size-256|{\"size\": \"256x256\"}|256"
  "Tc-11|{\"axes\": {\"temperature_threshold\": {\"min\": 1.0, \"max\": 2.0, \"count\": 11}}}"
  "ks-7|{\"axes\": {\"smoke_extinction\": {\"min\": 2, \"max\": 16, \"count\": 7, \"spacing\": \"geometric\"}}}"
  "kf-5|{\"axes\": {\"flame_extinction\": {\"min\": 0.5, \"max\": 4, \"count\": 5, \"spacing\": \"geometric\"}}}"
  "step-0.1|{\"trace\": {\"step_voxels\": 0.1}}"
  "target-0.001|{\"compression\": {\"target_relative_error\": 0.001}}"
  "cells-4vox|{\"trace\": {\"cell_voxels\": 4}}"
)
if [[ "${QUICK:-0}" == 1 ]]; then
  few='"trace": {"photons_primary": 4000, "photons_per_order": 2000, "photon_noise_target": 0, "max_orders": 3}'
  settings=("quick-baseline|{$few}" "quick-rank-2|{$few, \"compression\": {\"max_rank\": 2}}")
fi

# Merges a fragment into the base settings. Fragments never repeat a base key
# except "size", so textual merging is enough and keeps this script free of a JSON tool.
config_for() {
  local fragment="$1" base="\"size\": \"$size\", \"up\": \"$up\", \"frames\": \"$frames\""
  if [[ "$fragment" == "{}" ]]; then echo "{$base}"
  elif [[ "$fragment" == *'"size"'* ]]; then echo "{\"up\": \"$up\", \"frames\": \"$frames\", ${fragment:1}"
  else echo "{$base, ${fragment:1}"; fi
}

count=${#settings[@]}; n=0
for entry in "${settings[@]}"; do
  IFS='|' read -r label fragment row_spp <<< "$entry"; n=$((n + 1))
  if [[ -n "${ONLY:-}" && " $ONLY " != *" $label "* ]]; then continue; fi
  echo "== [$n/$count] $label"
  config="$out/configs/$label.json"; package="$out/packages/$label.firelook"
  config_for "$fragment" > "$config"
  "$firelook" bake "$sequence" --config "$config" -o "$package" --report "$out/packages/$label.bake.json" \
    > "$out/packages/$label.bake.txt"
  tail -n 1 "$out/packages/$label.bake.txt"
  "$firelook" bench "$sequence" --package "$package" --frames "$frames" --looks "$looks" --spp "${row_spp:-$spp}" \
    --reference-cache "${REFERENCES:-$root/out/bench/references}" --bake-report "$out/packages/$label.bake.json" \
    --csv "$out/sweep.csv" --label "$label" --json "$out/packages/$label.bench.json" > /dev/null
  tail -n 1 "$out/sweep.csv"
done

"$root/scripts/bench/plot_speed_vs_error.sh" "$out/sweep.csv" "$out"
echo "sweep: $out/sweep.csv, plots and Pareto fronts in $out"
