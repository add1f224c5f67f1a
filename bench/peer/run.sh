#!/bin/bash
# Builds and runs the MuJoCo peer benchmark (bench/peer). Opt-in: installs Debian's MuJoCo and
# OSMesa (bench-only dependencies the main build never needs), configures a separate build
# directory with -DTAVIS_BUILD_PEER_BENCH=ON and runs tavis_peer_bench with any extra arguments.
#   bench/peer/run.sh [--envs 16] [--ticks 600] [--rounds 3] [--frames 8] [--out peer_results]
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
build="${TAVIS_PEER_BUILD_DIR:-$repo/build-peer}"

missing=()
for package in libmujoco-dev libosmesa6-dev; do
  dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
done
if ((${#missing[@]} > 0)); then
  echo "installing ${missing[*]}"
  apt-get install -y --no-install-recommends "${missing[@]}"
fi

cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release -DTAVIS_BUILD_PEER_BENCH=ON
cmake --build "$build" -j2 --target tavis_peer_bench
# llvmpipe (Mesa's software rasteriser) gets the same two threads as our renderer.
export LP_NUM_THREADS="${LP_NUM_THREADS:-2}"
exec "$build/bench/peer/tavis_peer_bench" "$@"
