#!/usr/bin/env bash
# Plots a storage sweep (scripts/bench/storage_sweep.sh) with gnuplot: the median look's
# noise-corrected relative RMSE and the max alpha error against package size, and lists the Pareto
# front on size and median error (with the worst look's error) in pareto.txt.
#   scripts/bench/plot_storage_sweep.sh STORAGE.csv OUT_DIR
set -euo pipefail
csv="$1"; out="$2"
mkdir -p "$out"
source "$(dirname "${BASH_SOURCE[0]}")/csv_column.sh"
b=$(column package_bytes); e=$(column median_noise_corrected_rmse); w=$(column worst_noise_corrected_rmse)
a=$(column max_alpha_error)

awk -F, -v b="$b" -v e="$e" -v w="$w" -v a="$a" \
  'NR > 1 { n++; label[n] = $1; x[n] = $b / 1e6; y[n] = $e; worst[n] = $w; alpha[n] = $a }
  END {
    for (i = 1; i <= n; i++) {
      dominated = 0
      for (j = 1; j <= n; j++)
        if (j != i && x[j] <= x[i] && y[j] <= y[i] && (x[j] < x[i] || y[j] < y[i])) dominated = 1
      if (!dominated) printf "%s,%.6g,%.6g,%.6g,%.6g\n", label[i], x[i], y[i], worst[i], alpha[i]
    }
  }' "$csv" | sort -t, -k2,2g > "$out/pareto-size.dat"
{
  echo "Pareto front, noise-corrected median relative RMSE against package size:"
  awk -F, '{ printf "  %-16s %8.3f MB  median %.3f%%  worst %.3f%%  max alpha err %.4f\n", $1, $2, 100 * $3, 100 * $4, $5 }' \
    "$out/pareto-size.dat"
  echo "Every setting:"
  awk -F, -v b="$b" -v e="$e" -v w="$w" -v a="$a" \
    'NR > 1 { printf "  %-16s %8.3f MB  median %.3f%%  worst %.3f%%  max alpha err %.4f\n", $1, $b / 1e6, 100 * $e, 100 * $w, $a }' "$csv"
} > "$out/pareto.txt"

gnuplot <<GP
set terminal pngcairo size 1200,500 font ",10"
set output "$out/error-vs-size.png"
set datafile separator ","
set multiplot layout 1,2 title "FireLook package size against error (frame codec settings one knob per point; repack --target-error / --target-size)"
target(x) = (strcol(1)[1:7] eq "target-") ? x : NaN
knob(x) = (strcol(1)[1:7] eq "target-") ? NaN : x
set grid
set logscale x
set xlabel "package size, MB"
set key top right
set ylabel "relative RMSE vs reference, its noise removed (%)"
plot "$csv" every ::1 using (knob(\$$b / 1e6)):(100 * \$$e) with points pt 7 lc rgb "#c0392b" title "median look (codec settings)", \
     "$csv" every ::1 using (target(\$$b / 1e6)):(100 * \$$e) with points pt 5 lc rgb "#27ae60" title "median look (repack targets)", \
     "$out/pareto-size.dat" using 2:(100 * \$3) with lines lw 2 lc rgb "#2c3e50" title "Pareto front (median)", \
     "$out/pareto-size.dat" using 2:(100 * \$3):1 with labels offset char 0.6,0.6 left font ",8" notitle
set ylabel "max alpha error against exact rays"
plot "$csv" every ::1 using (\$$b / 1e6):$a with points pt 7 lc rgb "#2980b9" title "max alpha error", \
     "$csv" every ::1 using (\$$b / 1e6):$a:1 with labels offset char 0.6,0.6 left font ",8" notitle
unset multiplot
GP
cat "$out/pareto.txt"
