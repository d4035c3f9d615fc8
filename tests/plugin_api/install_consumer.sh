#!/usr/bin/env bash
# install_consumer.sh BUILD_DIR CONSUMER_SRC WORK_DIR CMAKE CC
# Installs BUILD_DIR into WORK_DIR/prefix, then configures, builds and runs CONSUMER_SRC against it.
set -euo pipefail
build_dir=$1 consumer=$2 work=$3 cmake=$4 cc=$5
rm -rf "$work"
mkdir -p "$work"
"$cmake" --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
test -f "$work/prefix/include/firelook/firelook.h"
ls "$work"/prefix/lib*/libfirelook_plugin.so* > /dev/null
"$cmake" -S "$consumer" -B "$work/build" -G Ninja -DCMAKE_C_COMPILER="$cc" \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release > "$work/configure.log"
"$cmake" --build "$work/build" > "$work/build.log"
# The consumer finds the library through the RPATH CMake gives it for the imported target.
"$work/build/consumer"
rm -rf "$work"
