#!/usr/bin/env bash
# Configures and builds one flavour of FireLook into build/<flavour>.
#   scripts/build.sh release        RelWithDebInfo (the tools you run)
#   scripts/build.sh asan           AddressSanitizer + UndefinedBehaviorSanitizer
#   scripts/build.sh tsan           ThreadSanitizer (scripts/test.sh builds only firelook_tsan_tests)
# Extra arguments go to the build tool (e.g. a target name).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
flavour="${1:-release}"; shift || true
# The sanitizer flavours keep line tables only (-g1): their reports still name file and line, and
# they compile and link faster than with full debug information (they are built in every CI run).
lines_only=(-DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG")
# Nor do they build the benchmarks, reports and samples that no test runs (FIRELOOK_BUILD_BENCHMARKS,
# tests/CMakeLists.txt); the release flavour builds them so that they keep compiling.
sanitized=("${lines_only[@]}" -DFIRELOOK_BUILD_BENCHMARKS=OFF)
case "$flavour" in
  release) extra=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIRELOOK_BUILD_BENCHMARKS=ON) ;;
  asan)    extra=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIRELOOK_SANITIZE=ON "${sanitized[@]}") ;;
  tsan)    extra=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DFIRELOOK_SANITIZE_THREAD=ON "${sanitized[@]}") ;;
  *) echo "build.sh: unknown flavour '$flavour' (release|asan|tsan)" >&2; exit 2 ;;
esac
jobs="$(nproc 2>/dev/null || echo 2)"
cmake -S "$root" -B "$root/build/$flavour" -G Ninja "${extra[@]}" >/dev/null
cmake --build "$root/build/$flavour" -j "$jobs" -- "$@"
