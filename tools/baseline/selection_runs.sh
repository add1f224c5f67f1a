#!/bin/bash
# The selection block of docs/baselines.md ("Selection, 2026-12-02"): heads x vision x
# demonstrations at equal time on one card, one training seed, GR1T2, head camera, id, 96 episodes,
# seed 1000, each checkpoint served with its own chunk execution (a queue of 10 rows; the act
# checkpoint also with temporal ensembling, cell `_te`). Two waves of six runs side by side, one
# wave per task (wait-then-act, clutter-pick-cube), each run stopped by the same --time-budget-s;
# wave 1's cells are evaluated while wave 2 trains. Written for one H200 with 16 cores, 128 GB and a
# 30-minute lease (the block took 18 minutes there); the frames on the card peak at ~87 GB
# (2,000 + 4 x 1,000 episodes at 96x96, three cameras).
#
#   tools/baseline/selection_runs.sh TAVIS WORK
#
# TAVIS is the `tavis` program (the portable bundle's bin/tavis on such a machine, docs/bundle.md);
# PYTHONPATH must reach tools/baseline and tools/policy_server, and a Python with PyTorch (CUDA),
# NumPy, OpenCV or PyAV, msgpack and websockets. Cells land in WORK/eval with each checkpoint's training.json beside
# them: `python3 -m tavis_baseline.selection WORK/eval` prints the tables.
set -u
if [ $# -ne 2 ] || [ ! -x "$1" ]; then
  echo "usage: $0 TAVIS WORK (TAVIS: the tavis program; got '${1:-}')" >&2
  exit 2
fi
T=$1; W=$2
BUDGET=${BUDGET:-360}      # seconds of training per run, all runs of a wave side by side
STEPS=${STEPS:-40000}      # upper bound; the budget stops them first
DEMOS=${DEMOS:-2000}
MID=${MID:-1000}; SMALL=${SMALL:-200}; EPISODES=${EPISODES:-96}; DEVICE=${DEVICE:-cuda}
source "$(dirname "$0")/gpu_block_common.sh"  # CORES, stamp, TASK, demos

train() {  # d name head episodes ["" extra options...]
  local d=$1 name=$2 head=$3 episodes=$4
  shift 4; [ $# -gt 0 ] && shift  # an empty place-holder before the extra options
  (OMP_NUM_THREADS=1 python3 -m tavis_baseline.train --dataset "$W/ds/$d" --camera head --seed 0 \
     --out "$W/ckpt/$name" --head $head --episodes $episodes --val-episodes ${VAL:-20} --steps $STEPS --time-budget-s $BUDGET \
     --save-every $((STEPS + 1)) --device $DEVICE --threads 1 "$@" > "$W/logs/train_$name.log" 2>&1
   stamp "train $name rc=$? $(grep -o 'saved .*' $W/logs/train_$name.log | tail -1)")
}

wave() {  # d: trains the wave's runs side by side (~87 GB of frames on the card at 2,000 + 4 x 1,000)
  local d=$1
  train $d ${d}_l1_$SMALL l1 $SMALL &
  train $d ${d}_l1_$DEMOS l1 $DEMOS &
  train $d ${d}_l1_$MID l1 $MID &
  train $d ${d}_flow_$MID flow $MID &
  train $d ${d}_act_$MID act $MID &
  train $d ${d}_rn18l1_$MID l1 $MID "" --vision resnet18 --crop-ratio 0.9 &
  wait
  stamp "wave $d trained"
}

evaluate() {  # d name port [serve options...]: cell `name`, from checkpoint `name` less a _te suffix
  local d=$1 name=$2 port=$3
  shift 3
  local ckpt=${name%_te}
  [ -f "$W/ckpt/$ckpt/config.json" ] || { stamp "eval $name skipped: no checkpoint"; return; }
  python3 -m tavis_baseline.serve "$W/ckpt/$ckpt" --port $port --device $DEVICE "$@" \
    > "$W/logs/serve_$name.log" 2>&1 &
  local s=$!
  for _ in $(seq 120); do python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$port/healthz')" 2>/dev/null && break; sleep 1; done
  "$T" eval --task ${TASK[$d]} --robot gr1t2 --camera head --split id --episodes $EPISODES --seed 1000 --policy openpi \
    --server "ws://127.0.0.1:$port" --match-dataset "$W/ds/$d" --replan-steps 1 --serving batched --envs 16 --threads 2 \
    --quiet --out "$W/eval/$name" > "$W/logs/eval_$name.log" 2>&1
  stamp "eval $name rc=$? $(grep -o "\"success_rate\": *[0-9.]*" $W/eval/$name/summary.json 2>/dev/null | head -1)"
  cp "$W/ckpt/$ckpt/training.json" "$W/eval/$name/" 2>/dev/null
  kill $s; wait $s 2>/dev/null
}

evaluate_wave() {  # d port
  local d=$1 port=$2
  for c in $W/ckpt/${d}_*; do port=$((port + 1)); evaluate $d $(basename $c) $port & sleep 1; done
  [ -d $W/ckpt/${d}_act_$MID ] && { port=$((port + 1)); evaluate $d ${d}_act_${MID}_te $port --temporal-ensemble 0.01 & }
  wait
}

demos wta $CORES
demos cpc $((CORES > 8 ? CORES - 4 : 1)) &
cpc_demos=$!
wave wta
wait $cpc_demos
evaluate_wave wta 9100 &
ev=$!
wave cpc
wait $ev
evaluate_wave cpc 9200
stamp "ALL DONE"
