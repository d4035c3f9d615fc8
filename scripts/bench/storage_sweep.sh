#!/usr/bin/env bash
# Package size against error for the frame codec's settings (docs/package-format.md, "Frame
# codec"): bakes FRAMES once at the finest storage settings, stores that package again at each
# setting below (`firelook repack`, no baking), and measures every package with `firelook bench` on
# the same random looks, references and exact alpha (cached once, so only the first bench traces).
# Writes OUT/storage.csv (bench --csv rows, one per setting), OUT/error-vs-size.png (median and worst
# noise-corrected relative RMSE, and the max alpha error, against package bytes) and
# OUT/pareto.txt (the settings no other beats on size and median error).
#   scripts/bench/storage_sweep.sh [SEQUENCE] [OUT]
# Environment: FRAMES (3,7,11), SIZE (256x256), LOOKS (4 per frame), SPP (256), ALPHA_RAYS (4),
# UP (z), TARGET_SIZES ("1M 768K 512K": repack --target-size values; scale them with SIZE),
# FIRELOOK (build/release's by default, built first when unset).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
sequence="${1:-$root/samples/data/explosion}"
out="${2:-$root/out/bench/storage}"
frames="${FRAMES:-3,7,11}"
size="${SIZE:-256x256}"; looks="${LOOKS:-4}"; spp="${SPP:-256}"; alpha_rays="${ALPHA_RAYS:-4}"; up="${UP:-z}"
if [[ -z "${FIRELOOK:-}" ]]; then "$root/scripts/build.sh" release firelook >/dev/null; fi
firelook="${FIRELOOK:-$root/build/release/baker/cli/firelook}"
mkdir -p "$out/packages"
csv="$out/storage.csv"
rm -f "$csv"

# The finest storage: alpha on the finest depth grid, every differing ray kept, U and S V^T within
# 1e-5 of the basis.
fine="$out/packages/finest.firelook"
if [[ ! -f "$fine" ]]; then
  echo '{"compression": {"alpha_error": 1e-6, "footprint_error": 0, "basis_error": 1e-5}}' > "$out/fine.json"
  echo "== bake frames $frames at the finest storage"
  "$firelook" bake "$sequence" --up "$up" --size "$size" --frames "$frames" --config "$out/fine.json" -o "$fine" \
    > "$out/bake.log"
fi
read -r -a bench_frames <<< "${frames//,/ }"

# label and the repack options: one knob from the defaults at a time, both ends, then repack's
# targets (a per-frame error, and sizes of the whole package of FRAMES).
settings=(
  "finest"
  "defaults --alpha-error 0.001 --footprint-error 0.001 --basis-error 0.0005"
  "alpha-0.0005 --alpha-error 0.0005" "alpha-0.002 --alpha-error 0.002" "alpha-0.004 --alpha-error 0.004"
  "footprint-0 --footprint-error 0" "footprint-0.003 --footprint-error 0.003" "footprint-0.01 --footprint-error 0.01"
  "basis-0.0002 --basis-error 0.0002" "basis-0.001 --basis-error 0.001" "basis-0.002 --basis-error 0.002"
  "basis-0.005 --basis-error 0.005"
  "coarse --alpha-error 0.004 --footprint-error 0.01 --basis-error 0.005"
  "target-error-0.002 --target-error 0.002" "target-error-0.004 --target-error 0.004"
  "target-error-0.008 --target-error 0.008" "target-error-0.016 --target-error 0.016"
)
for size_target in ${TARGET_SIZES:-1M 768K 512K}; do settings+=("target-size-$size_target --target-size $size_target"); done
for s in "${settings[@]}"; do
  read -r label options <<< "$s"
  package="$fine"
  if [[ "$label" != finest ]]; then
    package="$out/packages/$label.firelook"
    # shellcheck disable=SC2086  # the options are words
    "$firelook" repack "$fine" -o "$package" $options > /dev/null
  fi
  echo "== $label"
  "$firelook" bench "$sequence" --package "$package" --frames "${bench_frames[@]}" --looks "$looks" --spp "$spp" \
    --alpha-rays "$alpha_rays" --reference-cache "$out/references" --csv "$csv" --label "$label" \
    > "$out/bench-$label.log"
done
"$root/scripts/bench/plot_storage_sweep.sh" "$csv" "$out"
