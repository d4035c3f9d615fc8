#!/usr/bin/env bash
# Accuracy of a bake against the reference path tracer, regime by regime (issue 27): each regime
# bakes its frames at 128x128 with the default settings (unless its bake.json in
# scripts/bench/accuracy/ says otherwise), then `firelook bench` draws random looks over the baked
# ranges, path-traces each at 1024 spp and splits the error by source. Alpha is judged against 8x8
# exact rays per pixel. Prints one table (also written as OUT/regimes.csv and OUT/regimes.txt):
# noise-corrected relative RMSE median and worst, the image-mean bias of the worst channel with the
# reference's own noise of the mean, the bias split (tracing / interpolation / compression), alpha,
# the photon noise the bake predicted for its worst column beside the tracing error bench measured
# (median over the looks, the reference's noise removed), the look error the bake predicted (the
# largest of the regime's frames: `pred %`, to hold the worst look) and the bake's seconds.
#   emission      samples/data/explosion frames 3, 7, 11: flame and fresh smoke, emission dominates
#   sunlit-smoke  samples/data/smoke frame 20: smoke lit by the scene's light, emission off
#   dense-0.7     frame 20 as dense smoke (k_s at the top of its range: optical depth 5-20), albedo 0.7
#   dense-0.95    the same at albedo 0.95 (tens of scattering orders)
#   thin-late     samples/data/smoke frame 30: thin, spread-out late smoke, emission on
#   corners       explosion frame 7, every look on a corner of the (T_c, k_s, k_f) ranges
# References are kept in out/bench/references (REFERENCES=dir to move them); REGIMES="a b" runs some;
# FIRELOOK=path measures that binary instead of building build/release's (which a build going on
# beside the run would replace under it); BAKE_ARGS="--quality preview" adds arguments to every bake.
#   scripts/bench/accuracy.sh [out-dir]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="${1:-$root/out/bench/accuracy}"
if [[ -z "${FIRELOOK:-}" ]]; then
  "$root/scripts/build.sh" release firelook >/dev/null
fi
firelook="${FIRELOOK:-$root/build/release/baker/cli/firelook}"
configs="$root/scripts/bench/accuracy"
references="${REFERENCES:-$root/out/bench/references}"
read -r -a bake_args <<< "${BAKE_ARGS:-}"
mkdir -p "$out"
csv="$out/regimes.csv"
rm -f "$csv"

# regime NAME SEQUENCE FRAMES LOOKS_PER_FRAME BAKE_CONFIG|- BENCH_FLAGS...
regime() {
  local name="$1" sequence="$2" frames="$3" looks="$4" config="$5"
  shift 5
  local config_args=()
  [[ "$config" != - ]] && config_args=(--config "$configs/$config")
  echo "== $name"
  "$firelook" bake "$sequence" --up z --size 128x128 --frames "$frames" "${config_args[@]}" "${bake_args[@]}" \
    -o "$out/$name.firelook" --report "$out/$name.bake.json" | tee "$out/$name.bake.txt"
  "$firelook" bench "$sequence" --package "$out/$name.firelook" --frames "$frames" --looks "$looks" \
    --spp 1024 --split --json "$out/$name.json" --csv "$csv" --label "$name" \
    --bake-report "$out/$name.bake.json" --reference-cache "$references" "$@" > "$out/$name.summary.json"
}

sample="$root/samples/data/explosion"
smoke="$root/samples/data/smoke"
selected="${REGIMES:-emission sunlit-smoke dense-0.7 dense-0.95 thin-late corners}"
for name in $selected; do
  case "$name" in
    emission)     regime emission "$sample" 3,7,11 7 - ;;
    sunlit-smoke) regime sunlit-smoke "$smoke" 20 8 - --emission-scale 0 ;;
    dense-0.7)    regime dense-0.7 "$smoke" 20 6 dense_albedo_0.7.json --emission-scale 0.1 ;;
    dense-0.95)   regime dense-0.95 "$smoke" 20 6 dense_albedo_0.95.json --emission-scale 0.1 ;;
    thin-late)    regime thin-late "$smoke" 30 6 - ;;
    corners)      regime corners "$sample" 7 8 - --corners ;;
    *) echo "accuracy.sh: unknown regime '$name'" >&2; exit 2 ;;
  esac
done

# The table: the bias split comes from each regime's JSON (bench --split), the rest from the CSV.
{
  printf '%-13s %6s %9s %9s %10s %10s %24s %7s %16s %8s %7s\n' regime looks "median %" "worst %" "bias %" "ref noise %" \
    "bias: trace/interp/comp %" alpha "noise pred/trace" "pred %" "bake s"
  tail -n +2 "$csv" | while IFS=, read -r label looks med_rmse worst_rmse ref_noise med_corr worst_corr alpha \
      med_bias worst_bias coeff_us image_ms bytes bake_s bake_mib channel_bias mean_noise; do
    whole="$(tr -d ' \n' < "$out/$label.json")"
    split="$(echo "$whole" | grep -o '"split_median":{[^}]*}' || true)"
    field() { echo "$split" | grep -o "\"$1\":[-0-9.e+]*" | cut -d: -f2; }
    predicted="$(echo "$whole" | grep -o '"predicted_photon_noise":[-0-9.e+]*' | head -1 | cut -d: -f2)"
    look_predicted="$(echo "$whole" | grep -o '"predicted_look_error":[-0-9.e+]*' | head -1 | cut -d: -f2)"
    awk -v l="$label" -v n="$looks" -v m="$med_corr" -v w="$worst_corr" -v b="$channel_bias" -v r="$mean_noise" \
        -v bt="$(field tracing_bias)" -v bi="$(field interpolation_bias)" -v bc="$(field compression_bias)" \
        -v a="$alpha" -v s="$bake_s" -v p="${predicted:-0}" -v tc="$(field tracing_noise_corrected)" \
        -v lp="${look_predicted:-0}" 'BEGIN {
      printf "%-13s %6d %9.2f %9.2f %+10.2f %10.3f %+8.2f/%+6.2f/%+6.2f %7.4f %8.2f/%6.2f %8.2f %7.0f\n",
             l, n, 100*m, 100*w, 100*b, 100*r, 100*bt, 100*bi, 100*bc, a, 100*p, 100*tc, 100*lp, s }'
  done
} | tee "$out/regimes.txt"
