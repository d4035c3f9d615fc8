#!/usr/bin/env bash
# The README's test command: installs what is missing, builds the normal and the
# sanitizer (ASan + UBSan) flavours and runs the whole suite, each test in one of them (below);
# then the thread tests under ThreadSanitizer.
# Exits non-zero on any failure. The release flavour builds the benchmarks (so they keep compiling)
# but does not run them; the sanitizer flavours do not build them (scripts/build.sh).
# Prints the seconds of each phase at the end: CI must stay well under its 45 minutes
# (docs/testing.md, "The CI run").
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
start=$(date +%s)
phase_start=$start
phases=()
# phase_done NAME: records how long the phase that just ended took.
phase_done() {
  local now; now=$(date +%s)
  phases+=("$(printf '%-14s %5d s' "$1" $(( now - phase_start )))")
  phase_start=$now
}
"$root/scripts/setup.sh"
phase_done setup
jobs="$(nproc 2>/dev/null || echo 2)"
for flavour in release asan; do
  echo "== build ($flavour)"
  # The release flavour runs only the release-only labels (below), so it builds only what they and
  # the user need (tests/CMakeLists.txt, firelook_release_suite).
  if [[ "$flavour" == release ]]; then "$root/scripts/build.sh" release firelook_release_suite
  else "$root/scripts/build.sh" "$flavour"; fi
  phase_done "build $flavour"
  echo "== tests ($flavour)"
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  # Each test runs once, in the flavour that checks the most: under ASan + UBSan (the same -O2 code
  # with every access checked), except three labels that run in the release flavour only. The
  # accuracy guard (tests/accuracy): the same arithmetic under the sanitizers takes ten times as
  # long. The Blender tests (tests/blender): Blender is not sanitized, and the references they trace
  # take ten times as long under the sanitizers. The pipeline tests (tests/pipeline): scripts, a Slurm cluster and CMake around the bakes
  # and merges that tests/bake and tests/cli run under the sanitizers. The tools (tests/tools): the
  # scale bake's memory estimate is held to the peak of the normal build, which ASan's shadow
  # memory inflates.
  release_only='accuracy|blender|pipeline|tools'  # tests/CMakeLists.txt's FIRELOOK_RELEASE_ONLY_LABELS
  if [[ "$flavour" == release ]]; then selection=(-L "$release_only"); else selection=(-LE "bench|$release_only"); fi
  # Per-test seconds in build/<flavour>/ctest-junit.xml: where the time goes when CI grows slow.
  ctest --test-dir "$root/build/$flavour" --output-on-failure -j "$jobs" "${selection[@]}" \
    --output-junit "$root/build/$flavour/ctest-junit.xml"
  phase_done "tests $flavour"
done
# ThreadSanitizer (issue 14): only the test of worlds on several threads and the libraries it needs
# (a whole TSan suite would take as long again); no test is registered where TSan cannot run.
echo "== build (tsan: thread tests only)"
"$root/scripts/build.sh" tsan firelook_tsan_tests
echo "== tests (tsan)"
TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 \
  ctest --test-dir "$root/build/tsan" --output-on-failure -R '^PluginApiThreads\.'
phase_done tsan
# Bounded fuzzing (issue 7) of every reader of files: the package reader, the look file and the VDB
# front end, FUZZ_SECONDS each (default 30) from the seed corpus in tests/fuzz/corpus (clang, ASan +
# UBSan). The VDB front end checks a file's structure before OpenVDB 10 parses it
# (formats/vdb/file_structure.h), which keeps OpenVDB's own crashes on crafted files out
# (tests/fuzz/README.md). FUZZ_SECONDS=0 skips this step.
if [[ "${FUZZ_SECONDS:-30}" != 0 ]]; then
  echo "== fuzzing (${FUZZ_SECONDS:-30} s per target)"
  FUZZ_BUILD_DIR="$root/build/fuzz" "$root/scripts/fuzz.sh" "${FUZZ_SECONDS:-30}" package_reader look_file vdb_sequence
  phase_done fuzz
fi
printf '   %s\n' "${phases[@]}"
echo "== all tests passed in $(( $(date +%s) - start )) s"
