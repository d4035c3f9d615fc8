#!/usr/bin/env bash
# The runtime on real packages (tests/world/bench_runtime.cpp says what it measures): bakes frame 7
# of the bundled explosion at 256x256 and 512x512 once (the 512 bake takes minutes; a package
# already in the folder is reused) and runs bench_runtime on both beside its synthetic package,
# pinned to one core: coefficients of one instance and of 10,000 in one update, and each frame's
# CPU image from the resident form (rank, bytes read, ms, ratio to the plain-read bandwidth
# measured in the same run, share of pixels skipped).
#   scripts/bench/runtime_real.sh [out-dir] [core] [bench_runtime options, e.g. --quick]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="${1:-$root/out/bench/runtime_real}"
core="${2:-1}"
shift $(( $# < 2 ? $# : 2 ))
"$root/scripts/build.sh" release firelook bench_runtime >/dev/null
firelook="$root/build/release/baker/cli/firelook"
mkdir -p "$out"
packages=()
for size in 256 512; do
  package="$out/explosion_${size}.firelook"
  if [ ! -f "$package" ]; then
    "$firelook" bake "$root/samples/data/explosion" --up z --size "${size}x${size}" --frames 7 -o "$package" >/dev/null
  fi
  packages+=(--package "$package")
done
taskset -c "$core" "$root/build/release/tests/world/bench_runtime" "${packages[@]}" "$@"
