#!/usr/bin/env bash
# Light from a direction chosen at run time (README, "Light from any direction"): bakes frame 6 of
# the bundled sample at 128x128 with the six-way lights, then for 20 directions uniform on the
# sphere (fixed seed) and one baked direction (the six-way "top" light) path-traces the light alone
# (the package's default look with no emission and every other light off) twice with different
# seeds, and judges `firelook render --light-dir`'s weighting, and the others measured beside it,
# against the mean of the two (their difference gives the reference's noise, removed in quadrature).
# The light alone is noisy to trace (about 25% relative RMSE at 64 spp), so the baked direction, whose
# error is the bake's own (about 1%), gets BAKED_SPP. References are kept in OUT and reused.
#   SPP=1024 BAKED_SPP=8192 SEED=16 scripts/bench/relight.sh [out-dir]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="${1:-$root/out/bench/relight}"
spp="${SPP:-1024}"
baked_spp="${BAKED_SPP:-8192}"
seed="${SEED:-16}"
"$root/scripts/build.sh" release firelook bench_relight >/dev/null
firelook="$root/build/release/baker/cli/firelook"
bench="$root/build/release/tests/relight/bench_relight"
sample="$root/samples/data/explosion"
mkdir -p "$out"
package="$out/six_way_f6_128.firelook"
[ -f "$package" ] || "$firelook" bake "$sample" --up z --frames 6 --size 128x128 --lights six-way -o "$package"
"$bench" look "$package" "$out/light_only.json"
{ "$bench" directions 20 "$seed"; "$bench" baked "$package" | grep '^baked_top '; } > "$out/directions.txt"
while read -r name x y z; do
  for s in 1 2; do
    ref="$out/ref_${name}_s${s}.exr"
    [ -f "$ref" ] && continue
    "$firelook" reference "$sample" --up z --frame 6 --size 128x128 --lights six-way --look "$out/light_only.json" \
      --light-dir "$x,$y,$z" --spp "$([[ $name == baked_* ]] && echo "$baked_spp" || echo "$spp")" --seed "$s" \
      -o "$ref" 2>/dev/null < /dev/null | tail -1
  done
done < "$out/directions.txt"
"$bench" judge "$package" 6 "$out/light_only.json" "$out" | tee "$out/table.txt"
