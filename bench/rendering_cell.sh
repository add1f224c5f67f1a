#!/bin/sh
# The rendering cell of #32's acceptance (clutter-pick-cube, GR1T2, `id` split, scripted expert,
# head + both wrists rendered at 224x224 on every policy tick, seed 0): the one definition that
# bench/scaling.sh and `bench/parallel_ceiling.sh --cell` time, so both always run the same cell.
#
#   bench/rendering_cell.sh TAVIS THREADS EPISODES OUT [EXTRA tavis eval ARGS...]
#
# Runs `tavis eval` in the foreground with its output left to the caller; exits with its status.
set -eu
[ $# -ge 4 ] || { echo "usage: $0 TAVIS THREADS EPISODES OUT [EXTRA tavis eval ARGS...]" >&2; exit 2; }
tavis=$1 threads=$2 episodes=$3 out=$4
shift 4
exec "$tavis" eval --task clutter-pick-cube --robot gr1t2 --split id --policy expert --episodes "$episodes" --seed 0 \
  --render-cameras head,left_wrist,right_wrist --image-size 224x224 --threads "$threads" --out "$out" "$@"
