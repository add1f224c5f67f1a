#!/bin/bash
# A real single-node Slurm (Debian's slurm-wlm and munge, daemons on localhost, private ports,
# sockets and state under a temporary folder) runs tools/slurm/sweep_array.sbatch as a 3-task job
# array over a small sweep. Then the documented recovery: one task's shard is lost, merge refuses
# the rest, the task is resubmitted alone (`--array=1 ... N`; without N that is refused with a
# message saying how), and `tavis sweep merge` combines the shards: the merged result must equal
# the same sweep run locally in one piece (apart from the timing fields).
#
# usage: slurm_sweep_test.sh TAVIS_BINARY SOURCE_DIR      (needs root, or sudo without a password,
# for slurmd; about 20-40 s)
set -euo pipefail
tavis=$1
source_dir=$2
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo -n)
for program in munged slurmctld slurmd sbatch sinfo; do
  command -v "$program" >/dev/null || PATH=$PATH:/usr/sbin
  command -v "$program" >/dev/null || { echo "FAIL: $program missing (slurm-wlm, munge: .ci/install-deps)"; exit 1; }
done

work=$(mktemp -d /tmp/tavis_slurm_test.XXXXXX)
chmod 755 "$work"
pids=()
cleanup() {
  for pid in "${pids[@]}"; do "${sudo_cmd[@]}" kill "$pid" 2>/dev/null || true; done
  sleep 0.5
  for pid in "${pids[@]}"; do "${sudo_cmd[@]}" kill -9 "$pid" 2>/dev/null || true; done
  "${sudo_cmd[@]}" rm -rf "$work"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*"
  for log in "$work"/*.log "$work"/out/*.log; do [ -f "$log" ] && { echo "--- $log"; tail -20 "$log"; }; done
  exit 1
}

# munge: its own key, socket and files, so the machine's munge (if any) is left alone.
mkdir -p "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 700 "$work/munge"
chmod 400 "$work/munge/munge.key"
"${sudo_cmd[@]}" chown -R root:root "$work/munge"
"${sudo_cmd[@]}" munged --force --socket="$work/munge/munge.socket" --key-file="$work/munge/munge.key" \
  --pid-file="$work/munge/munged.pid" --log-file="$work/munged.log" --seed-file="$work/munge/munged.seed"
for _ in $(seq 50); do [ -f "$work/munge/munged.pid" ] && break; sleep 0.1; done
pids+=("$("${sudo_cmd[@]}" cat "$work/munge/munged.pid")")

# Slurm: one node (this machine, as "localhost") with its cores, one partition, ports off the defaults.
cpus=$(nproc)
mkdir -p "$work/state" "$work/spool" "$work/out"
chmod 777 "$work/out"
cat >"$work/slurm.conf" <<CONF
ClusterName=tavistest
SlurmctldHost=localhost
SlurmctldPort=16917
SlurmdPort=16918
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$work/munge/munge.socket
SlurmUser=root
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
ReturnToService=2
PlugStackConfig=/dev/null
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf
"${sudo_cmd[@]}" env SLURM_CONF="$SLURM_CONF" slurmctld -f "$SLURM_CONF" -i
"${sudo_cmd[@]}" env SLURM_CONF="$SLURM_CONF" slurmd -f "$SLURM_CONF" -N localhost
for _ in $(seq 100); do [ -f "$work/slurmctld.pid" ] && [ -f "$work/slurmd.pid" ] && break; sleep 0.1; done
pids+=("$(cat "$work/slurmctld.pid")" "$(cat "$work/slurmd.pid")")
for _ in $(seq 100); do
  sinfo -h -o %T 2>/dev/null | grep -qx idle && break
  sleep 0.2
done
sinfo -h -o %T | grep -qx idle || fail "the Slurm node did not come up: $(sinfo 2>&1)"

# The sweep: 6 cells of 4 episodes.
cat >"$work/out/spec.yaml" <<SPEC
tasks: [clutter-pick-cube]
robots: [gr1t2]
splits: [id, ood-spatial, ood-init-pose]
cameras: [head, fixed]
seeds: [1]
episodes: 4
envs: 2
policy:
  name: expert
SPEC
cd "$work/out"
TAVIS=$tavis timeout 300 sbatch --wait --array=0-2 --cpus-per-task=1 --chdir="$work/out" \
  "$source_dir/tools/slurm/sweep_array.sbatch" "$work/out/spec.yaml" "$work/out/shards" 3 >"$work/sbatch.out" 2>&1 ||
  fail "the job array failed: $(cat "$work/sbatch.out")"
for index in 0 1 2; do
  [ -f "$work/out/shards/shard_$index/manifest.json" ] || fail "array task $index left no shard"
done

# Recovery (README, docs/sweeps.md): task 1's shard is lost, as when its node died.
rm -rf "$work/out/shards/shard_1"
if "$tavis" sweep merge --out "$work/out/merged_partial" "$work/out/shards"/shard_* >"$work/merge_partial.log" 2>&1; then
  fail "merge accepted shards 0 and 2 of 3"
fi
# Without N, a resubmitted task cannot know the shard count: it must say so, not guess.
TAVIS=$tavis timeout 120 sbatch --wait --array=1 --cpus-per-task=1 --chdir="$work/out" \
  "$source_dir/tools/slurm/sweep_array.sbatch" "$work/out/spec.yaml" "$work/out/shards" >"$work/sbatch_no_n.out" 2>&1 &&
  fail "a resubmitted task without N ran"
grep -q "give N" "$work/out"/tavis-sweep-*_1.log || fail "a resubmitted task without N did not say how: $(cat "$work/out"/tavis-sweep-*_1.log)"
[ ! -e "$work/out/shards/shard_1" ] || fail "a refused task wrote a shard"
# The documented recovery: the task alone, with N.
TAVIS=$tavis timeout 300 sbatch --wait --array=1 --cpus-per-task=1 --chdir="$work/out" \
  "$source_dir/tools/slurm/sweep_array.sbatch" "$work/out/spec.yaml" "$work/out/shards" 3 >"$work/sbatch_recovery.out" 2>&1 ||
  fail "the resubmitted task failed: $(cat "$work/sbatch_recovery.out")"
[ -f "$work/out/shards/shard_1/manifest.json" ] || fail "the resubmitted task left no shard"
"$tavis" sweep merge --out "$work/out/merged" "$work/out/shards"/shard_* >/dev/null || fail "merge failed"
"$tavis" sweep "$work/out/spec.yaml" --out "$work/out/local" --quiet >/dev/null || fail "the local run failed"

/usr/bin/python3 - "$work/out/local" "$work/out/merged" <<'PY' || fail "the merged result differs from the local run"
import json, os, re, sys
def results(root):
    files = {}
    for folder, _, names in os.walk(root):
        for name in names:
            path = os.path.join(folder, name)
            rel = os.path.relpath(path, root)
            if rel == "manifest.json":
                continue
            if not name.endswith((".json", ".jsonl", ".md", ".csv", ".tex", ".html", ".svg")):
                files[rel] = open(path, "rb").read()  # figures' PNGs and the like: compared as bytes
                continue
            text = open(path, encoding="utf-8").read()
            if rel.startswith("cells/") and name == "summary.json":
                summary = json.loads(text)
                for timing in ("wall_s", "control_ticks_per_s", "threads", "resumed_episodes", "control_ticks",
                               "provenance"):
                    summary.pop(timing, None)
                text = json.dumps(summary, sort_keys=True)
            elif rel == "report.html":
                text = re.sub(r'<pre id="manifest">.*?</pre>', "", text, flags=re.S)
            elif name == "episode_times.jsonl":  # the seconds are how it ran, the episodes timed are not
                text = [json.loads(line)["episode"] for line in text.splitlines()]
            files[rel] = text
    return files
local, merged = results(sys.argv[1]), results(sys.argv[2])
if local != merged:
    print("differ:", sorted(k for k in set(local) | set(merged) if local.get(k) != merged.get(k)))
    sys.exit(1)
print("slurm ok: a 3-task job array with task 1 rerun alone: shards merged equal the local run (%d files, %d cells)"
      % (len(local), sum(1 for k in local if k.endswith("episodes.jsonl"))))
PY

# The sweep lock on Slurm: a task requeued while its first attempt still runs (or the same task
# submitted twice) must be refused naming the holder, and the first attempt's shard must come out
# whole. One 96-episode cell on one CPU runs for seconds, so the second attempt is submitted once
# the first holds the shard's lock.
mkdir -p "$work/lock"
chmod 777 "$work/lock"
cat >"$work/lock/spec.yaml" <<SPEC
tasks: [clutter-pick-cube]
robots: [gr1t2]
splits: [id]
cameras: [head]
seeds: [2]
episodes: 96
envs: 2
policy:
  name: expert
SPEC
TAVIS=$tavis timeout 300 sbatch --wait --array=0 --cpus-per-task=1 --chdir="$work/lock" \
  "$source_dir/tools/slurm/sweep_array.sbatch" "$work/lock/spec.yaml" "$work/lock/shards" 1 >"$work/sbatch_first.out" 2>&1 &
first=$!
for _ in $(seq 300); do
  [ -s "$work/lock/shards/shard_0/.tavis_lock" ] && break
  sleep 0.1
done
[ -s "$work/lock/shards/shard_0/.tavis_lock" ] || fail "the first attempt never held the shard's lock"
if TAVIS=$tavis timeout 120 sbatch --wait --array=0 --cpus-per-task=1 --chdir="$work/lock" \
     "$source_dir/tools/slurm/sweep_array.sbatch" "$work/lock/spec.yaml" "$work/lock/shards" 1 >"$work/sbatch_second.out" 2>&1; then
  fail "a second attempt of a running task was not refused"
fi
wait $first || fail "the first attempt failed beside the refused one: $(cat "$work/sbatch_first.out")"
grep -l "is being written by" "$work/lock"/tavis-sweep-*_0.log >/dev/null ||
  fail "the refused attempt did not name the lock's holder: $(cat "$work/lock"/tavis-sweep-*_0.log)"
records=$(cat "$work/lock/shards/shard_0"/cells/*/episodes.jsonl | wc -l)
[ "$records" -eq 96 ] || fail "the locked shard holds $records records, not 96"
[ -f "$work/lock/shards/shard_0/manifest.json" ] || fail "the locked shard has no manifest"
echo "slurm lock ok: a second attempt of a running task was refused naming the holder; the first wrote its 96 records"
