#!/bin/sh
# The parallel ceiling of a machine: how much more work N independent processes get through than
# one process alone. No program's thread scaling on that machine can be expected to beat what
# independent copies of the same work reach, since they share nothing but the machine (its
# cores' clocks, caches and memory, and whatever else runs on the host).
#
#   bench/parallel_ceiling.sh [N [ROUNDS [ITERATIONS]]]
#   bench/parallel_ceiling.sh --cell TAVIS [N [ROUNDS [EPISODES]]]
#   bench/parallel_ceiling.sh 16 3
#   bench/parallel_ceiling.sh --cell tavis-*/bin/tavis 16 2
#
# Without --cell each copy is an awk loop of ITERATIONS (default 20000000) that touches no memory:
# the ceiling of the cores alone. With --cell each copy is bench/rendering_cell.sh's rendering cell
# of EPISODES episodes (default 24) on one thread, all copies the same episodes: the ceiling for
# that very work, which `bench/scaling.sh`'s speed-up is to be read against (docs/performance-history.md:
# on the lent 16-core machine 16 such cells did 11.5x the work of one, 16 awk loops 12.9-15.7x,
# the cell on 16 threads 12.7x). N defaults to the number of online CPUs, ROUNDS to 2. Each round
# times one copy alone, then N copies started together, and prints each copy's wall time, the
# throughput of the N against one alone (the sum over the copies of alone / its time) and the
# slowest copy's time against alone. Cells must all give the records of the one alone, or the
# script fails. Needs only a POSIX shell, date, cmp and awk.
set -eu

here=$(CDPATH='' cd -- "$(dirname -- "$0")" && pwd)
tavis=
if [ "${1:-}" = --cell ]; then
  if [ $# -lt 2 ]; then
    echo "usage: $0 --cell TAVIS [N [ROUNDS [EPISODES]]]" >&2
    exit 2
  fi
  tavis=$2
  shift 2
  "$tavis" --version >/dev/null || { echo "$0: cannot run '$tavis'" >&2; exit 2; }
fi
n=${1:-$(getconf _NPROCESSORS_ONLN)}
rounds=${2:-2}
if [ -n "$tavis" ]; then size=${3:-24}; else size=${3:-20000000}; fi
for value in "$n" "$rounds" "$size"; do
  case $value in '' | *[!0-9]*) echo "$0: N, ROUNDS and ITERATIONS or EPISODES must be positive integers, got '$value'" >&2; exit 2 ;; esac
  [ "$value" -ge 1 ] || { echo "$0: N, ROUNDS and ITERATIONS or EPISODES must be at least 1, got '$value'" >&2; exit 2; }
done

work=$(mktemp -d "${TMPDIR:-/tmp}/tavis-ceiling.XXXXXX")
trap 'rm -rf "$work"' EXIT INT TERM

# work_once NAME: one copy's work (the awk loop, or the cell into $work/NAME).
work_once() {
  if [ -z "$tavis" ]; then
    awk -v n="$size" 'BEGIN { s = 0; for (i = 0; i < n; i++) s += i; if (s < 0) print s }'
  else
    "$here/rendering_cell.sh" "$tavis" 1 "$size" "$work/$1" >/dev/null 2>"$work/$1.log" ||
      { cat "$work/$1.log" >&2; echo "$0: the cell of copy '$1' failed" >&2; return 1; }
  fi
}

# copy NAME: one copy; prints its wall seconds.
copy() {
  start=$(date +%s.%N)
  work_once "$1"
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f\n", b - a }'
}

# same_records NAME: a cell copy's records must be the one alone's (the same episodes, any load).
same_records() {
  [ -z "$tavis" ] && return 0
  cmp -s "$work/alone/episodes.jsonl" "$work/$1/episodes.jsonl" ||
    { echo "$0: the records of copy '$1' differ from those of the cell run alone" >&2; exit 1; }
}

if [ -n "$tavis" ]; then
  echo "$n independent rendering cells of $size episodes on one thread each against one alone, $rounds round(s)"
else
  echo "$n independent awk loops of $size iterations against one alone, $rounds round(s)"
fi
r=1
while [ "$r" -le "$rounds" ]; do
  alone=$(copy alone)
  k=1
  while [ "$k" -le "$n" ]; do
    copy "copy.$k" >"$work/time.$k" &
    k=$((k + 1))
  done
  wait
  k=1
  while [ "$k" -le "$n" ]; do
    [ -s "$work/time.$k" ] || { echo "$0: copy $k gave no time" >&2; exit 1; }
    same_records "copy.$k"
    k=$((k + 1))
  done
  cat "$work"/time.* | sort -n | awk -v alone="$alone" -v r="$r" -v n="$n" '
    { t[NR] = $1; work += alone / $1; times = times " " $1 }
    END { printf "round %d: alone %.3f s; %d at once:%s s; throughput %.1fx of one alone, slowest %.2fx alone\n",
                 r, alone, n, times, work, t[NR] / alone }'
  rm -rf "$work"/time.* "$work"/copy.* "$work"/alone "$work"/*.log
  r=$((r + 1))
done
