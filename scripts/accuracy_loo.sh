#!/usr/bin/env bash
# The main job's protocol over box seeds: for each seed S in FIRST..LAST, detector-like boxes
# (detections-from-gt --jitter 0.1 --distractors 0.3 --seed S), then the estimator with seed S
# three times on the same boxes, as scripts/run_main.sh does: textured (the real textures of
# $DATA/ycbv_textured/models, or $MODELS), captured (leave-one-video-out appearance,
# scripts/estimate_loo.sh; the models are captured once, for the first seed) and depth only
# (--appearance off). Prints per object, per video and overall the mean over the seeds of the
# three runs side by side (scripts/accuracy_table.py --per-video). Files: $LOO_SEEDS_DIR
# (default out/loo_seeds/). LOO_RUNS="textured depth" (a subset of textured, captured, depth)
# runs only those.
# Usage: scripts/accuracy_loo.sh FIRST LAST [mcpose estimate options for every run]
# Needs build/mcpose (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ]; then sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; fi
FIRST=$1 LAST=$2
shift 2
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}"
MODELS=${MODELS:-$DATA/ycbv_textured/models}
dir=${LOO_SEEDS_DIR:-out/loo_seeds}
read -r -a runs <<< "${LOO_RUNS:-textured captured depth}"
mkdir -p "$dir"
evals=()
for ((s = FIRST; s <= LAST; s++)); do
  dets="$dir/dets_$s.json"
  ./build/mcpose detections-from-gt --dataset "$DATA/ycbv" --out "$dets" --jitter 0.1 --distractors 0.3 --seed "$s" \
    > /dev/null
  for run in "${runs[@]}"; do
    out="$dir/${run}_$s.csv"
    case $run in
      textured)
        ./build/mcpose estimate --dataset "$DATA/ycbv" --models "$MODELS" --detections "$dets" --out "$out" -q \
          --seed "$s" "$@" ;;
      captured)
        keep=$([ "$s" = "$FIRST" ] && echo 0 || echo 1)
        LOO_KEEP_MODELS=$keep scripts/estimate_loo.sh "$DATA/ycbv" "$dets" "$out" -q --seed "$s" "$@" ;;
      depth)
        ./build/mcpose estimate --dataset "$DATA/ycbv" --detections "$dets" --out "$out" -q --seed "$s" \
          --appearance off "$@" ;;
      *) echo "accuracy_loo: unknown run '$run' in LOO_RUNS (textured, captured, depth)" >&2; exit 2 ;;
    esac
    ./build/mcpose eval --dataset "$DATA/ycbv" --metrics ycbv,bop19 \
      --models-info "$DATA/bop_ycbv_subset/models/models_info.json" --results "$out" --json "$dir/${run}_$s.eval.json" > /dev/null
    evals+=("$run:$dir/${run}_$s.eval.json")
  done
done
scripts/accuracy_table.py --per-video "${evals[@]}"
