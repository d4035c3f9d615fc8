#!/usr/bin/env bash
# firelook_add_package() (plugin_api/cmake/FireLookBake.cmake) in a consumer project built with
# Ninja against `cmake --install`'s tree (bake_consumer/): two packages from two 2-frame copies of
# the sample, a folder and a pattern. Checks which bakes each build runs:
#   first build: both, in parallel (their runs overlap in .ninja_log), a.firelook cmp-equal to the
#     installed firelook's own bake of the same inputs; second build: nothing ("no work to do");
#   touching one VDB of sequence A: pkg_a only; a new frame in A: CMake re-runs, pkg_a only (and
#     a.firelook then holds the 3 frames: cmp-equal to a direct bake); that frame removed again:
#     pkg_a only, cmp-equal to the 2-frame bake; a frame removed from B (the pattern): pkg_b only;
#   touching the config or the firelook executable: both;
#   with Make instead of Ninja: a frame removed from A rebakes pkg_a only;
#   an unquoted pattern (cut at '#', CMake's comment): configuring fails saying to quote it.
#   cmake_package_test.sh BUILD_DIR CONSUMER_SRC WORK_DIR CMAKE
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
build_dir=$1 consumer=$2 work=$3 cmake=$4
rm -rf "$work"
mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }

"$cmake" --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
firelook="$work/prefix/bin/firelook"
[[ -x "$firelook" ]] || fail "cmake --install did not install bin/firelook"
ls "$work"/prefix/lib*/cmake/FireLook/FireLookBake.cmake > /dev/null || fail "FireLookBake.cmake not installed"

sample="$root/samples/data/explosion"
mkdir -p "$work/seq_a" "$work/seq_b"
cp "$sample"/fluid_data_000{4,5}.vdb "$work/seq_a/"
cp "$sample"/fluid_data_000{7,8}.vdb "$work/seq_b/"
cp "$here/tiny_bake.json" "$work/bake.json"
"$cmake" -S "$consumer" -B "$work/build" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DSEQUENCE_A="$work/seq_a" -DSEQUENCE_B="$work/seq_b/fluid_data_####.vdb" -DBAKE_CONFIG="$work/bake.json" \
  > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; fail "the consumer did not configure"; }

# build NAME: builds $build_dir with two jobs, logs to NAME.log, prints the packages baked ("pkg_a pkg_b").
build_dir="$work/build"
build() {
  "$cmake" --build "$build_dir" -j 2 > "$work/$1.log" 2>&1 || { cat "$work/$1.log"; fail "build '$1' failed"; }
  { grep -o 'Baking FireLook package pkg_[ab]' "$work/$1.log" || true; } | awk '{print $4}' | sort | tr '\n' ' ' | sed 's/ $//'
}
expect() {
  local what=$1 want=$2 got
  got=$(build "$what")
  [[ "$got" == "$want" ]] || { cat "$work/$what.log"; fail "$what: baked '$got', expected '$want'"; }
  echo "cmake_package: $what: baked '${got:-nothing}'"
}

expect first "pkg_a pkg_b"
a="$work/build/packages/a.firelook" b="$work/build/packages/b.firelook"
[[ -s "$a" && -s "$b" ]] || fail "the packages were not written"
"$firelook" bake "$work/seq_a" -o "$work/direct_a.firelook" --config "$work/bake.json" --size 32x32 --up z \
  > "$work/direct.log" 2>&1 || { cat "$work/direct.log"; fail "the direct bake failed"; }
