#!/usr/bin/env bash
# Light from a direction chosen at run time (README, "Light from any direction"): bakes frame 6 of
# the bundled sample at SIZE once per light basis in LIGHTS (six-way, and the geodesic sphere of
# `--lights sphere`), then for COUNT directions uniform on the sphere (fixed seed) and one baked
# direction (the "top" light, which both bases bake) path-traces the light alone (the package's
# default look with no emission and every other light off) twice with different seeds, and judges
# each package's `firelook render --light-dir` weighting, and the others measured beside it, against
# the mean of the two (their difference gives the reference's noise, removed in quadrature).
# The references are the same for every basis (`reference --light-dir` traces the light itself in
# place of the basis' lights), traced once with the six-way scene, kept in OUT and reused.
# The light alone is noisy to trace (about 25% relative RMSE at 64 spp), so the baked direction, whose
# error is the bake's own, gets BAKED_SPP. Each bake's seconds, bytes and load go to OUT/bakes.txt
# (its --report beside it).
#   SIZE=64x64 COUNT=40 SPP=4096 BAKED_SPP=16384 SEED=16 LIGHTS="six-way sphere" scripts/bench/relight.sh [out-dir]
# (The README's earlier six-way table: SIZE=128x128 COUNT=20 SPP=1024 BAKED_SPP=8192 LIGHTS=six-way.)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="${1:-$root/out/bench/relight}"
size="${SIZE:-64x64}"
count="${COUNT:-40}"
spp="${SPP:-4096}"
baked_spp="${BAKED_SPP:-16384}"
seed="${SEED:-16}"
lights="${LIGHTS:-six-way sphere}"
"$root/scripts/build.sh" release firelook bench_relight >/dev/null
firelook="$root/build/release/baker/cli/firelook"
bench="$root/build/release/tests/relight/bench_relight"
sample="$root/samples/data/explosion"
mkdir -p "$out"
tag="f6_${size}"
# The six-way package gives the references' look (its light count) and the baked "top" direction.
for basis in six-way $lights; do
  package="$out/${basis//:/_}_$tag.firelook"
  [ -f "$package" ] && continue
  # The bake's own report: seconds by stage, peak memory, rank; and the load it ran under.
  "$firelook" bake "$sample" --up z --frames 6 --size "$size" --lights "$basis" -o "$package" \
    --report "$out/bake_${basis//:/_}_$tag.json" >/dev/null 2>&1 </dev/null
  printf '%s %s seconds %s bytes %d load %s\n' "$basis" "$size" \
    "$(grep -o '"seconds": *[0-9.]*' "$out/bake_${basis//:/_}_$tag.json" | head -1 | grep -o '[0-9.]*$')" \
    "$(stat -c %s "$package")" "$(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/bakes.txt"
done
six="$out/six-way_$tag.firelook"
"$bench" look "$six" "$out/light_only_$tag.json"
{ "$bench" directions "$count" "$seed"; "$bench" baked "$six" | grep '^baked_top '; } > "$out/directions_$tag.txt"
while read -r name x y z; do
  for s in 1 2; do
    ref="$out/ref_${tag}_${name}_s${s}.exr"
    [ -f "$ref" ] && continue
    "$firelook" reference "$sample" --up z --frame 6 --size "$size" --lights six-way --look "$out/light_only_$tag.json" \
      --light-dir "$x,$y,$z" --spp "$([[ $name == baked_* ]] && echo "$baked_spp" || echo "$spp")" --seed "$s" \
      -o "$ref" 2>/dev/null < /dev/null | tail -1
  done
done < "$out/directions_$tag.txt"
for basis in $lights; do
  package="$out/${basis//:/_}_$tag.firelook"
  echo "== $basis ($size, $(grep "^$basis $size " "$out/bakes.txt" | tail -1 | cut -d' ' -f3-))"
  "$bench" look "$package" "$out/light_only_${basis//:/_}_$tag.json"
  "$bench" judge "$package" 6 "$out/light_only_${basis//:/_}_$tag.json" "$out/directions_$tag.txt" "$out/ref_${tag}_"
done | tee "$out/table_$tag.txt"
