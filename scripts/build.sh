#!/usr/bin/env bash
# Configures and builds one flavour of FireLook into build/<flavour>.
#   scripts/build.sh release        RelWithDebInfo (the tools you run)
#   scripts/build.sh asan           AddressSanitizer + UndefinedBehaviorSanitizer
#   scripts/build.sh tsan           ThreadSanitizer (scripts/test.sh builds only firelook_tsan_tests)
# Extra arguments go to the build tool (e.g. a target name).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
flavour="${1:-release}"; shift || true
case "$flavour" in
  release) extra=(-DCMAKE_BUILD_TYPE=RelWithDebInfo) ;;
  asan)    extra=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIRELOOK_SANITIZE=ON) ;;
  tsan)    extra=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIRELOOK_SANITIZE_THREAD=ON) ;;
  *) echo "build.sh: unknown flavour '$flavour' (release|asan|tsan)" >&2; exit 2 ;;
esac
jobs="$(nproc 2>/dev/null || echo 2)"
cmake -S "$root" -B "$root/build/$flavour" -G Ninja "${extra[@]}" >/dev/null
cmake --build "$root/build/$flavour" -j "$jobs" -- "$@"
