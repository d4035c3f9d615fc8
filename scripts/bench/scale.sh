#!/usr/bin/env bash
# How the baker scales with the grid (issue 11): one real frame upsampled N times per axis
# (firelook_upsample, quadratic), each baked as a one-frame sequence under /usr/bin/time -v and
# measured with `firelook bench`. Prints one row per factor: active density voxels, bake
# seconds, peak memory (the bake report's and time's maximum RSS, as a cross-check), package
# bytes and the bench's error figures.
#   scripts/bench/scale.sh
# Environment: FACTORS ("1 2 4 6"), FRAME (samples/data/explosion/fluid_data_0012.vdb, the VDB
# file to upsample), SIZE (256x256), LOOKS (8), SPP (256), ALPHA_RAYS (8: the exact alpha's rays per
# pixel along each axis), UP (z), OUT (out/bench/scale),
# BAKE_ARGS (extra `firelook bake` arguments, e.g. "--config B.json --memory-budget 8G"),
# FIRELOOK and UPSAMPLE (the binaries; build/release's by default, built first when either is unset).
# Output in OUT: xN/seq/ (the upsampled frame), xN/package.firelook, xN/{bake,bench}.* and
# scale.csv (bench --csv, one row per factor). References are cached per factor in
# xN/references: the bench's cache key does not include the grid, so factors must not share one
# (and a new FRAME needs a new OUT). Needs GNU time (Debian package `time`).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
factors="${FACTORS:-1 2 4 6}"
frame="${FRAME:-$root/samples/data/explosion/fluid_data_0012.vdb}"
size="${SIZE:-256x256}"; looks="${LOOKS:-8}"; spp="${SPP:-256}"; up="${UP:-z}"; alpha_rays="${ALPHA_RAYS:-8}"
read -r -a bake_args <<< "${BAKE_ARGS:-}"
out="${OUT:-$root/out/bench/scale}"
[[ -x /usr/bin/time ]] || { echo "scale.sh: needs GNU time as /usr/bin/time (apt-get install time)" >&2; exit 1; }
if [[ -z "${FIRELOOK:-}" || -z "${UPSAMPLE:-}" ]]; then
  "$root/scripts/build.sh" release firelook firelook_upsample >/dev/null
fi
firelook="${FIRELOOK:-$root/build/release/baker/cli/firelook}"
upsample="${UPSAMPLE:-$root/build/release/tests/tools/firelook_upsample}"
csv="$out/scale.csv"
mkdir -p "$out"
rm -f "$csv"

for n in $factors; do
  dir="$out/x$n"; seq="$dir/seq"
  echo "== x$n"
  rm -rf "$seq"; mkdir -p "$seq"
  # The file keeps its name: the sequence reader numbers frames from it.
  "$upsample" "$frame" "$seq/$(basename "$frame")" --factor "$n"
  "$firelook" info "$seq" --json > "$dir/info.json"
  /usr/bin/time -v -o "$dir/bake.time" "$firelook" bake "$seq" -o "$dir/package.firelook" --size "$size" \
    --up "$up" --report "$dir/bake.json" "${bake_args[@]}" > "$dir/bake.txt"
  tail -n 1 "$dir/bake.txt"
  "$firelook" bench "$seq" --package "$dir/package.firelook" --looks "$looks" --spp "$spp" \
    --reference-cache "$dir/references" --bake-report "$dir/bake.json" --alpha-rays "$alpha_rays" \
    --csv "$csv" --label "x$n" --json "$dir/bench.json" > "$dir/bench.txt"
done

# A CSV cell by column name (columns added to `bench --csv` later do not shift the table),
# printed with FORMAT when it is a number, as is when not (null), "missing" without the column.
cell() {  # cell LABEL COLUMN FORMAT
  awk -F, -v label="$1" -v column="$2" -v format="$3" '
    NR == 1 { for (i = 1; i <= NF; i++) if ($i == column) c = i; next }
    $1 == label { v = c ? $c : "missing"; print (v ~ /^-?[0-9.eE+-]+$/ ? sprintf(format, v) : v); exit }' "$csv"
}
echo
echo "frame $(basename "$frame"), $size, $looks looks x $spp spp; relative RMSE with the reference's noise removed"
printf '%-6s %12s %8s %9s %9s %11s %11s %10s %11s %11s %9s\n' factor active_voxels bake_s peak_MiB time_MiB \
  package_B median_rmse worst_rmse median_bias worst_bias alpha_err
for n in $factors; do
  dir="$out/x$n"
  voxels="$(awk '/"density": \{/ { d = 1 } d && /"active_voxels"/ { gsub(/[^0-9]/, ""); print; exit }' "$dir/info.json")"
  rss_kib="$(awk -F': ' '/Maximum resident set size/ { print $2 }' "$dir/bake.time")"
  printf '%-6s %12s %8s %9s %9s %11s %11s %10s %11s %11s %9s\n' "x$n" "$voxels" "$(cell "x$n" bake_seconds %.1f)" \
    "$(cell "x$n" bake_peak_memory_mib %.0f)" "$((rss_kib / 1024))" "$(cell "x$n" package_bytes %d)" \
    "$(cell "x$n" median_noise_corrected_rmse %.5f)" "$(cell "x$n" worst_noise_corrected_rmse %.5f)" \
    "$(cell "x$n" median_image_mean_bias %.5f)" "$(cell "x$n" worst_image_mean_bias %.5f)" \
    "$(cell "x$n" max_alpha_error %.5f)"
done
