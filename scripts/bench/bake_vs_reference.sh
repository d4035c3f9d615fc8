#!/usr/bin/env bash
# What a bake costs against what it replaces (issue 30 item 2): per image size, the seconds to bake
# one frame against the seconds `firelook reference` takes to render the same frame and size to a
# relative noise of TARGET_NOISE (2%), measured in the same run, with the error each reaches.
#   scripts/bench/bake_vs_reference.sh [OUT]
# For every factor in FACTORS (1: the bundled sample's frame; N > 1: that frame upsampled N times
# per axis by firelook_upsample) and every size in SIZES:
#   - bake: `firelook bake --frames FRAME --size S --quality Q` for each Q in QUALITIES (wall
#     seconds; the predicted look error from its report);
#   - reference: a pilot at PILOT_SPP samples per pixel gives the reference's own estimate of its
#     relative RMSE e; noise falls as 1/sqrt(spp), so TARGET_NOISE needs PILOT_SPP (e / target)^2
#     samples, and that render is timed (its own estimate is printed beside, as a check);
#   - error: `firelook bench --looks LOOKS --spp JUDGE_SPP` on each bake (noise-corrected relative
#     RMSE median and worst, worst-channel image-mean bias), JUDGE_SPP defaulting to the reference's spp (a
#     judge of 2% noise resolves errors down to about 0.3%; below that the noise correction
#     reports 0: raise JUDGE_SPP to see them).
# Ratio = bake seconds / reference seconds: what the issue bars (<= 0.5 at 128x128, <= 0.25 at
# 256x256). The machine's load moves both; run it on an idle machine.
# Environment: SIZES ("64 128 256 512"), FACTORS ("1 4"), QUALITIES ("default"), FRAME (12), TARGET_NOISE (0.02),
# PILOT_SPP (16), LOOKS (2), JUDGE_SPP, UP (z), BAKE_ARGS (extra `firelook bake` arguments),
# FIRELOOK and UPSAMPLE (the binaries; build/release's by default, built first when either is unset).
# Output in OUT (out/bench/bake_vs_reference): fN/SIZE/{Q.firelook,Q.bake.json,Q.bench.json,...}
# and bake_vs_reference.csv, one row per factor, size and quality.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
sizes="${SIZES:-64 128 256 512}"; factors="${FACTORS:-1 4}"; frame="${FRAME:-12}"
qualities="${QUALITIES:-default}"; target="${TARGET_NOISE:-0.02}"; pilot_spp="${PILOT_SPP:-16}"; looks="${LOOKS:-2}"; up="${UP:-z}"
read -r -a bake_args <<< "${BAKE_ARGS:-}"
out="${1:-$root/out/bench/bake_vs_reference}"
if [[ -z "${FIRELOOK:-}" || -z "${UPSAMPLE:-}" ]]; then
  "$root/scripts/build.sh" release firelook firelook_upsample >/dev/null
fi
firelook="${FIRELOOK:-$root/build/release/baker/cli/firelook}"
upsample="${UPSAMPLE:-$root/build/release/tests/tools/firelook_upsample}"
sample="$root/samples/data/explosion"
csv="$out/bake_vs_reference.csv"
mkdir -p "$out"
echo "factor,size,quality,bake_s,reference_spp,reference_s,ratio,reference_noise,bake_noise_corrected_rmse,bake_worst_noise_corrected_rmse,bake_worst_channel_bias,predicted_look_error,load_before" > "$csv"

now() { date +%s.%N; }
# The "estimated relative RMSE X" a reference prints.
estimated_rmse() { sed -n 's/.*estimated relative RMSE \([0-9.eE+-]*\).*/\1/p' "$1" | tail -n 1; }
json_number() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))$2)" "$1"; }
# render_reference SPP NAME: the reference of this row's frame and size as DIR/NAME.exr, its
# output (with the noise estimate) in DIR/NAME.txt.
render_reference() {
  "$firelook" reference "$seq" --frame "$frame" --size "${s}x$s" --up "$up" --spp "$1" \
    -o "$dir/$2.exr" > "$dir/$2.txt" 2> /dev/null
}

