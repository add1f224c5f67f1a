#!/usr/bin/env bash
# Prints "cell sha256" for the records of the scripted expert's reference cells: every task of both
# suites on both robots (split id) and clutter-pick-cube ood-init-pose on both robots, 96 episodes,
# seed 0 (the defaults). A refactor must leave every line unchanged (issue 26, acceptance 1).
# Each line: "cell HASH with events HASH2" (below).
#
#   tools/dev/record_hashes.sh [TAVIS_BINARY] [WORK_DIR]   (defaults: build/tavis, a fresh temp dir)
set -euo pipefail
tavis=${1:-build/tavis}
work=${2:-$(mktemp -d)}
[[ -x $tavis ]] || { echo "record_hashes: no program '$tavis' (build the tavis target)" >&2; exit 2; }
mkdir -p "$work"
for robot in gr1t2 reachy2; do
  for suite in tavis-head tavis-hands; do
    "$tavis" eval --suite "$suite" --robot "$robot" --split id --policy expert --out "$work/$robot-$suite" \
      --overwrite > "$work/$robot-$suite.log" 2>&1 || { cat "$work/$robot-$suite.log" >&2; exit 1; }
  done
  "$tavis" eval --task clutter-pick-cube --robot "$robot" --split ood-init-pose --policy expert \
    --out "$work/$robot-ood/clutter-pick-cube_${robot}_ood-init-pose" --overwrite \
    > "$work/$robot-ood.log" 2>&1 || { cat "$work/$robot-ood.log" >&2; exit 1; }
done
# The hash is of the records without the keys issue 49 added (failure "events" and arm "motion",
# docs/events.md), cut from each line as written (keys are sorted, so each is followed by a comma),
# so that the lines stay comparable with hashes taken before them; "with events" hashes whole lines.
strip_new_keys() {
  sed -E 's/"events":\{[^}]*\},//; s/"motion":\{"left":\{[^}]*\},"right":\{[^}]*\}\},//' "$1"
}
for file in "$work"/*/*/episodes.jsonl; do
  cell=$(basename "$(dirname "$file")")
  echo "$cell $(strip_new_keys "$file" | sha256sum | cut -d' ' -f1) with events $(sha256sum < "$file" | cut -d' ' -f1)"
done | sort
