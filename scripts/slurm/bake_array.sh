#!/usr/bin/env bash
# Bakes a VDB sequence on a Slurm cluster: a plan job that reads every frame once (`firelook bake
# --plan-only`), one array task per shard (a contiguous run of frames, `firelook bake --plan
# --frames ...`, which reads only its own frames), then a merge job that starts only when every
# shard succeeded (`--dependency=afterok`) and writes the package with `firelook merge`, the same
# bytes as a one-shot bake of the same frames. --resume after a failed run submits only what is
# missing. README.md, "Baking on a Slurm cluster".
set -euo pipefail

usage() {
  cat <<'EOF'
Usage: scripts/slurm/bake_array.sh SEQUENCE -o OUT.firelook --shards N [options] [bake options...]

Bakes SEQUENCE (a folder of .vdb files or a pattern such as fire_####.vdb) as a Slurm array job:
a plan job reads every frame once into WORK/plan.json (what the whole sequence gives the bake:
frame hashes, bounds, temperature and density survey); then task K bakes the K-th contiguous run
of frames into WORK/part_K.firelook reading only those frames, and a merge job that depends on
every task (afterok) merges the parts into OUT. SEQUENCE, OUT, WORK and the firelook executable
must be on a filesystem every node sees; the jobs run in the current directory, so relative paths
in bake options work there too.

Options:
  -o, --out OUT      the merged package (required)
  --shards N         number of array tasks (required); at most one per frame
  --frames SPEC      frames to bake: A-B ranges and single frames, comma-separated, holes
                     allowed (the merge is told so); default: every frame of SEQUENCE, as
                     `firelook info` lists them
  --work DIR         plan, parts, job scripts and logs (default: OUT.shards); what an earlier
                     run left there is removed first, unless --resume
  --resume           after a failed or cancelled run with the same arguments: keep its plan and
                     finished parts, submit only the shards without a part (each reuses the
                     frames its failed task finished, WORK/part_K.firelook.partial/) and the merge
  --firelook EXE     the firelook executable (default: $FIRELOOK, else firelook on PATH)
  --sbatch ARG       an extra sbatch argument for every job, e.g. --sbatch --partition=cpu or
                     --sbatch --cpus-per-task=8 (repeatable)
  --wait             wait until the merge has run; exit with its outcome
  --keep-parts       keep WORK/part_K.firelook after a successful merge
  -h, --help         this help

Every other argument after SEQUENCE goes to `firelook bake` unchanged (--size, --config, --scene,
--camera, --bins, --seed, --up, --memory-budget, ...). --report is refused: every shard would
write the same file.

Logs: WORK/logs/plan.log, WORK/logs/shard_K.log and WORK/logs/merge.log. WORK/merge.rc holds the
merge's exit status.

Exit status: 0 when submitted (with --wait: when OUT is written); 1 when a submission, a shard or
the merge failed (with --wait the failed job and its log are named); 2 on a usage error. Every
error is one line on stderr.
EOF
}

die() { echo "bake_array.sh: $*" >&2; exit "${2:-1}"; }
usage_error() { echo "bake_array.sh: $* (scripts/slurm/bake_array.sh --help)" >&2; exit 2; }

# --- arguments ---------------------------------------------------------------------------------
[[ $# -ge 1 ]] || usage_error "missing SEQUENCE"
case "$1" in -h|--help) usage; exit 0 ;; -*) usage_error "the first argument must be SEQUENCE, not '$1'" ;; esac
sequence=$1; shift
out="" shards="" frames="" work="" firelook="${FIRELOOK:-}" wait=0 keep_parts=0 resume=0
sbatch_args=() bake_args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    -o|--out|--output) [[ $# -ge 2 ]] || usage_error "$1 needs a value"; out=$2; shift 2 ;;
    --out=*|--output=*) out=${1#*=}; shift ;;
    --shards) [[ $# -ge 2 ]] || usage_error "--shards needs a value"; shards=$2; shift 2 ;;
    --shards=*) shards=${1#*=}; shift ;;
    --frames) [[ $# -ge 2 ]] || usage_error "--frames needs a value"; frames=$2; shift 2 ;;
    --frames=*) frames=${1#*=}; shift ;;
    --work) [[ $# -ge 2 ]] || usage_error "--work needs a value"; work=$2; shift 2 ;;
    --work=*) work=${1#*=}; shift ;;
    --firelook) [[ $# -ge 2 ]] || usage_error "--firelook needs a value"; firelook=$2; shift 2 ;;
    --firelook=*) firelook=${1#*=}; shift ;;
    --sbatch) [[ $# -ge 2 ]] || usage_error "--sbatch needs a value"; sbatch_args+=("$2"); shift 2 ;;
    --sbatch=*) sbatch_args+=("${1#*=}"); shift ;;
    --wait) wait=1; shift ;;
    --keep-parts) keep_parts=1; shift ;;
    --resume) resume=1; shift ;;
    --report|--report=*) usage_error "--report is not supported here: every shard would write the same file" ;;
    *) bake_args+=("$1"); shift ;;
  esac
done
[[ -n "$out" ]] || usage_error "missing -o OUT.firelook"
[[ -n "$shards" ]] || usage_error "missing --shards N"
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || usage_error "--shards must be a positive integer, not '$shards'"

command -v sbatch > /dev/null || die "sbatch not found on PATH (is this a Slurm submit host?)"
if [[ -z "$firelook" ]]; then firelook=$(command -v firelook) || die "firelook not found on PATH; pass --firelook EXE or set FIRELOOK"; fi
[[ -x "$firelook" ]] || die "$firelook: not an executable (--firelook)"
[[ -e "$sequence" || "$sequence" == *"#"* ]] || die "$sequence: no such folder or file"

# Absolute paths: the jobs may start anywhere on the cluster.
abspath() { local d; d=$(cd "$(dirname "$1")" 2> /dev/null && pwd) || die "$1: its folder does not exist"; echo "$d/$(basename "$1")"; }
firelook=$(abspath "$firelook")
sequence=$(abspath "$sequence")
out=$(abspath "$out")
[[ -n "$work" ]] || work="$out.shards"
work=$(abspath "${work%/}")

# --- frames and shards -------------------------------------------------------------------------
# The frame numbers, one a line, ascending.
list_frames() {
  if [[ -n "$frames" ]]; then
    local item
    IFS=',' read -r -a items <<< "${frames// /}"
    for item in "${items[@]}"; do
      if [[ "$item" =~ ^([0-9]+)-([0-9]+)$ ]]; then
        ((10#${BASH_REMATCH[1]} <= 10#${BASH_REMATCH[2]})) || usage_error "--frames: '$item' is an empty range"
        seq "$((10#${BASH_REMATCH[1]}))" "$((10#${BASH_REMATCH[2]}))"
      elif [[ "$item" =~ ^[0-9]+$ ]]; then
        echo "$((10#$item))"
      else
        usage_error "--frames: '$item' is neither a frame nor a range A-B"
      fi
    done | sort -n -u
  else
    local json
    json=$("$firelook" info --json "$sequence") || die "$sequence: firelook info failed (see above)"
    grep -o '"frame": *[0-9]*' <<< "$json" | grep -o '[0-9]*$' | sort -n -u
  fi
}
frame_lines=$(list_frames) || exit $?   # its usage error (2) or failure (1), already reported
mapfile -t all_frames <<< "$frame_lines"
[[ -n "$frame_lines" ]] || all_frames=()
((${#all_frames[@]} > 0)) || die "$sequence: no frames to bake"
if ((shards > ${#all_frames[@]})); then
  echo "bake_array.sh: $shards shards for ${#all_frames[@]} frames; using ${#all_frames[@]}" >&2
  shards=${#all_frames[@]}
fi

# Frames first..end-1 of all_frames as a --frames spec, consecutive numbers joined into A-B.
frames_spec() {
  local first=$1 end=$2 spec="" start prev i
  start=${all_frames[first]} prev=$start
  for ((i = first + 1; i <= end; ++i)); do
    if ((i < end)) && ((all_frames[i] == prev + 1)); then prev=${all_frames[i]}; continue; fi
    spec+="${spec:+,}$start"
    if ((prev != start)); then spec+="-$prev"; fi
    if ((i < end)); then start=${all_frames[i]} prev=${all_frames[i]}; fi
  done
  echo "$spec"
}

count=${#all_frames[@]}
parts=() shard_lines=""
for ((k = 1; k <= shards; ++k)); do
  # Shard k holds frames [(k-1)*count/shards, k*count/shards): sizes differ by at most one.
  shard_lines+="$(frames_spec $(((k - 1) * count / shards)) $((k * count / shards)))"$'\n'
  parts+=("$work/part_$k.firelook")
done
# Shell-quoted words for the job scripts (nothing for no words).
q() { if (($# > 0)); then local s; s=$(printf '%q ' "$@"); echo "${s% }"; fi; }
# What a run is: --resume continues only a run of the same executable, sequence, bake options,
# frames and shards, since its plan and parts were made with them.
run_text="$(q "$firelook" "$sequence" "${bake_args[@]}")"$'\n'"$shard_lines"

mkdir -p "$work/logs" || die "$work: cannot create the work folder"
if ((resume)); then
  [[ -f "$work/run.txt" ]] || die "$work: no earlier run to resume (no run.txt); run without --resume"
  [[ "$(cat "$work/run.txt")"$'\n' == "$run_text" ]] ||
    die "$work/run.txt: the earlier run had other arguments, frames or shards; run without --resume"
  rm -f "$work"/merge.rc
else
  # Clear what an earlier run left (only the files this script writes).
  rm -rf "$work"/part_*.firelook "$work"/part_*.firelook.partial "$work"/plan.json "$work"/merge.rc \
    "$work"/shards.txt "$work"/run.txt "$work"/plan.sh "$work"/shard.sh "$work"/merge.sh "$work"/logs/*.log
  printf '%s' "$shard_lines" > "$work/shards.txt"
  printf '%s' "$run_text" > "$work/run.txt"
fi
# What is left to do: the plan unless it was written, the shards without a part.
todo=()
for ((k = 1; k <= shards; ++k)); do [[ -f "${parts[k - 1]}" ]] || todo+=("$k"); done
need_plan=1
[[ -f "$work/plan.json" ]] && need_plan=0

# --- job scripts -------------------------------------------------------------------------------
cat > "$work/plan.sh" <<EOF
#!/usr/bin/env bash
# The plan job of bake_array.sh: reads every frame once, so that the shards read only their own.
set -euo pipefail
echo "plan on \$(hostname)"
exec $(q "$firelook") bake $(q "$sequence") --plan-only -o $(q "$work/plan.json") $(q "${bake_args[@]}")
EOF
cat > "$work/shard.sh" <<EOF
#!/usr/bin/env bash
# Array task K of bake_array.sh: bakes line K of shards.txt into part_K.firelook, reading only
# those frames (--plan); --resume reuses the frames an earlier try of this task finished.
set -euo pipefail
k=\${SLURM_ARRAY_TASK_ID:?not run as a Slurm array task}
frames=\$(sed -n "\${k}p" $(q "$work/shards.txt"))
[[ -n "\$frames" ]] || { echo "shard \$k: no line \$k in $(q "$work/shards.txt")" >&2; exit 1; }
echo "shard \$k of $shards on \$(hostname): frames \$frames"
exec $(q "$firelook") bake $(q "$sequence") --plan $(q "$work/plan.json") --frames "\$frames" --resume \\
  -o $(q "$work/part_")\$k.firelook $(q "${bake_args[@]}")
EOF
# The parts' frames have holes only where the frames asked for do: then merge must accept them.
merge_opts=()
((all_frames[count - 1] - all_frames[0] + 1 == count)) || merge_opts=(--allow-gaps)
cleanup_parts="# --keep-parts: the parts stay"
((keep_parts)) || cleanup_parts="if ((rc == 0)); then rm -f $(q "${parts[@]}"); fi"
cat > "$work/merge.sh" <<EOF
#!/usr/bin/env bash
# The merge job of bake_array.sh: runs once every shard succeeded; its status goes to merge.rc.
set -uo pipefail
echo "merging $shards parts on \$(hostname) into $(q "$out")"
$(q "$firelook") merge $(q "${merge_opts[@]}" "${parts[@]}") -o $(q "$out")
rc=\$?
$cleanup_parts
echo "\$rc" > $(q "$work/merge.rc")
exit "\$rc"
EOF
chmod +x "$work/plan.sh" "$work/shard.sh" "$work/merge.sh"

# --- submission --------------------------------------------------------------------------------
name=$(basename "$out" .firelook)
# Each job waits for the one before (afterok); Slurm cancels it when that one failed.
after=() plan_id=""
if ((need_plan)); then
  plan_id=$(sbatch --parsable --job-name="firelook-plan-$name" --chdir="$PWD" --output="$work/logs/plan.log" \
    "${sbatch_args[@]}" "$work/plan.sh") || die "sbatch of the plan job failed (see above)"
  plan_id=${plan_id%%;*}   # --parsable prints "id;cluster" on multi-cluster sites
  after=(--dependency="afterok:$plan_id" --kill-on-invalid-dep=yes)
fi
array_text="no shard left to bake"
if ((${#todo[@]} > 0)); then
  array_spec=$(IFS=,; echo "${todo[*]}")
  array_id=$(sbatch --parsable --job-name="firelook-bake-$name" --array="$array_spec" --chdir="$PWD" \
    --output="$work/logs/shard_%a.log" "${after[@]}" "${sbatch_args[@]}" "$work/shard.sh") ||
    die "sbatch of the shard array failed (see above)"
  array_id=${array_id%%;*}
  after=(--dependency="afterok:$array_id" --kill-on-invalid-dep=yes)
  array_text="job $array_id (array $array_spec)"
fi
merge_args=(--job-name="firelook-merge-$name" "${after[@]}" --chdir="$PWD" --output="$work/logs/merge.log" "${sbatch_args[@]}")
if ((resume)); then
  plan_text="plan kept"
  ((need_plan == 0)) || plan_text="plan job $plan_id"
  echo "bake_array.sh: resuming: $plan_text, $((shards - ${#todo[@]})) of $shards parts kept, $array_text"
else
  echo "bake_array.sh: $count frames in $shards shards: plan job $plan_id, $array_text, logs in $work/logs"
fi
if ((wait == 0)); then
  merge_id=$(sbatch --parsable "${merge_args[@]}" "$work/merge.sh") ||
    die "sbatch of the merge job failed (see above); the plan and the shards still run"
  echo "bake_array.sh: merge job ${merge_id%%;*} runs after every shard succeeded and writes $out"
  exit 0
fi

echo "bake_array.sh: waiting for the shards and the merge into $out"
# sbatch --wait returns when the merge job ends, also when Slurm cancels it because a shard failed
# (then with status 0), so the outcome is read from merge.rc, which only the merge job writes.
merge_id=$(sbatch --parsable --wait "${merge_args[@]}" "$work/merge.sh") || true
[[ -n "$merge_id" ]] || die "sbatch of the merge job failed (see above); the plan and the shards still run"
if [[ -f "$work/merge.rc" ]]; then
  rc=$(cat "$work/merge.rc")
  if [[ "$rc" == 0 ]]; then
    echo "bake_array.sh: wrote $out"
    exit 0
  fi
  echo "bake_array.sh: the merge failed (exit $rc): $work/logs/merge.log" >&2
  tail -n 5 "$work/logs/merge.log" >&2 || true
  exit 1
fi
if [[ ! -f "$work/plan.json" ]]; then
  echo "bake_array.sh: the plan job failed: $work/logs/plan.log (--resume submits it again)" >&2
  tail -n 3 "$work/logs/plan.log" 2> /dev/null | sed 's/^/    /' >&2 || true
  exit 1
fi
failed=0
for ((k = 1; k <= shards; ++k)); do
  if [[ ! -f "$work/part_$k.firelook" ]]; then
    failed=1
    echo "bake_array.sh: shard $k (frames $(sed -n "${k}p" "$work/shards.txt")) failed: $work/logs/shard_$k.log" >&2
    tail -n 3 "$work/logs/shard_$k.log" 2> /dev/null | sed 's/^/    /' >&2 || true
  fi
done
((failed == 0)) || echo "bake_array.sh: --resume bakes only the failed shards, reusing the frames they finished" >&2
((failed)) || echo "bake_array.sh: every shard wrote its part but the merge job did not run (cancelled?); see $work/logs/merge.log" >&2
exit 1
