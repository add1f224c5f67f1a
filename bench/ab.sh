#!/bin/sh
# Interleaved A/B timing of tavis builds on one command: each round runs every build once, in
# turn, so that a machine whose load changes during the sitting slows them alike. Prints every
# run's wall time, then per build the median, the spread (min-max) and the ratio of the first
# build's median to its own (above 1: faster than the first).
#
#   bench/ab.sh ROUNDS "TAVIS ARGS" TAVIS_A TAVIS_B [TAVIS_C ...]
#   bench/ab.sh 3 "eval --task clutter-pick-cube --robot gr1t2 --threads 2" /tmp/old/build/tavis build/tavis
#
# `--out DIR --overwrite` is added to eval and demos commands (a scratch folder per run, removed
# afterwards). Needs only a POSIX shell, date, sort and awk.
set -eu

if [ $# -lt 4 ]; then
  echo "usage: $0 ROUNDS \"TAVIS ARGS\" TAVIS_A TAVIS_B [TAVIS_C ...]" >&2
  exit 2
fi
rounds=$1
args=$2
shift 2
case $rounds in '' | *[!0-9]*) echo "$0: ROUNDS must be a positive integer, got '$rounds'" >&2; exit 2 ;; esac
for tavis in "$@"; do
  "$tavis" --version >/dev/null || { echo "$0: cannot run '$tavis'" >&2; exit 2; }
done

work=$(mktemp -d "${TMPDIR:-/tmp}/tavis-ab.XXXXXX")
trap 'rm -rf "$work"' EXIT INT TERM

round=1
while [ "$round" -le "$rounds" ]; do
  build=1
  for tavis in "$@"; do
    start=$(date +%s.%N)
    # shellcheck disable=SC2086  # the arguments are split on purpose
    "$tavis" $args --out "$work/out" --overwrite >"$work/log" 2>&1 ||
      { cat "$work/log" >&2; echo "$0: '$tavis $args' failed" >&2; exit 1; }
    end=$(date +%s.%N)
    seconds=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }')
    echo "round $round: $tavis $seconds s"
    echo "$seconds" >>"$work/times.$build"
    rm -rf "$work/out"
    build=$((build + 1))
  done
  round=$((round + 1))
done

median() { sort -n "$1" | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
first=$(median "$work/times.1")
build=1
for tavis in "$@"; do
  m=$(median "$work/times.$build")
  low=$(sort -n "$work/times.$build" | head -n 1)
  high=$(sort -n "$work/times.$build" | tail -n 1)
  awk -v t="$tavis" -v m="$m" -v lo="$low" -v hi="$high" -v f="$first" \
    'BEGIN { printf "%s: median %.2f s (%s-%s s), speed %.2fx the first\n", t, m, lo, hi, f / m }'
  build=$((build + 1))
done
