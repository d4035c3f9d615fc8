#!/usr/bin/env bash
# Issue 15's merge figure: SEQUENCE baked once whole and once as SHARDS contiguous shards (each with
# its own thread count: 1, 2, 1, 2, ...), the shards merged with `firelook merge`; prints whether
# the two packages are byte-identical (cmp) and the times.
#   scripts/bench/merge_shards.sh [SEQUENCE] [OUT]
# Environment: SHARDS (3), SIZE (256x256), UP (z), WHOLE (an existing one-shot package of the same
# settings to compare with, instead of baking it), FIRELOOK (build/release's by default, built
# first when unset).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
sequence="${1:-$root/samples/data/explosion}"
out="${2:-$root/out/bench/merge}"
shards="${SHARDS:-3}"; size="${SIZE:-256x256}"; up="${UP:-z}"
if [[ -z "${FIRELOOK:-}" ]]; then "$root/scripts/build.sh" release firelook >/dev/null; fi
firelook="${FIRELOOK:-$root/build/release/baker/cli/firelook}"
mkdir -p "$out"
bake=("$firelook" bake "$sequence" --up "$up" --size "$size")
whole="${WHOLE:-$out/whole.firelook}"
if [[ -z "${WHOLE:-}" ]]; then
  echo "== one-shot bake"
  s=$(date +%s); "${bake[@]}" -o "$whole" >/dev/null; echo "one-shot: $(( $(date +%s) - s )) s"
fi
# The sequence's frame numbers, from `firelook info` (its table: one row per frame).
mapfile -t frames < <("$firelook" info "$sequence" | awk '$1 ~ /^[0-9]+$/ {print $1}')
n=${#frames[@]}
parts=()
for ((k = 0; k < shards; ++k)); do
  first=${frames[$(( k * n / shards ))]}; last=${frames[$(( (k + 1) * n / shards - 1 ))]}
  threads=$(( k % 2 + 1 ))
  echo "== shard $((k + 1))/$shards: frames $first-$last, $threads thread(s)"
  s=$(date +%s)
  "${bake[@]}" --frames "$first-$last" --threads "$threads" -o "$out/part_$k.firelook" >/dev/null
  echo "shard $((k + 1)): $(( $(date +%s) - s )) s"
  parts+=("$out/part_$k.firelook")
done
"$firelook" merge "${parts[@]}" -o "$out/merged.firelook"
if cmp "$whole" "$out/merged.firelook"; then echo "merged shards: identical to the one-shot bake ($(stat -c %s "$whole") bytes)"
else echo "merged shards: DIFFERENT from the one-shot bake"; exit 1; fi
