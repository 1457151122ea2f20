#!/usr/bin/env bash
# The colour protocol over box seeds: for each seed S in FIRST..LAST, detector-like boxes
# (detections-from-gt --jitter 0.1 --distractors 0.3 --seed S), then the estimator with seed S
# twice on the same boxes: leave-one-video-out with colour (scripts/estimate_loo.sh) and depth
# only (--appearance off). Prints per object and overall the mean over the seeds of the runs side
# by side (scripts/accuracy_table.py). LOO_CAPTURED=1 adds a third run,
# "captured": the same with the three real textures replaced by appearance captured like the
# others' (CAPTURE_OPTIONS=--replace-own-colour, models in out/appearance_captured). The models
# are captured once, for the first seed. Files: $LOO_SEEDS_DIR (default out/loo_seeds/).
# Usage: scripts/accuracy_loo.sh FIRST LAST [mcpose estimate options for both runs]
# Needs build/mcpose (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ]; then sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; fi
FIRST=$1 LAST=$2
shift 2
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}/ycbv"
dir=${LOO_SEEDS_DIR:-out/loo_seeds}
mkdir -p "$dir"
evals=()
for ((s = FIRST; s <= LAST; s++)); do
  ./build/mcpose detections-from-gt --dataset "$DATA" --out "$dir/dets_$s.json" --jitter 0.1 --distractors 0.3 --seed "$s" > /dev/null
  keep=$([ "$s" = "$FIRST" ] && echo 0 || echo 1)
  runs=(colour depth)
  LOO_KEEP_MODELS=$keep scripts/estimate_loo.sh "$DATA" "$dir/dets_$s.json" "$dir/colour_$s.csv" -q --seed "$s" "$@"
  if [ "${LOO_CAPTURED:-0}" = 1 ]; then
    APPEARANCE_DIR=out/appearance_captured CAPTURE_OPTIONS=--replace-own-colour LOO_KEEP_MODELS=$keep \
      scripts/estimate_loo.sh "$DATA" "$dir/dets_$s.json" "$dir/captured_$s.csv" -q --seed "$s" "$@"
    runs=(colour captured depth)
  fi
  ./build/mcpose estimate --dataset "$DATA" --detections "$dir/dets_$s.json" --out "$dir/depth_$s.csv" -q --seed "$s" \
    --appearance off "$@"
  for run in "${runs[@]}"; do
    ./build/mcpose eval --dataset "$DATA" --results "$dir/${run}_$s.csv" --json "$dir/${run}_$s.eval.json" > /dev/null
    evals+=("$run:$dir/${run}_$s.eval.json")
  done
done
scripts/accuracy_table.py "${evals[@]}"
