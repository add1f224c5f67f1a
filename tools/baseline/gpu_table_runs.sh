#!/bin/bash
# The baseline table's runs on one GPU machine (docs/baselines.md, second measurement): the
# demonstrations, fifteen trainings side by side on the one card, then the evaluation cells served
# from the GPU, nine at a time, with the expert on the same scenes. Written for a 16-core machine
# with one H100; everything lands under WORK (datasets ds/, checkpoints ckpt/, cells eval/,
# logs/, and progress.log, a line per finished step).
#
#   tools/baseline/gpu_table_runs.sh TAVIS WORK
#
# TAVIS is the `tavis` program (on a machine without the project's Debian libraries, the
# portable bundle's bin/tavis, docs/bundle.md); PYTHONPATH must reach batch/python and a Python
# with PyTorch (CUDA), NumPy, OpenCV or PyAV, msgpack and websockets.
set -u
T=$1
W=$2
mkdir -p "$W/logs" "$W/eval" "$W/ckpt" "$W/ds"
export PYTHONUNBUFFERED=1 OMP_NUM_THREADS=1
stamp() { echo "$(date -u +%H:%M:%S) $*" >> "$W/progress.log"; }

demo() {  # name task expert-mode
  "$T" demos --task "$2" --robot gr1t2 --episodes 200 --fps 20 --expert-hz 20 --image-size 96x96 --seed 0 --envs 8 \
     --threads 5 --expert-mode "$3" --out "$W/ds/$1" --quiet > "$W/logs/demos_$1.log" 2>&1
  stamp "demos $1 rc=$?"
}
demo cp conditional-pick gaze-first &
demo wta wait-then-act gaze-first &
demo wtahs wait-then-act head-still &
wait

train() {  # dataset camera seed name
  python3 -m tavis_baseline.train --dataset "$W/ds/$1" --camera "$2" --seed "$3" --out "$W/ckpt/$4" --steps 4000 \
     --time-budget-s 660 --device cuda --val-episodes 10 --threads 1 > "$W/logs/train_$4.log" 2>&1
  stamp "train $4 rc=$?"
}
for seed in 0 1 2; do
  for task in cp wta; do
    for camera in head fixed; do train $task $camera $seed ${task}_${camera}_$seed & done
  done
  train wtahs fixed $seed wtahs_fixed_$seed &  # the fixed-camera bias ablation
done
wait

declare -A TASK=([cp]=conditional-pick [wta]=wait-then-act [wtahs]=wait-then-act)
evaluate() {  # checkpoint split port
  local name=$1 split=$2 port=$3
  local dataset=${name%%_*} camera
  camera=$(echo "$name" | cut -d_ -f2)
  python3 -m tavis_baseline.serve "$W/ckpt/$name" --port "$port" --device cuda > "$W/logs/serve_${name}_$split.log" 2>&1 &
  local server=$!
  for _ in $(seq 120); do
    python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$port/healthz')" 2>/dev/null && break
    sleep 1
  done
  "$T" eval --task "${TASK[$dataset]}" --robot gr1t2 --camera "$camera" --split "$split" --episodes 96 --seed 1000 \
     --policy openpi --server "ws://127.0.0.1:$port" --match-dataset "$W/ds/$dataset" --replan-steps 1 --serving batched \
     --envs 16 --threads 2 --quiet --out "$W/eval/${name}_$split" > "$W/logs/eval_${name}_$split.log" 2>&1
  stamp "eval ${name}_$split rc=$?"
  kill $server
  wait $server 2>/dev/null
}
# The expert on the same scenes (the GALT reference), then the policies: id first.
for task in conditional-pick wait-then-act; do
  for split in id ood-spatial ood-init-pose; do
    "$T" eval --task $task --robot gr1t2 --split $split --episodes 96 --seed 1000 --expert-hz 20 --threads 1 --quiet \
       --out "$W/eval/expert_${task}_$split" > "$W/logs/expert_${task}_$split.log" 2>&1 &
  done
done
cells=()
for split in id ood-spatial ood-init-pose; do
  for seed in 0 1 2; do
    for name in cp_head cp_fixed wta_head wta_fixed; do cells+=("${name}_$seed $split"); done
    [ $split = id ] && cells+=("wtahs_fixed_$seed $split")
  done
done
port=9100
for cell in "${cells[@]}"; do
  while [ "$(jobs -r | wc -l)" -ge 9 ]; do sleep 2; done
  port=$((port + 1))
  # shellcheck disable=SC2086  # "checkpoint split" splits into two arguments
  evaluate $cell $port &
done
wait
stamp "ALL DONE"