for n in $factors; do
  if [[ "$n" == 1 ]]; then
    seq="$sample"
  else
    seq="$out/f$n/seq"
    if [[ ! -d "$seq" ]]; then
      mkdir -p "$seq"
      vdb="$(printf '%s/fluid_data_%04d.vdb' "$sample" "$frame")"
      # The file keeps its name: the sequence reader numbers frames from it.
      "$upsample" "$vdb" "$seq/$(basename "$vdb")" --factor "$n"
    fi
  fi
  for s in $sizes; do
    dir="$out/f$n/$s"; mkdir -p "$dir"
    # The machine's load when the row starts (1-minute average): the seconds are upper bounds above 0.
    load=$(cut -d' ' -f1 /proc/loadavg)
    echo "== factor $n, ${s}x$s (load $load)"
    declare -A bake_s=()
    for q in $qualities; do
      t0=$(now)
      "$firelook" bake "$seq" --frames "$frame" --size "${s}x$s" --up "$up" --quality "$q" -o "$dir/$q.firelook" \
        --report "$dir/$q.bake.json" "${bake_args[@]}" > "$dir/$q.bake.txt" 2> "$dir/$q.bake.err"
      bake_s[$q]=$(python3 -c "print($(now) - $t0)")
    done
    render_reference "$pilot_spp" pilot
    pilot_rmse=$(estimated_rmse "$dir/pilot.txt")
    spp=$(python3 -c "import math; print(max(1, math.ceil($pilot_spp * ($pilot_rmse / $target) ** 2)))")
    t0=$(now)
    render_reference "$spp" reference
    ref_s=$(python3 -c "print($(now) - $t0)")
    ref_noise=$(estimated_rmse "$dir/reference.txt")
    for q in $qualities; do
      # The judge's references are cached in the row's folder: every quality is judged on the same ones.
      "$firelook" bench "$seq" --package "$dir/$q.firelook" --frames "$frame" --looks "$looks" \
        --spp "${JUDGE_SPP:-$spp}" --reference-cache "$dir/judge" --json "$dir/$q.bench.json" > "$dir/$q.bench.txt" 2> /dev/null
      rmse=$(json_number "$dir/$q.bench.json" "['summary']['median_noise_corrected_rmse']")
      worst=$(json_number "$dir/$q.bench.json" "['summary']['worst_noise_corrected_rmse']")
      bias=$(json_number "$dir/$q.bench.json" "['summary']['worst_channel_image_mean_bias']")
      predicted=$(json_number "$dir/$q.bake.json" "['frames'][0]['predicted_look_error']")
      ratio=$(python3 -c "print(${bake_s[$q]} / $ref_s)")
      echo "$n,$s,$q,${bake_s[$q]},$spp,$ref_s,$ratio,$ref_noise,$rmse,$worst,$bias,$predicted,$load" >> "$csv"
      python3 -c "print('  %s: bake %.1f s, reference %d spp %.1f s (noise %.4f), ratio %.2f; bake error %.4f (worst %.4f, predicted %.4f), bias %+.4f' % ('$q', ${bake_s[$q]}, $spp, $ref_s, $ref_noise, $ratio, $rmse, $worst, $predicted, $bias))"
    done
  done
done

echo
echo "frame $frame: bake against a reference of ${target} relative noise (same run)"
python3 - "$csv" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("%-7s %-5s %-8s %9s %9s %10s %7s %10s %11s %11s %10s %10s %6s" % (
    "factor", "size", "quality", "bake_s", "ref_spp", "ref_s", "ratio", "ref_noise", "bake_rmse", "bake_worst",
    "bake_bias", "predicted", "load"))
for r in rows:
    print("%-7s %-5s %-8s %9.1f %9s %10.1f %7.2f %10.4f %11.4f %11.4f %+10.4f %10.4f %6s" % (
        r["factor"], r["size"], r["quality"], float(r["bake_s"]), r["reference_spp"], float(r["reference_s"]),
        float(r["ratio"]), float(r["reference_noise"]), float(r["bake_noise_corrected_rmse"]),
        float(r["bake_worst_noise_corrected_rmse"]), float(r["bake_worst_channel_bias"]),
        float(r["predicted_look_error"]), r["load_before"]))
EOF
