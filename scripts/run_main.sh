#!/usr/bin/env bash
# Installs the Debian packages, builds, and runs the main job on every real YCB-Video frame:
# detector-like boxes from the ground truth (10% jitter, 30% distractors, seed 0), then the
# Monte-Carlo estimator with default options three times on the same boxes:
#   textured  with the objects' real colour textures ($DATA/ycbv_textured/models, or $MODELS);
#   captured  with colour captured from other frames, leave-one-video-out (each video's objects
#             coloured only from the other videos and the synthetic frames; scripts/estimate_loo.sh):
#             the condition of a user whose CAD models have no colour;
#   depth     depth only (--appearance off).
# Prints the per-object and per-video accuracy of the three side by side, and writes the HTML
# report of the textured run (mcpose report) to out/report/.
# Usage: scripts/run_main.sh [extra `mcpose estimate` options for every run, e.g. --threads 2]
# Outputs: out/detections.json; textured out/results.csv, out/results.json, out/eval.json;
# captured out/results_captured.csv, out/eval_captured.json (models in out/appearance/); depth
# only out/results_depth.csv, out/eval_depth.json; the report out/report/.
set -euo pipefail
cd "$(dirname "$0")/.."
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}"
MODELS=${MODELS:-$DATA/ycbv_textured/models}
scripts/install_deps.sh
scripts/build.sh
mkdir -p out
./build/mcpose detections-from-gt --dataset "$DATA/ycbv" --out out/detections.json \
  --jitter 0.1 --distractors 0.3 --seed 0
./build/mcpose estimate --dataset "$DATA/ycbv" --models "$MODELS" --detections out/detections.json \
  --out out/results.csv --out-json out/results.json "$@"
scripts/estimate_loo.sh "$DATA/ycbv" out/detections.json out/results_captured.csv "$@"
./build/mcpose estimate --dataset "$DATA/ycbv" --detections out/detections.json --appearance off \
  --out out/results_depth.csv "$@"
for run in "" _captured _depth; do
  ./build/mcpose eval --dataset "$DATA/ycbv" --metrics ycbv,bop19 \
      --models-info "$DATA/bop_ycbv_subset/models/models_info.json" --results "out/results$run.csv" --json "out/eval$run.json" > /dev/null
done
scripts/accuracy_table.py --per-video "textured:out/eval.json" "captured:out/eval_captured.json" \
  "depth:out/eval_depth.json"
./build/mcpose report --dataset "$DATA/ycbv" --results out/results.csv \
  --detections out/detections.json --detail out/results.json --gt --out out/report
echo "run_main: the report is $(pwd)/out/report/index.html (open it in a browser)"
