#!/usr/bin/env bash
# The speed-vs-error sweep end to end on a tiny setting (QUICK=1: one frame, 32x32, two
# settings, few photons): a CSV row per setting with finite figures, three plots and the
# Pareto fronts. Checks the plumbing, not the figures (those come from the full sweep).
#   speed_vs_error_quick_test.sh FIRELOOK_EXE
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
work="$(mktemp -d "${TMPDIR:-/tmp}/firelook-sweep-test.XXXXXX")"
trap 'rm -rf "$work"' EXIT
FIRELOOK="$1" QUICK=1 REFERENCES="$work/refs" "$root/scripts/bench/speed_vs_error.sh" \
  "$root/samples/data/explosion" "$work/out" > "$work/log.txt" 2>&1 || { cat "$work/log.txt"; exit 1; }
fail() { echo "FAIL: $*"; cat "$work/log.txt"; exit 1; }
csv="$work/out/sweep.csv"
[[ $(wc -l < "$csv") -eq 3 ]] || fail "expected a header and 2 rows in sweep.csv"
grep -q '^quick-baseline,2,' "$csv" || fail "baseline row missing"
grep -q '^quick-rank-2,2,' "$csv" || fail "rank row missing"
if grep -qiE 'nan|inf' "$csv"; then fail "non-finite figure in sweep.csv"; fi
for plot in runtime bake package; do
  [[ -s "$work/out/error-vs-$plot.png" ]] || fail "plot error-vs-$plot.png missing"
  [[ $(head -c 4 "$work/out/error-vs-$plot.png" | od -An -c | tr -d ' ') == '211PNG' ]] || fail "error-vs-$plot.png is not a PNG"
done
grep -q 'Pareto front' "$work/out/pareto.txt" || fail "pareto.txt missing"
grep -q 'quick-' "$work/out/pareto.txt" || fail "no setting on any Pareto front"
echo "speed-vs-error sweep quick run: OK"
