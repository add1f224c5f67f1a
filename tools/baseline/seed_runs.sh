#!/bin/bash
# Training seeds of the chosen recipe (docs/baselines.md, "Seeds of the chosen recipe"): the L1
# CNN head, 1,000 demonstrations per task, a fixed number of steps with the cosine schedule run to
# its end (--steps sized to the card, no time budget cutting it), GR1T2. Each run of RUNS is
# "dataset:camera:seed", optionally ":head" (l1, flow or act; default l1) and ":demos" (the first N
# episodes of the recording; default DEMOS): "cp:head:0:flow", "cp:head:0:l1:200". All of them
# train side by side on the one card, then each
# checkpoint is served twice on the same 96 id scenes (seed 1000): with its queue of 10 rows and
# re-planning every step (`serve --executed-steps 1`). Cells named in ood's list are evaluated on
# ood-spatial as well (queue of 10 rows). Written for one H200 with 16 cores and a 30-minute lease.
#
#   tools/baseline/seed_runs.sh TAVIS WORK
#
# TAVIS is the `tavis` program (the portable bundle's bin/tavis on such a machine, docs/bundle.md);
# PYTHONPATH must reach the tavis_baseline and tavis_server packages and a Python with PyTorch
# (CUDA), NumPy, OpenCV or PyAV, msgpack and websockets. Cells land in WORK/eval with each
# checkpoint's training.json beside them; progress lines in WORK/progress.log.
set -u
if [ $# -ne 2 ] || [ ! -x "$1" ]; then
  echo "usage: $0 TAVIS WORK (TAVIS: the tavis program; got '${1:-}')" >&2
  exit 2
fi
T=$1; W=$2
RUNS=${RUNS:-"wta:head:1 wta:head:2 cp:head:0 cp:fixed:0"}
OOD=${OOD-"cp:head:0 cp:fixed:0"}  # OOD="" evaluates none on ood-spatial
STEPS=${STEPS:-30000}
BUDGET=${BUDGET:-1500}     # a safety stop only: the runs are sized to end by --steps
DEMOS=${DEMOS:-1000}; EPISODES=${EPISODES:-96}; DEVICE=${DEVICE:-cuda}
source "$(dirname "$0")/gpu_block_common.sh"  # CORES, stamp, TASK, demos

name_of() { echo "$1" | tr ':' '_'; }  # wta:head:1 -> wta_head_1, cp:head:0:flow -> cp_head_0_flow

train() {  # d:camera:seed[:head[:demos]]
  local d c s h n; IFS=: read d c s h n <<< "$1"
  local name=$(name_of "$1")
  OMP_NUM_THREADS=1 python3 -m tavis_baseline.train --dataset "$W/ds/$d" --camera $c --seed $s \
     --out "$W/ckpt/$name" --head ${h:-l1} --episodes ${n:-$DEMOS} --val-episodes 20 --steps $STEPS --time-budget-s $BUDGET \
     --save-every $((STEPS + 1)) --device $DEVICE --threads 1 > "$W/logs/train_$name.log" 2>&1
  stamp "train $name rc=$? $(grep -o 'saved .*' $W/logs/train_$name.log | tail -1)"
}

evaluate() {  # d:camera:seed[:head[:demos]] split executed-steps port
  local d c s; IFS=: read d c s _ <<< "$1"
  local ckpt=$(name_of "$1") split=$2 k=$3 port=$4
  local name=${ckpt}_${split}_exec$k
  [ -f "$W/ckpt/$ckpt/config.json" ] || { stamp "eval $name skipped: no checkpoint"; return; }
  python3 -m tavis_baseline.serve "$W/ckpt/$ckpt" --port $port --device $DEVICE --executed-steps $k \
    > "$W/logs/serve_$name.log" 2>&1 &
  local srv=$!
  for _ in $(seq 120); do python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$port/healthz')" 2>/dev/null && break; sleep 1; done
  "$T" eval --task ${TASK[$d]} --robot gr1t2 --camera $c --split $split --episodes $EPISODES --seed 1000 --policy openpi \
    --server "ws://127.0.0.1:$port" --match-dataset "$W/ds/$d" --replan-steps 1 --serving batched --envs 16 --threads 2 \
    --quiet --out "$W/eval/$name" > "$W/logs/eval_$name.log" 2>&1
  stamp "eval $name rc=$? $(grep -o "\"success_rate\": *[0-9.]*" $W/eval/$name/summary.json 2>/dev/null | head -1)"
  cp "$W/ckpt/$ckpt/training.json" "$W/eval/$name/" 2>/dev/null
  kill $srv; wait $srv 2>/dev/null
}

tasks=$(for r in $RUNS; do echo ${r%%:*}; done | sort -u)
for d in $tasks; do demos $d $(( CORES / $(echo $tasks | wc -w) )) & done
wait
for r in $RUNS; do train $r & sleep 2; done
wait
stamp "trained"
port=9300
for r in $RUNS; do
  for k in ${EXECUTED:-10 1}; do port=$((port + 1)); evaluate $r id $k $port & sleep 1; done
done
for r in $OOD; do port=$((port + 1)); evaluate $r ood-spatial 10 $port & sleep 1; done
wait
stamp "ALL DONE"
