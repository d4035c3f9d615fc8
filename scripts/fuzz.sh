#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) and runs each for a bounded time on a copy of
# its seed corpus (tests/fuzz/corpus/<target>). Prints executions and crashes per target; exits
# non-zero when any target crashed. Crash inputs are left in the run folder it prints.
#   scripts/fuzz.sh [seconds-per-target] [target...]     (default 60 s, all three targets)
# Environment: FUZZ_BUILD_DIR (default build-fuzz), FUZZ_JOBS (build jobs, default 2),
#   FUZZ_ARGS (extra libFuzzer flags, e.g. "-fork=2 -ignore_crashes=1" to keep going after a crash).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"; shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(package_reader look_file vdb_sequence)
build="${FUZZ_BUILD_DIR:-$root/build-fuzz}"
case "$build" in /*) ;; *) build="$root/$build" ;; esac

command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ not found (scripts/setup.sh installs it)" >&2; exit 2; }
# Instrument every FireLook library for coverage (fuzzer-no-link), not only the entry points;
# FIRELOOK_SANITIZE adds ASan + UBSan everywhere. Warnings are not errors here: a newer clang's
# new warning must not stop a fuzzing run.
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_C_FLAGS=-fsanitize=fuzzer-no-link -DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link \
  -DFIRELOOK_SANITIZE=ON -DFIRELOOK_BUILD_FUZZERS=ON -DFIRELOOK_WERROR=OFF \
  -DCMAKE_UNITY_BUILD=ON >/dev/null  # as scripts/build.sh: headers parsed once a batch of files
cmake --build "$build" -j "${FUZZ_JOBS:-2}" --target "${targets[@]/#/fuzz_}"

run="$(mktemp -d "${TMPDIR:-/tmp}/firelook-fuzz-run.XXXXXX")"
echo "fuzz.sh: ${seconds}s per target; corpora, logs and any crash inputs in $run"
# OpenVDB and TBB are not instrumented; leaks at exit are not what these targets look for.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0:allocator_may_return_null=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
status=0
for target in "${targets[@]}"; do
  corpus="$run/$target/corpus"; artifacts="$run/$target/"
  mkdir -p "$corpus"
  cp "$root/tests/fuzz/corpus/$target/"* "$corpus/"
  log="$run/$target/log.txt"
  set +e
  # shellcheck disable=SC2086
  "$build/tests/fuzz/fuzz_$target" "$corpus" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=3072 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$artifacts" ${FUZZ_ARGS:-} >"$log" 2>&1
  rc=$?
  set -e
  # Plain runs print the final stats; -fork runs only their progress lines ("#N: cov: ...").
  execs="$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1 || true)"
  [ -z "$execs" ] && execs="$(grep -oE '^#[0-9]+' "$log" | tail -1 | tr -d '#' || true)"
  crashes=$(find "$artifacts" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'oom-*' -o -name 'timeout-*' -o -name 'leak-*' \) | wc -l)
  printf '%-16s executions: %-10s corpus: %-5s exit: %s  crash/oom/timeout inputs: %s\n' \
    "$target" "${execs:-?}" "$(ls "$corpus" | wc -l)" "$rc" "$crashes"
  if [ "$rc" -ne 0 ] || [ "$crashes" -ne 0 ]; then
    status=1
    grep -E 'ERROR: |contract violated|runtime error|SUMMARY' "$log" | head -5 | sed 's/^/    /'
    find "$artifacts" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'oom-*' -o -name 'timeout-*' -o -name 'leak-*' \) | sed 's/^/    input: /'
  fi
done
exit $status
