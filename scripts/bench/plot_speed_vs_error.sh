#!/usr/bin/env bash
# Plots a speed-vs-error sweep (scripts/bench/speed_vs_error.sh) with gnuplot and
# lists the Pareto front of each plot: the settings no other setting beats on
# both cost and median relative RMSE. The error plotted is the noise-corrected
# relative RMSE (the reference's own noise removed in quadrature), because the
# raw figure's ~1.3% of reference noise would hide the differences between settings.
#   scripts/bench/plot_speed_vs_error.sh SWEEP.csv OUT_DIR
set -euo pipefail
csv="$1"; out="$2"
mkdir -p "$out"
source "$(dirname "${BASH_SOURCE[0]}")/csv_column.sh"
col_rmse=$(column median_noise_corrected_rmse); col_worst=$(column worst_noise_corrected_rmse)
col_raw=$(column median_relative_rmse); col_alpha=$(column max_alpha_error)
declare -A cost_col=([runtime]=$(column median_image_ms) [package]=$(column package_bytes) [bake]=$(column bake_seconds))
declare -A cost_name=([runtime]="image reconstruction, ms (128x128 unless the label says)"
                      [package]="package size, MB" [bake]="bake time, s")
declare -A cost_scale=([runtime]=1 [package]=1e-6 [bake]=1)

: > "$out/pareto.txt"
for cost in runtime bake package; do
  c=${cost_col[$cost]}; scale=${cost_scale[$cost]}
  # Pareto front: keep a row unless another is no worse on both axes and better on one.
  awk -F, -v c="$c" -v e="$col_rmse" -v w="$col_worst" -v r="$col_raw" -v a="$col_alpha" -v s="$scale" \
    'NR > 1 && $c != "null" { n++; label[n] = $1; x[n] = $c * s; y[n] = $e; worst[n] = $w; raw[n] = $r; alpha[n] = $a }
    END {
      for (i = 1; i <= n; i++) {
        dominated = 0
        for (j = 1; j <= n; j++)
          if (j != i && x[j] <= x[i] && y[j] <= y[i] && (x[j] < x[i] || y[j] < y[i])) dominated = 1
        if (!dominated) printf "%s,%.6g,%.6g,%.6g,%.6g,%.6g\n", label[i], x[i], y[i], worst[i], raw[i], alpha[i]
      }
    }' "$csv" | sort -t, -k2,2g > "$out/pareto-$cost.dat"
  {
    echo "Pareto front, noise-corrected median relative RMSE against ${cost_name[$cost]}:"
    awk -F, '{ printf "  %-16s cost %-10.4g median %.2f%% (raw %.2f%%)  worst %.2f%%  max alpha err %.4f\n", $1, $2, 100 * $3, 100 * $5, 100 * $4, $6 }' \
      "$out/pareto-$cost.dat"
  } >> "$out/pareto.txt"
  gnuplot <<GP
set terminal pngcairo size 900,600 font ",10"
set output "$out/error-vs-$cost.png"
set datafile separator ","
set key top right
set grid
set logscale x
set xlabel "${cost_name[$cost]}"
set ylabel "relative RMSE vs reference, its noise removed (%)"
set title "FireLook speed against error: $cost (one knob varied per point)"
plot "$csv" every ::1 using (\$$c * $scale):(100 * \$$col_worst) with points pt 6 lc rgb "#999999" title "worst look", \
     "$csv" every ::1 using (\$$c * $scale):(100 * \$$col_rmse) with points pt 7 lc rgb "#c0392b" title "median", \
     "$out/pareto-$cost.dat" using 2:(100 * \$3) with lines lw 2 lc rgb "#2c3e50" title "Pareto front (median)", \
     "$out/pareto-$cost.dat" using 2:(100 * \$3):1 with labels offset char 0.6,0.6 left font ",9" notitle
GP
done
cat "$out/pareto.txt"
