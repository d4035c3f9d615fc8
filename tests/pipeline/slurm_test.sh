#!/usr/bin/env bash
# scripts/slurm/bake_array.sh against a real single-node Slurm started here (slurm_cluster.sh):
#  1. three frames of the sample (copied into a folder of their own, so the frames come from
#     `firelook info`) in 3 shards, --wait: exit 0, the package cmp-equal to a one-shot bake of the
#     same folder, the parts removed, one log per shard and the merge's;
#  2. the same frames picked with --frames, with a firelook that fails for the middle shard:
#     exit 1, the failed shard named, the merge never run and no package written;
#  3. a firelook whose merge fails: exit 1, the merge's failure reported, no package;
#  4. without --wait (returns once submitted), frames 4,6 (a hole), --keep-parts, --work,
#     --sbatch, a relative config and 5 shards for 2 frames: capped to 2, the merged package equal
#     to a one-shot bake of 4,6, the parts kept, the sbatch argument on the job;
#  5. a failed run resumed: frames 4-7 in 2 shards, with a firelook that breaks frame 7's file
#     after the plan job read it, so shard 2 keeps frame 6 and fails at 7 (shard 1, whose frames
#     are fine, succeeds); with the file restored, --resume submits shard 2 alone (plan and part 1
#     kept, their logs untouched), which reuses frame 6: one frame baked in the resumed run, and
#     the package cmp-equal to a one-shot bake.
# Exit 77 (ctest: skipped) with the reason where Slurm is missing or the test is not root.
#   slurm_test.sh FIRELOOK_EXE
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
firelook=$(realpath "$1")
# shellcheck source=slurm_cluster.sh
source "$here/slurm_cluster.sh"

missing=$(slurm_cluster_missing)
if [[ -n "$missing" ]]; then
  echo "SKIP: $missing"
  exit 77
fi

