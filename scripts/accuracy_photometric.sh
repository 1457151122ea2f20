#!/usr/bin/env bash
# Photometric robustness of the colour term: every real frame of the YCB-Video data re-lit
# (mcpose-tools relight: the colour image transformed, depth untouched) by each transform below,
# then the estimator with the textured models (../shared/data/ycbv_textured/models, or
# $MODELS) on the same detector-like boxes (seed S: --jitter 0.1 --distractors 0.3), and the
# depth-only run once (depth is the same in every version). Prints ADD(-S) < 4 cm, ADD-S < 4 cm,
# ADD-S AUC overall and for the banana, mustard bottle and tomato soup can per transform, beside
# the untransformed run and depth only.
# Usage: scripts/accuracy_photometric.sh [SEED] [mcpose estimate options]
# Files: $PHOTOMETRIC_DIR (default out/photometric/): the re-lit datasets, results, evaluations.
# Needs build/mcpose and build/mcpose-tools (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
SEED=${1:-0}
[ $# -gt 0 ] && shift
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}"
MODELS=${MODELS:-$DATA/ycbv_textured/models}
dir=${PHOTOMETRIC_DIR:-out/photometric}
mkdir -p "$dir"
TRANSFORMS=(none exposure:0.5 exposure:2 gamma:0.6 gamma:1.6 white-balance:1.3,1,0.7 white-balance:0.7,1,1.3
  white-balance:1,1.3,0.7 saturation:0.5 saturation:1.5 clip:0.8 jpeg:30 noise:8)
dets="$dir/dets_$SEED.json"
./build/mcpose detections-from-gt --dataset "$DATA/ycbv" --out "$dets" --jitter 0.1 --distractors 0.3 \
  --seed "$SEED" > /dev/null
evals=()
for t in "${TRANSFORMS[@]}"; do
  name=${t//[:,]/_}
  ds="$dir/ycbv_$name"
  [ -d "$ds" ] || ./build/mcpose-tools relight --dataset "$DATA/ycbv" --out "$ds" --transform "$t" --seed "$SEED"
  ./build/mcpose estimate --dataset "$ds" --models "$MODELS" --detections "$dets" --out "$dir/${name}_$SEED.csv" \
    -q --seed "$SEED" "$@"
  ./build/mcpose eval --dataset "$DATA/ycbv" --results "$dir/${name}_$SEED.csv" --json "$dir/${name}_$SEED.eval.json" \
    > /dev/null
  evals+=("$t:$dir/${name}_$SEED.eval.json")
done
./build/mcpose estimate --dataset "$DATA/ycbv" --detections "$dets" --out "$dir/depth_$SEED.csv" -q --seed "$SEED" \
  --appearance off "$@"
./build/mcpose eval --dataset "$DATA/ycbv" --results "$dir/depth_$SEED.csv" --json "$dir/depth_$SEED.eval.json" > /dev/null
evals+=("depth only:$dir/depth_$SEED.eval.json")
scripts/accuracy_table.py --transposed --objects 011_banana,006_mustard_bottle,005_tomato_soup_can \
  --baseline none "${evals[@]}"
