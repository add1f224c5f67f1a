#!/bin/bash
# Smoke check of tavis_peer_bench (ctest label "peer", only with -DTAVIS_BUILD_PEER_BENCH=ON): a tiny
# run must print the full side-by-side table with finite positive rates in both engines and write
# both engines' images at the same size; a bad option must fail naming the bad value.
#   check_peer_bench.sh BENCH_BINARY WORK_DIR
set -euo pipefail
bench="$1"
work="$2"
rm -rf "$work"
mkdir -p "$work"

fail() { echo "FAIL: $*" >&2; exit 1; }

if "$bench" --envs 0 >"$work/bad.out" 2>&1; then fail "--envs 0 was accepted"; fi
grep -q "'0'" "$work/bad.out" || fail "--envs 0 error does not name the value: $(cat "$work/bad.out")"

"$bench" --envs 2 --ticks 120 --frames 1 --rounds 1 --out "$work/out" >"$work/run.out" 2>&1 ||
  fail "tiny run failed: $(cat "$work/run.out")"

table="$work/out/peer_table.md"
[[ -s "$table" ]] || fail "no $table"
rows=$(grep -c '^| [p0-9]' "$table") || true
[[ "$rows" == 6 ]] || fail "expected 6 rows (2 physics, 4 rendering), got $rows: $(cat "$table")"
# Columns: measure | unit | ours | MuJoCo | ratio | setting; every rate must be a positive number.
awk -F'|' '/^\| [p0-9]/ { if (!($4 + 0 > 0) || !($5 + 0 > 0)) { print "non-positive rate: " $0; bad = 1 } } END { exit bad }' "$table" ||
  fail "a rate is not positive"

png_size() { od -An -tu1 -j16 -N8 "$1" | tr -s ' '; }  # IHDR width and height bytes
for config in 4cam_640x480 3cam_224x224; do
  ours="$work/out/ours_$config.png"
  mujoco="$work/out/mujoco_$config.png"
  [[ -s "$ours" && -s "$mujoco" ]] || fail "missing images for $config"
  [[ "$(png_size "$ours")" == "$(png_size "$mujoco")" ]] || fail "$config: image sizes differ"
  cmp -s "$ours" "$mujoco" && fail "$config: both engines wrote the same file"
done
echo "peer bench smoke check passed"
