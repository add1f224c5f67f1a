# Sourced by the GPU-lease scripts beside it (selection_runs.sh, seed_runs.sh) after they set T
# (the tavis program), W (the work folder) and DEMOS (episodes per dataset): the folders under W,
# the progress log, the task names of the dataset short names, and the recording of one dataset
# per task, shared so that every block's demonstrations come from the same command.
CORES=$(getconf _NPROCESSORS_ONLN)
export PYTHONUNBUFFERED=1 PYTORCH_CUDA_ALLOC_CONF=expandable_segments:True
mkdir -p $W/logs $W/eval $W/ckpt $W/ds
stamp() { echo "$(date -u +%H:%M:%S) $*" | tee -a "$W/progress.log"; }
declare -A TASK=([wta]=wait-then-act [cp]=conditional-pick [cpc]=clutter-pick-cube)
stamp "start cores=$CORES $(nvidia-smi --query-gpu=name,memory.total --format=csv,noheader 2>/dev/null)"

demos() {  # d threads: DEMOS gaze-first demonstrations of task d at 96x96, 20 fps, seed 0
  [ -f "$W/ds/$1/meta/info.json" ] && return  # a re-run keeps the demonstrations it recorded
  "$T" demos --task ${TASK[$1]} --robot gr1t2 --episodes $DEMOS --fps 20 --expert-hz 20 --image-size 96x96 --seed 0 \
    --envs 32 --threads $2 --expert-mode gaze-first --out "$W/ds/$1" --quiet > "$W/logs/demos_$1.log" 2>&1
  stamp "demos $1 rc=$? $(du -sh $W/ds/$1 | cut -f1)"
}
