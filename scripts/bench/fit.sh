#!/usr/bin/env bash
# Issue 17's bars for the look fit (README "Look fitting"), on one frame of the bundled sample:
#  1. self-consistency: COUNT random looks inside the baked ranges of a 256x256 package, each
#     rendered by the runtime and fitted from its image alone (bench_fit looks);
#  2. time: `firelook fit` of one 256x256 frame, RUNS runs, median of the fit's seconds;
#  3. a target from another renderer: the reference path tracer's image of samples/looks/inferno.json
#     at SPP samples per pixel (REF_SIZE), its own noise from a second seed, the package's own error
#     against it (the look rendered as baked) and the fit's error;
#  4. a target from outside the model: the reference tracer with a blackbody emission law
#     (bench_fit blackbody), fitted; target / fit / difference written to OUT/blackbody.png.
#   scripts/bench/fit.sh [OUT]
# Environment: STEPS (which of them: "1 2 3 4"), FRAME (7), COUNT (20), RUNS (5), SPP (1024), REF_SIZE (128x128), KELVIN_PER_UNIT
# (1000), KELVIN_AT_0 (300): K = 300 + 1000 T is the data's own scale (1000 K above ambient).
# Packages are baked at the default settings (frame FRAME only) and kept in OUT.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="${1:-$root/out/bench/fit}"
steps="${STEPS:-1 2 3 4}"; frame="${FRAME:-7}"; count="${COUNT:-20}"; runs="${RUNS:-5}"; spp="${SPP:-1024}"; ref_size="${REF_SIZE:-128x128}"
kelvin_per_unit="${KELVIN_PER_UNIT:-1000}"; kelvin_at_0="${KELVIN_AT_0:-300}"
"$root/scripts/build.sh" release firelook bench_fit >/dev/null
firelook="$root/build/release/baker/cli/firelook"
bench_fit="$root/build/release/tests/fit/bench_fit"
sample="$root/samples/data/explosion"
look="$root/samples/looks/inferno.json"
mkdir -p "$out"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"

bake() {  # SIZE OUT
  [[ -f "$2" ]] || "$firelook" bake "$sample" --up z --size "$1" --frames "$frame" -o "$2" >/dev/null
}
rmse() {  # IMAGE REFERENCE: relative RMSE, a fraction
  "$firelook" compare "$1" "$2" --json | sed -n 's/.*"relative_rmse": \([-0-9.eE+]*\).*/\1/p'
}
percent() { awk -v v="$1" 'BEGIN { printf "%.3f%%", 100 * v }'; }

step() { [[ " $steps " == *" $1 "* ]]; }
step 1 || step 2 && bake 256x256 "$out/p256.firelook"
if step 1; then
echo "== 1. self-consistency: $count random looks, frame $frame, 256x256"
"$bench_fit" looks "$out/p256.firelook" "$frame" "$count" 1 | tee "$out/looks.txt"

fi
if step 2; then
echo "== 2. time: firelook fit of one 256x256 frame (inferno.json rendered), $runs runs"
"$firelook" render "$out/p256.firelook" --frame "$frame" --look "$look" -o "$out/t256.exr" >/dev/null
for i in $(seq "$runs"); do
  "$firelook" fit "$out/p256.firelook" --frame "$frame" --target "$out/t256.exr" -o "$out/t256_fit.json" 2>/dev/null |
    sed -n 's/.*; fit \([0-9.]*\) s, \([0-9.]*\) s in all/\1 \2/p'
done | sort -n | tee "$out/times.txt" | awk '{ f[NR] = $1; a[NR] = $2 } END {
  printf "fit seconds: median %.3f (min %.3f, max %.3f); with loading the package: median %.3f\n",
    f[int((NR + 1) / 2)], f[1], f[NR], a[int((NR + 1) / 2)] }'
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
fi

step 3 || step 4 && bake "$ref_size" "$out/pref.firelook"
if step 3; then
echo "== 3. the reference path tracer's image of inferno.json, $spp spp, $ref_size"
for seed in 1 2; do
  [[ -f "$out/ref${spp}_s$seed.exr" ]] || "$firelook" reference "$sample" --up z --frame "$frame" --size "$ref_size" \
    --look "$look" --spp "$spp" --seed "$seed" -o "$out/ref${spp}_s$seed.exr" >/dev/null 2>&1
done
"$firelook" render "$out/pref.firelook" --frame "$frame" --look "$look" -o "$out/ref_baked.exr" >/dev/null
"$firelook" fit "$out/pref.firelook" --frame "$frame" --target "$out/ref${spp}_s1.exr" -o "$out/ref_fit.json" \
  --image "$out/ref_fit.exr" 2>/dev/null | tee "$out/ref_fit.txt"
noise2=$(rmse "$out/ref${spp}_s1.exr" "$out/ref${spp}_s2.exr")
noise=$(awk -v d="$noise2" 'BEGIN { print d / sqrt(2) }')
denoised() { awk -v e="$1" -v n="$noise" 'BEGIN { v = e * e - n * n; print (v > 0 ? sqrt(v) : 0) }'; }
baked=$(rmse "$out/ref_baked.exr" "$out/ref${spp}_s1.exr"); fitted=$(rmse "$out/ref_fit.exr" "$out/ref${spp}_s1.exr")
fitted2=$(rmse "$out/ref_fit.exr" "$out/ref${spp}_s2.exr"); baked2=$(rmse "$out/ref_baked.exr" "$out/ref${spp}_s2.exr")
echo "reference noise (seed 1 vs 2, / sqrt 2): $(percent "$noise")"
echo "against seed 1 (the fitted target): package with the true look $(percent "$baked"), fit $(percent "$fitted");" \
  "noise removed: $(percent "$(denoised "$baked")"), $(percent "$(denoised "$fitted")")"
echo "against seed 2 (not fitted): package with the true look $(percent "$baked2"), fit $(percent "$fitted2");" \
  "noise removed: $(percent "$(denoised "$baked2")"), $(percent "$(denoised "$fitted2")")"

fi
if step 4; then
echo "== 4. blackbody emission (K = $kelvin_at_0 + $kelvin_per_unit T), $spp spp, $ref_size"
[[ -f "$out/bb${spp}.exr" ]] || "$bench_fit" blackbody "$sample" "$out/pref.firelook" "$frame" "$spp" "$out/bb${spp}.exr" \
  "$kelvin_per_unit" "$kelvin_at_0"
"$firelook" fit "$out/pref.firelook" --frame "$frame" --target "$out/bb${spp}.exr" -o "$out/bb_fit.json" \
  --image "$out/bb_fit.png" --difference "$out/bb_diff.png" 2>/dev/null | tee "$out/bb_fit.txt"
# target | fit | difference (x4), each over black.
"$bench_fit" montage "$out/blackbody.png" 4 "$out/bb${spp}.png" "$out/bb_fit.png" "$out/bb_diff.png"
echo "wrote $out/blackbody.png (target | fit | |fit - target| x4)"
fi