cmp "$a" "$work/direct_a.firelook" || fail "the build step's package differs from firelook bake's"
# .ninja_log: start and end (ms) of each output's last run; independent bakes overlap.
read -r a_start a_end b_start b_end < <(awk -F'\t' '$4 ~ /packages\/a.firelook$/ {as = $1; ae = $2}
  $4 ~ /packages\/b.firelook$/ {bs = $1; be = $2} END {print as, ae, bs, be}' "$work/build/.ninja_log")
((a_start < b_end && b_start < a_end)) || fail "the two bakes did not run in parallel (a $a_start-$a_end ms, b $b_start-$b_end ms)"

expect second ""
# Not `ninja -n`: the CONFIGURE_DEPENDS glob check always runs, so a dry run cannot tell that it
# finds nothing new and lists a CMake re-run; the real build's log shows what was done.
grep -q "ninja: no work to do" "$work/second.log" || { cat "$work/second.log"; fail "the second build did some work"; }

b_before=$(stat -c %Y.%y "$b")
touch "$work/seq_a/fluid_data_0005.vdb"
expect touched-frame "pkg_a"
[[ "$(stat -c %Y.%y "$b")" == "$b_before" ]] || fail "b.firelook was rewritten although its inputs did not change"
expect after-touch ""

cp "$sample/fluid_data_0006.vdb" "$work/seq_a/"
expect new-frame "pkg_a"
grep -q "Re-running CMake" "$work/new-frame.log" || fail "a new frame did not make CMake re-run"
"$firelook" bake "$work/seq_a" -o "$work/direct_a3.firelook" --config "$work/bake.json" --size 32x32 --up z \
  > "$work/direct.log" 2>&1 || { cat "$work/direct.log"; fail "the direct bake failed"; }
cmp "$a" "$work/direct_a3.firelook" || fail "after a new frame the package differs from firelook bake's of the 3 frames"

# A removed frame: the package loses it (CMake re-runs, the file list changes, the bake runs).
rm "$work/seq_a/fluid_data_0006.vdb"
expect removed-frame "pkg_a"
cmp "$a" "$work/direct_a.firelook" || fail "after a removed frame the package differs from firelook bake's of the 2 frames"
rm "$work/seq_b/fluid_data_0008.vdb"
expect removed-pattern-frame "pkg_b"
"$firelook" bake "$work/seq_b/fluid_data_####.vdb" -o "$work/direct_b1.firelook" --config "$work/bake.json" --size 32x32 --up z \
  > "$work/direct.log" 2>&1 || { cat "$work/direct.log"; fail "the direct bake failed"; }
cmp "$b" "$work/direct_b1.firelook" || fail "after a removed frame of the pattern the package differs from firelook bake's"
expect after-remove ""

touch "$work/bake.json"
expect touched-config "pkg_a pkg_b"
touch "$firelook"
expect touched-firelook "pkg_a pkg_b"
expect last ""

# The same with Make: a removed frame rebakes.
build_dir="$work/make-build"
"$cmake" -S "$consumer" -B "$build_dir" -G "Unix Makefiles" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DSEQUENCE_A="$work/seq_a" -DSEQUENCE_B="$work/seq_b/fluid_data_####.vdb" -DBAKE_CONFIG="$work/bake.json" \
  > "$work/configure-make.log" 2>&1 || { cat "$work/configure-make.log"; fail "the consumer did not configure for Make"; }
expect make-first "pkg_a pkg_b"
rm "$work/seq_a/fluid_data_0005.vdb"
expect make-removed-frame "pkg_a"
expect make-last ""

# An unquoted pattern is cut at '#'; configuring says to quote it.
if "$cmake" -S "$consumer" -B "$work/cut-build" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DSEQUENCE_A="$work/seq_a" -DSEQUENCE_B="$work/seq_b/fluid_data_####.vdb" -DBAKE_CONFIG="$work/bake.json" \
  -DUNQUOTED_PATTERN_FOLDER="$work/seq_b" > "$work/configure-cut.log" 2>&1; then
  fail "an unquoted pattern configured"
fi
# CMake wraps the message's lines.
tr -s ' \n' '  ' < "$work/configure-cut.log" | grep -q "an unquoted '#' starts a CMake comment, so quote the pattern" ||
  { cat "$work/configure-cut.log"; fail "the cut pattern's error does not say to quote it"; }
rm -rf "$work"
echo "cmake_package_test: OK"
