#!/bin/sh
# The parallel ceiling of a machine: how much more work N independent CPU-bound processes (an awk
# loop that touches no memory and shares nothing) get through than one process alone. No
# program's thread scaling on that machine can be expected to beat it: `bench/scaling.sh`'s
# speed-up is to be read against this figure (docs/performance.md: on the lent 16-core machine
# 16 such processes did 9.7-11.1x the work of one).
#
#   bench/parallel_ceiling.sh [N [ROUNDS [ITERATIONS]]]
#   bench/parallel_ceiling.sh 16 3
#
# N defaults to the number of online CPUs, ROUNDS to 2, ITERATIONS (of the loop, per process) to
# 20000000. Each round times one copy alone, then N copies started together, and prints each
# copy's wall time, the throughput of the N against one alone (the sum over the copies of
# alone / its time) and the slowest copy's time against alone. Needs only a POSIX shell, date and awk.
set -eu

n=${1:-$(getconf _NPROCESSORS_ONLN)}
rounds=${2:-2}
iterations=${3:-20000000}
for value in "$n" "$rounds" "$iterations"; do
  case $value in '' | *[!0-9]*) echo "$0: N, ROUNDS and ITERATIONS must be positive integers, got '$value'" >&2; exit 2 ;; esac
  [ "$value" -ge 1 ] || { echo "$0: N, ROUNDS and ITERATIONS must be at least 1, got '$value'" >&2; exit 2; }
done

work=$(mktemp -d "${TMPDIR:-/tmp}/tavis-ceiling.XXXXXX")
trap 'rm -rf "$work"' EXIT INT TERM

# copy: one process's loop; prints its wall seconds.
copy() {
  start=$(date +%s.%N)
  awk -v n="$iterations" 'BEGIN { s = 0; for (i = 0; i < n; i++) s += i; if (s < 0) print s }'
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f\n", b - a }'
}

echo "$n independent awk loops of $iterations iterations against one alone, $rounds round(s)"
r=1
while [ "$r" -le "$rounds" ]; do
  alone=$(copy)
  k=1
  while [ "$k" -le "$n" ]; do
    copy >"$work/copy.$k" &
    k=$((k + 1))
  done
  wait
  cat "$work"/copy.* | sort -n | awk -v alone="$alone" -v r="$r" -v n="$n" '
    { t[NR] = $1; work += alone / $1; times = times " " $1 }
    END { printf "round %d: alone %.3f s; %d at once:%s s; throughput %.1fx of one alone, slowest %.2fx alone\n",
                 r, alone, n, times, work, t[NR] / alone }'
  rm -f "$work"/copy.*
  r=$((r + 1))
done
