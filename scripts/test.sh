#!/usr/bin/env bash
# The README's test command: installs what is missing, builds the normal and the
# sanitizer (ASan + UBSan) flavours, and runs the whole suite under both.
# Exits non-zero on any failure. Benchmarks are built but not run here.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
start=$(date +%s)
"$root/scripts/setup.sh"
jobs="$(nproc 2>/dev/null || echo 2)"
for flavour in release asan; do
  echo "== build ($flavour)"
  "$root/scripts/build.sh" "$flavour"
  echo "== tests ($flavour)"
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  ctest --test-dir "$root/build/$flavour" --output-on-failure -j "$jobs" -LE bench
done
echo "== all tests passed in $(( $(date +%s) - start )) s"
