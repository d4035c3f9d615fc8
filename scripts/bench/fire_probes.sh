#!/usr/bin/env bash
# The fire lighting the scene (issue 29, items 3-4): bakes one frame of the bundled sample small
# (64x64: neither the probes nor the lights depend on the image size) with the fire lights and an
# N x N x N probe grid for each N of RESOLUTIONS, prints what each grid costs (stored bytes and bake
# seconds of its FPRB section, from the bake's --report), then measures the fire's fluence and
# irradiance at random points around the volume, on a ground plane below it and on a wall beside it,
# for the probe grids and the point lights, against the full model (tests/bake/bench_fire_probes.cpp).
#   scripts/bench/fire_probes.sh [frame] [paths per point] [points] [resolutions] [looks] [out-dir]
# (looks: the default look, then random extinctions within the baked axes)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
frame="${1:-7}"
samples="${2:-65536}"
points="${3:-100}"
resolutions="${4:-4,6}"
looks="${5:-1}"
out="${6:-$root/out/bench/fire_probes}"
"$root/scripts/build.sh" release firelook bench_fire_probes >/dev/null
firelook="$root/build/release/baker/cli/firelook"
mkdir -p "$out"
first=""
for n in ${resolutions//,/ }; do
  package="$out/probes$n.firelook"
  "$firelook" bake "$root/samples/data/explosion" --up z --frames "$frame-$frame" --size 64x64 --fire-lights \
    --fire-probes "$n" --report "$out/report$n.json" -o "$package" >/dev/null
  python3 - "$out/report$n.json" "$n" <<'PY'
import json, sys
f = json.load(open(sys.argv[1]))["frames"][0]
p, l = f["fire_probes"], f["fire_lights"]
print(f"probes {sys.argv[2]}^3: FPRB {p['bytes']} bytes stored ({p['bytes'] / 1024:.1f} KiB) a frame, traced in "
      f"{p['seconds']:.2f} s; fire lights FLIT {l['bytes']} bytes, {l['seconds']:.2f} s; the frame's trace "
      f"{f['trace_seconds']:.1f} s")
PY
  first="${first:-$package}"
done
"$root/build/release/tests/bake/bench_fire_probes" "$first" "$root/samples/data/explosion" "$frame" "$samples" \
  "$points" "$resolutions" z "$looks"