work="$(mktemp -d "${TMPDIR:-/tmp}/firelook-slurm-test.XXXXXX")"
chmod 755 "$work"   # munged refuses a socket below a folder that not everyone can traverse
# A running bake_array.sh, in the background and in its own process group so that a TERM stops
# the test at once and the cleanup stops it with its sbatch.
child=""
run_bounded() {
  setsid timeout 300 "$@" &
  child=$!
  local rc=0
  wait "$child" || rc=$?
  child=""
  return "$rc"
}
cleanup() {
  if [[ -n "$child" ]]; then kill -TERM -- "-$child" 2> /dev/null || true; wait "$child" 2> /dev/null || true; fi
  slurm_cluster_stop
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 143' TERM
trap 'exit 130' INT
fail() {
  echo "FAIL: $*"
  for log in "$work"/out/*.shards/logs/*.log "$work"/parts/logs/*.log "$work"/cluster/log/slurmctld.log "$work"/cluster/log/slurmd.log; do
    [[ -f "$log" ]] && { echo "--- $log (last lines)"; tail -n 15 "$log"; }
  done
  exit 1
}

slurm_cluster_start "$work/cluster" || fail "the private Slurm cluster did not start"
echo "slurm: cluster up ($SLURM_CONF)"

# Each frame bakes in about a second: 32x32, the tiny settings.
bake_opts=(--size 32x32 --up z --config "$here/tiny_bake.json")
mkdir -p "$work/seq" "$work/out"
cp "$root"/samples/data/explosion/fluid_data_000{4,5,6}.vdb "$work/seq/"

# The array job can take a while on a loaded 2-core machine; 300 s is ~10x what it takes idle.
cd "$work"
run_bounded "$root/scripts/slurm/bake_array.sh" "$work/seq" -o "$work/out/array.firelook" --shards 3 \
  --firelook "$firelook" --wait "${bake_opts[@]}" > "$work/array.log" 2>&1 || {
  rc=$?
  cat "$work/array.log"
  ((rc != 124)) || fail "bake_array.sh did not finish within 300 s"
  fail "bake_array.sh exited $rc"
}
cat "$work/array.log"
"$firelook" bake "$work/seq" -o "$work/out/oneshot.firelook" "${bake_opts[@]}" > "$work/oneshot.log" 2>&1 ||
  { cat "$work/oneshot.log"; fail "the one-shot bake failed"; }
cmp "$work/out/array.firelook" "$work/out/oneshot.firelook" || fail "the merged package differs from the one-shot bake"
shards_dir="$work/out/array.firelook.shards"
for k in 1 2 3; do
  [[ -s "$shards_dir/logs/shard_$k.log" ]] || fail "no log for shard $k"
  [[ ! -e "$shards_dir/part_$k.firelook" ]] || fail "part $k left behind after the merge"
done
[[ -s "$shards_dir/logs/merge.log" ]] || fail "no merge log"
[[ -s "$shards_dir/logs/plan.log" ]] || fail "no plan log"
[[ "$(sed -n 2p "$shards_dir/shards.txt")" == 5 ]] || fail "shard 2 should bake frame 5: $(cat "$shards_dir/shards.txt")"
echo "slurm: 3 shards merged into the same bytes as the one-shot bake"

# A firelook whose bake of frame 5 fails.
cat > "$work/failing_firelook.sh" <<EOF
#!/usr/bin/env bash
for arg in "\$@"; do [[ "\$arg" != 5 ]] || { echo "failing_firelook: refusing frame 5" >&2; exit 3; }; done
exec "$firelook" "\$@"
EOF
chmod +x "$work/failing_firelook.sh"
set +e
run_bounded "$root/scripts/slurm/bake_array.sh" "$root/samples/data/explosion" -o "$work/out/failing.firelook" \
  --shards 3 --frames 4-6 --firelook "$work/failing_firelook.sh" --wait "${bake_opts[@]}" > "$work/failing.log" 2>&1
rc=$?
set -e
cat "$work/failing.log"
((rc != 124)) || fail "bake_array.sh with a failing shard did not finish within 300 s"
((rc == 1)) || fail "bake_array.sh with a failing shard exited $rc, expected 1"
grep -q "shard 2 (frames 5) failed" "$work/failing.log" || fail "the failed shard is not named"
if grep -q "shard [13] (" "$work/failing.log"; then fail "a shard that succeeded is reported as failed"; fi
[[ ! -e "$work/out/failing.firelook" ]] || fail "a package was written although a shard failed"
[[ ! -e "$work/out/failing.firelook.shards/merge.rc" ]] || fail "the merge ran although a shard failed"
echo "slurm: a failed shard stops the merge and is named"

# A firelook whose merge fails.
cat > "$work/failing_merge.sh" <<EOF
#!/usr/bin/env bash
[[ "\$1" != merge ]] || { echo "failing_merge: refusing to merge" >&2; exit 4; }
exec "$firelook" "\$@"
EOF
chmod +x "$work/failing_merge.sh"
set +e
run_bounded "$root/scripts/slurm/bake_array.sh" "$work/seq" -o "$work/out/unmerged.firelook" --shards 1 \
  --firelook "$work/failing_merge.sh" --wait "${bake_opts[@]}" > "$work/unmerged.log" 2>&1
rc=$?
set -e
cat "$work/unmerged.log"
((rc == 1)) || fail "bake_array.sh with a failing merge exited $rc, expected 1"
grep -q "the merge failed (exit 4)" "$work/unmerged.log" || fail "the failed merge is not reported"
[[ ! -e "$work/out/unmerged.firelook" ]] || fail "a package was written although the merge failed"
echo "slurm: a failed merge is reported"

# Submit and return: frames with a hole (4,6), --keep-parts, --work (a stale part there goes),
# --sbatch, more shards than frames, a config path relative to the submitting folder.
mkdir -p "$work/parts"
touch "$work/parts/part_9.firelook"
cp "$here/tiny_bake.json" "$work/bake.json"
"$root/scripts/slurm/bake_array.sh" "$work/seq" -o "$work/out/later.firelook" --shards 5 --frames 4,6 --work "$work/parts" \
  --keep-parts --sbatch --comment=firelook-test --firelook "$firelook" --size 32x32 --up z --config bake.json \
  > "$work/later.log" 2>&1 || { cat "$work/later.log"; fail "bake_array.sh without --wait failed"; }
[[ ! -e "$work/parts/part_9.firelook" ]] || fail "a part of an earlier run was left in the work folder"
cat "$work/later.log"
grep -q "5 shards for 2 frames; using 2" "$work/later.log" || fail "the shard count was not capped at the frame count"
merge_id=$(sed -n 's/.*merge job \([0-9]*\) runs after.*/\1/p' "$work/later.log")
[[ -n "$merge_id" ]] || fail "no merge job id printed"
deadline=$((SECONDS + 300))
until [[ -f "$work/parts/merge.rc" ]]; do
  ((SECONDS < deadline)) || fail "the merge job of the submitted bake did not run within 300 s"
  sleep 1
done
[[ "$(cat "$work/parts/merge.rc")" == 0 ]] || fail "the submitted bake's merge failed"
"$firelook" bake "$work/seq" --frames 4,6 -o "$work/out/oneshot46.firelook" "${bake_opts[@]}" > "$work/oneshot.log" 2>&1 ||
  { cat "$work/oneshot.log"; fail "the one-shot bake of frames 4,6 failed"; }
cmp "$work/out/later.firelook" "$work/out/oneshot46.firelook" || fail "the submitted bake differs from the one-shot bake"
for k in 1 2; do [[ -s "$work/parts/part_$k.firelook" ]] || fail "--keep-parts: part $k missing"; done
scontrol show job "$merge_id" | grep -q "Comment=firelook-test" || fail "--sbatch arguments did not reach the merge job"
echo "slurm: submitted without --wait, parts kept, same bytes"

# A failed run, resumed.
mkdir -p "$work/seq4"
cp "$root"/samples/data/explosion/fluid_data_000{4,5,6,7}.vdb "$work/seq4/"
cp "$work/seq4/fluid_data_0007.vdb" "$work/frame7.vdb"
cat > "$work/breaking_firelook.sh" <<EOF
#!/usr/bin/env bash
if [[ -f "$work/break" && " \$* " == *" --frames 6-7 "* ]]; then
  echo "breaking_firelook: frame 7 broken after the plan read it" >&2
  echo "not a VDB file" > "$work/seq4/fluid_data_0007.vdb"
fi
exec "$firelook" "\$@"
EOF
chmod +x "$work/breaking_firelook.sh"
touch "$work/break"
resume_args=("$work/seq4" -o "$work/out/resumed.firelook" --shards 2 --firelook "$work/breaking_firelook.sh" --wait "${bake_opts[@]}")
set +e
run_bounded "$root/scripts/slurm/bake_array.sh" "${resume_args[@]}" > "$work/broken.log" 2>&1
rc=$?
set -e
cat "$work/broken.log"
((rc == 1)) || fail "bake_array.sh with a frame broken in shard 2 exited $rc, expected 1"
grep -q "shard 2 (frames 6-7) failed" "$work/broken.log" || fail "the failed shard is not named"
resumed_dir="$work/out/resumed.firelook.shards"
[[ -s "$resumed_dir/part_1.firelook" ]] || fail "shard 1, whose frames are fine, did not write its part"
[[ -s "$resumed_dir/part_2.firelook.partial/frame_6.firelook" ]] || fail "shard 2 did not keep frame 6"
cp "$resumed_dir/logs/shard_1.log" "$work/shard_1.before"
cp "$resumed_dir/logs/plan.log" "$work/plan.before"
rm "$work/break"
cp "$work/frame7.vdb" "$work/seq4/fluid_data_0007.vdb"
run_bounded "$root/scripts/slurm/bake_array.sh" "${resume_args[@]}" --resume > "$work/resumed.log" 2>&1 ||
  { cat "$work/resumed.log"; fail "bake_array.sh --resume failed"; }
cat "$work/resumed.log"
grep -q "resuming: plan kept, 1 of 2 parts kept, job [0-9]* (array 2)" "$work/resumed.log" ||
  fail "--resume did not submit shard 2 alone"
cmp -s "$resumed_dir/logs/shard_1.log" "$work/shard_1.before" || fail "--resume ran shard 1 again"
cmp -s "$resumed_dir/logs/plan.log" "$work/plan.before" || fail "--resume made the plan again"
# The bake's table in shard 2's log: one row per frame, "(resumed)" on a frame reused.
rows=$(grep -cE '^ +[67] +[0-9]+ ' "$resumed_dir/logs/shard_2.log" || true)
reused=$(grep -E '^ +[67] +[0-9]+ ' "$resumed_dir/logs/shard_2.log" | grep -c '(resumed)' || true)
[[ "$rows" == 2 && "$reused" == 1 ]] || fail "shard 2 resumed: $rows frames, $reused reused; expected 2 and 1"
grep -qE '^ +6 .*\(resumed\)' "$resumed_dir/logs/shard_2.log" || fail "frame 6 was not the frame reused"
"$firelook" bake "$work/seq4" -o "$work/out/oneshot4.firelook" "${bake_opts[@]}" > "$work/oneshot.log" 2>&1 ||
  { cat "$work/oneshot.log"; fail "the one-shot bake of frames 4-7 failed"; }
cmp "$work/out/resumed.firelook" "$work/out/oneshot4.firelook" || fail "the resumed bake differs from the one-shot bake"
echo "slurm: a failed run resumed: 1 of 4 frames baked again, same bytes"
slurm_cluster_stop
leftovers=$(slurm_cluster_leftovers "$work/cluster")
[[ -z "$leftovers" ]] || fail "daemons still running after the cluster was stopped: $leftovers"
echo "slurm_test: OK"
