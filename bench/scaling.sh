#!/bin/sh
# Thread scaling of the rendering cell (clutter-pick-cube, GR1T2, `id` split, scripted expert,
# head + both wrists rendered at 224x224 on every policy tick, 96 episodes, seed 0): runs it on 1
# thread and on N threads (default 16), alternating, R times each (default 1), and prints each
# run's wall time, the medians and their ratio (the speed-up from 1 to N threads).
#
#   bench/scaling.sh TAVIS [THREADS [REPEATS [EXTRA ARGS...]]]
#   bench/scaling.sh build/tavis 16 3
#   bench/scaling.sh tavis-*/bin/tavis 16 3 --envs 96      (the portable bundle)
#
# Extra arguments go to every `tavis eval` (options other than those the script sets: --envs,
# --expert-mode, --profile). Needs only a POSIX shell, date, cmp and awk. The records of every
# run must be the same: the script compares each run's episodes.jsonl with the first's and fails
# if one differs. The cell itself is bench/rendering_cell.sh's; `bench/parallel_ceiling.sh --cell
# TAVIS` gives the speed-up to read this one against.
set -eu

if [ $# -lt 1 ]; then
  echo "usage: $0 TAVIS [THREADS [REPEATS [EXTRA tavis eval ARGS...]]]" >&2
  exit 2
fi
tavis=$1
threads=${2:-16}
repeats=${3:-1}
[ $# -ge 1 ] && shift
[ $# -ge 1 ] && shift
[ $# -ge 1 ] && shift
case $threads in '' | *[!0-9]*) echo "$0: THREADS must be a positive integer, got '$threads'" >&2; exit 2 ;; esac
case $repeats in '' | *[!0-9]*) echo "$0: REPEATS must be a positive integer, got '$repeats'" >&2; exit 2 ;; esac
if [ "$threads" -lt 1 ] || [ "$repeats" -lt 1 ]; then
  echo "$0: THREADS and REPEATS must be at least 1" >&2
  exit 2
fi
"$tavis" --version >/dev/null || { echo "$0: cannot run '$tavis'" >&2; exit 2; }
here=$(CDPATH='' cd -- "$(dirname -- "$0")" && pwd)

work=$(mktemp -d "${TMPDIR:-/tmp}/tavis-scaling.XXXXXX")
trap 'rm -rf "$work"' EXIT INT TERM

# run LABEL THREADS [EXTRA...]: one cell; prints its wall seconds.
run() {
  label=$1
  on=$2
  shift 2
  out="$work/$label"
  start=$(date +%s.%N)
  "$here/rendering_cell.sh" "$tavis" "$on" 96 "$out" "$@" >/dev/null 2>"$work/$label.log" ||
    { cat "$work/$label.log" >&2; echo "$0: the cell on $on threads failed" >&2; exit 1; }
  end=$(date +%s.%N)
  if [ -f "$work/reference.jsonl" ]; then
    cmp -s "$work/reference.jsonl" "$out/episodes.jsonl" ||
      { echo "$0: the records on $on threads differ from the first run's" >&2; exit 1; }
  else
    cp "$out/episodes.jsonl" "$work/reference.jsonl"
  fi
  rm -rf "$out"
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f\n", b - a }'
}

median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

echo "rendering cell (clutter-pick-cube gr1t2, head + wrists 224x224, 96 episodes), $repeats run(s) each"
: >"$work/one" && : >"$work/many"
i=1
while [ "$i" -le "$repeats" ]; do
  t1=$(run "one-$i" 1 "$@")
  tn=$(run "many-$i" "$threads" "$@")
  echo "run $i: 1 thread ${t1} s, $threads threads ${tn} s"
  echo "$t1" >>"$work/one"
  echo "$tn" >>"$work/many"
  i=$((i + 1))
done
m1=$(median <"$work/one")
mn=$(median <"$work/many")
awk -v a="$m1" -v b="$mn" -v n="$threads" \
  'BEGIN { printf "median: 1 thread %.2f s, %d threads %.2f s, speed-up %.2fx (%.0f%% of %d)\n", a, n, b, a / b, 100 * a / b / n, n }'
