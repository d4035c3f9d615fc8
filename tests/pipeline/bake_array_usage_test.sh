#!/usr/bin/env bash
# scripts/slurm/bake_array.sh's command line without Slurm: --help (exit 0), and exit 2 with a
# one-line message naming the problem for each usage error. The bakes themselves: slurm_test.sh.
set -uo pipefail
script="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/scripts/slurm/bake_array.sh"
fail() { echo "FAIL: $*"; exit 1; }
out=$("$script" --help) || fail "--help exited $?"
grep -q "^Usage: scripts/slurm/bake_array.sh SEQUENCE -o OUT.firelook --shards N" <<< "$out" || fail "--help has no usage line"
# expect_usage_error MESSAGE ARGS...: exit 2 and one line on stderr, holding MESSAGE.
expect_usage_error() {
  local message=$1 err rc
  shift
  err=$("$script" "$@" 2>&1 > /dev/null)
  rc=$?
  ((rc == 2)) || fail "'$*' exited $rc, expected 2 ($err)"
  grep -qF -- "$message" <<< "$err" || fail "'$*': expected '$message' in: $err"
  [[ "$(wc -l <<< "$err")" == 1 ]] || fail "'$*': expected one line, got: $err"
}
expect_usage_error "missing SEQUENCE"
expect_usage_error "the first argument must be SEQUENCE" -o x.firelook seq
expect_usage_error "missing -o OUT.firelook" seq --shards 2
expect_usage_error "missing --shards N" seq -o x.firelook
expect_usage_error "--shards must be a positive integer, not '0'" seq -o x.firelook --shards 0
expect_usage_error "--report is not supported" seq -o x.firelook --shards 2 --report r.json
expect_usage_error "--frames needs a value" seq -o x.firelook --shards 2 --frames
echo "bake_array_usage_test: OK"
