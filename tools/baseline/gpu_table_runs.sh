#!/bin/bash
# The baseline table's runs on one GPU machine (docs/baselines.md, third measurement): four
# demonstration sets, twenty-one trainings in two waves on the one card, and the evaluation cells
# served from the GPU, with the expert on the same scenes. Written for a 16-core machine with one
# H100 and a 30-minute lease; everything lands under WORK (datasets ds/, checkpoints ckpt/, cells
# eval/, logs/, and progress.log, a line per finished step).
#
#   tools/baseline/gpu_table_runs.sh TAVIS WORK
#
# TAVIS is the `tavis` program (on a machine without the project's Debian libraries, the
# portable bundle's bin/tavis, docs/bundle.md); PYTHONPATH must reach tools/baseline and
# tools/policy_server, and a Python with PyTorch (CUDA), NumPy, OpenCV or PyAV, msgpack and
# websockets.
#
# Why waves: runs side by side share the card's time (one run alone made 58.8 steps/s, four side
# by side 4 x 14, twelve 12 x 4.6), so the total number of steps is set by the lease, not by how
# many run at once; fifteen at once ran out of its 78 GiB. Every run trains a fixed number of
# steps (--steps), so each number of the table is reproducible by its command whatever else
# shared the card. The first wave's cells are evaluated while the second wave trains.
set -u
if [ $# -ne 2 ] || [ ! -x "$1" ]; then
  echo "usage: $0 TAVIS WORK (TAVIS: the tavis program; got '${1:-}')" >&2
  exit 2
fi
T=$1
W=$2
STEPS=${STEPS:-1800}
# Rows of each predicted chunk executed per forward pass, stored in each checkpoint's config.json
# and served as stored (tavis_baseline.serve reads it): a queue of 10 rows (the measured default,
# docs/baselines.md "Chunk execution"); 1 re-plans every step.
EXECUTED_STEPS=${EXECUTED_STEPS:-10}
mkdir -p "$W/logs" "$W/eval" "$W/ckpt" "$W/ds"
export PYTHONUNBUFFERED=1 OMP_NUM_THREADS=1 PYTORCH_CUDA_ALLOC_CONF=expandable_segments:True
stamp() { echo "$(date -u +%H:%M:%S) $*" >> "$W/progress.log"; }

declare -A TASK=([cp]=conditional-pick [wta]=wait-then-act [wtahs]=wait-then-act [cpc]=clutter-pick-cube)
demo() {  # name expert-mode
  "$T" demos --task "${TASK[$1]}" --robot gr1t2 --episodes 200 --fps 20 --expert-hz 20 --image-size 96x96 --seed 0 \
     --envs 8 --threads 4 --expert-mode "$2" --out "$W/ds/$1" --quiet > "$W/logs/demos_$1.log" 2>&1
  stamp "demos $1 rc=$?"
}
demo cp gaze-first &
demo wta gaze-first &
demo wtahs head-still &
demo cpc gaze-first &
wait

train() {  # name (dataset_camera_seed)
  local dataset camera seed
  IFS=_ read -r dataset camera seed <<< "$1"
  python3 -m tavis_baseline.train --dataset "$W/ds/$dataset" --camera "$camera" --seed "$seed" --out "$W/ckpt/$1" \
     --steps "$STEPS" --executed-steps "$EXECUTED_STEPS" --time-budget-s 900 --device cuda --val-episodes 10 --threads 1 > "$W/logs/train_$1.log" 2>&1
  stamp "train $1 rc=$?"
}
train_wave() {  # names...; waits for these runs only (cells of the other wave go on)
  local pids=()
  for name in "$@"; do train "$name" & pids+=($!); sleep 2; done
  wait "${pids[@]}"
}

evaluate() {  # checkpoint split port
  local name=$1 split=$2 port=$3
  local dataset camera
  IFS=_ read -r dataset camera _ <<< "$name"
  # No --executed-steps: each checkpoint is served with its own setting (summary.json's
  # server_metadata records executed_steps, chunk_execution and action_queue).
  nice -n 5 python3 -m tavis_baseline.serve "$W/ckpt/$name" --port "$port" --device cuda \
     > "$W/logs/serve_${name}_$split.log" 2>&1 &
  local server=$!
  for _ in $(seq 120); do
    python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$port/healthz')" 2>/dev/null && break
    sleep 1
  done
  nice -n 5 "$T" eval --task "${TASK[$dataset]}" --robot gr1t2 --camera "$camera" --split "$split" --episodes 96 \
     --seed 1000 --policy openpi --server "ws://127.0.0.1:$port" --match-dataset "$W/ds/$dataset" --replan-steps 1 \
     --serving batched --envs 16 --threads 2 --quiet --out "$W/eval/${name}_$split" > "$W/logs/eval_${name}_$split.log" 2>&1
  stamp "eval ${name}_$split rc=$?"
  kill $server
  wait $server 2>/dev/null
}
evaluate_all() {  # first-port checkpoint-names...
  local port=$1
  shift
  for split in id ood-spatial ood-init-pose; do
    for name in "$@"; do
      [ "${name%%_*}" = wtahs ] && [ $split != id ] && continue  # the ablation is an id comparison
      while [ "$(jobs -r | wc -l)" -ge 8 ]; do sleep 2; done
      port=$((port + 1))
      evaluate "$name" $split $port &
    done
  done
  wait
}

names() {  # dataset cameras...
  local dataset=$1
  shift
  for seed in 0 1 2; do for camera in "$@"; do echo "${dataset}_${camera}_$seed"; done; done
}
wave1=($(names cp head fixed) $(names wta head fixed))
wave2=($(names cpc head fixed) $(names wtahs fixed))  # wtahs: the fixed-camera bias ablation

# The expert on the same scenes (the GALT reference), on the CPUs the first wave leaves.
for task in conditional-pick wait-then-act clutter-pick-cube; do
  for split in id ood-spatial ood-init-pose; do
    nice -n 5 "$T" eval --task $task --robot gr1t2 --split $split --episodes 96 --seed 1000 --expert-hz 20 --threads 1 \
       --quiet --out "$W/eval/expert_${task}_$split" > "$W/logs/expert_${task}_$split.log" 2>&1 &
  done
done
train_wave "${wave1[@]}"
stamp "wave 1 trained"
evaluate_all 9100 "${wave1[@]}" &
train_wave "${wave2[@]}"
stamp "wave 2 trained"
evaluate_all 9300 "${wave2[@]}"
wait
stamp "ALL DONE"
