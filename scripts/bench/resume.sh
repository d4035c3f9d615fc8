#!/usr/bin/env bash
# Issue 15's resume figure: a bake killed with SIGKILL once KEEP of its frames are finished, then
# resumed (`--resume`), against an uninterrupted bake with the same settings. Prints whether the
# packages are identical (cmp), the frames the resumed run reused, its wall time, and the time the
# uninterrupted bake spent on the frames the resumed run had to bake (trace + SVD seconds, from its
# --report), with the ratio of the two; and, less exposed to a machine whose load changes between the
# two bakes, the resumed run's wall time against its own time on those frames (its overhead).
#   scripts/bench/resume.sh [SEQUENCE] [OUT]
# Environment: KEEP (5), SIZE (128x128), UP (z), FIRELOOK (build/release's by default, built first
# when unset). Every frame of SEQUENCE is baked at the default settings otherwise.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
sequence="${1:-$root/samples/data/explosion}"
out="${2:-$root/out/bench/resume}"
keep="${KEEP:-5}"; size="${SIZE:-128x128}"; up="${UP:-z}"
if [[ -z "${FIRELOOK:-}" ]]; then "$root/scripts/build.sh" release firelook >/dev/null; fi
firelook="${FIRELOOK:-$root/build/release/baker/cli/firelook}"
mkdir -p "$out"
rm -rf "$out/resumed.firelook" "$out/resumed.firelook.partial"
bake=("$firelook" bake "$sequence" --up "$up" --size "$size")

echo "== uninterrupted bake"
"${bake[@]}" -o "$out/whole.firelook" --report "$out/whole.json" >/dev/null
echo "== bake killed once $keep frames are finished"
"${bake[@]}" -o "$out/resumed.firelook" >/dev/null 2>&1 &
pid=$!
until [[ $(find "$out/resumed.firelook.partial" -name 'frame_*.firelook' 2>/dev/null | wc -l) -ge $keep ]]; do
  kill -0 "$pid" 2>/dev/null || { echo "resume.sh: the bake ended before $keep frames were kept" >&2; exit 1; }
  sleep 0.05
done
kill -KILL "$pid"; wait "$pid" 2>/dev/null || true
echo "== resumed"
start=$(date +%s.%N)
"${bake[@]}" -o "$out/resumed.firelook" --resume --report "$out/resumed.json" >/dev/null
end=$(date +%s.%N)

cmp "$out/whole.firelook" "$out/resumed.firelook" && same=identical || same=DIFFERENT
# Per frame in a report (dump(2): one key a line): its number, whether it was resumed, trace + SVD s.
frames_of() { awk '/"frame":/ {gsub(/[^0-9]/, "", $2); f = $2} /"resumed":/ {r[f] = ($2 ~ /true/)}
                   /"trace_seconds":/ {t[f] += $2} /"svd_seconds":/ {t[f] += $2}
                   END {for (f in t) print f, r[f], t[f]}' "$1" | sort -n; }
missing=$(frames_of "$out/resumed.json" | awk '$2 == 0 {print $1}')
reused=$(frames_of "$out/resumed.json" | awk '$2 == 1' | wc -l)
baked_time=$(frames_of "$out/whole.json" | awk -v list=" $(echo $missing) " 'index(list, " " $1 " ") {s += $3} END {printf "%.1f", s}')
own_time=$(frames_of "$out/resumed.json" | awk '$2 == 0 {s += $3} END {printf "%.1f", s}')
wall=$(echo "$end $start" | awk '{printf "%.1f", $1 - $2}')
echo "packages: $same; resumed run reused $reused frames and baked $(echo $missing | wc -w) ($(echo $missing))"
echo "resumed run: $wall s; the same frames in the uninterrupted bake: $baked_time s; ratio $(echo "$wall $baked_time" | awk '{printf "%.2f", $1 / $2}')"
echo "resumed run against its own trace + SVD time on those frames ($own_time s): ratio $(echo "$wall $own_time" | awk '{printf "%.2f", $1 / $2}')"
