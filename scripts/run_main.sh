#!/usr/bin/env bash
# Installs the Debian packages, builds, and runs the main job on every real YCB-Video frame:
# detector-like boxes from the ground truth (10% jitter, 30% distractors, seed 0), then the
# Monte-Carlo estimator with default options twice: with colour, leave-one-video-out (each
# video's objects coloured only from the other videos and the synthetic frames;
# scripts/estimate_loo.sh), and depth only (--appearance off). Prints the per-object accuracy
# of both side by side, and writes the HTML report of the colour run (mcpose report) to
# out/report/.
# Usage: scripts/run_main.sh [extra `mcpose estimate` options for both runs, e.g. --threads 2]
# Outputs: out/detections.json; with colour out/results.csv, out/results.json, out/eval.json;
# depth only out/results_depth.csv, out/eval_depth.json; the captured models in out/appearance/;
# the report out/report/.
set -euo pipefail
cd "$(dirname "$0")/.."
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}"
scripts/install_deps.sh
scripts/build.sh
mkdir -p out
./build/mcpose detections-from-gt --dataset "$DATA/ycbv" --out out/detections.json \
  --jitter 0.1 --distractors 0.3 --seed 0
scripts/estimate_loo.sh "$DATA/ycbv" out/detections.json out/results.csv --out-json out/results.json "$@"
./build/mcpose estimate --dataset "$DATA/ycbv" --detections out/detections.json --appearance off \
  --out out/results_depth.csv "$@"
./build/mcpose eval --dataset "$DATA/ycbv" --results out/results.csv --json out/eval.json > /dev/null
./build/mcpose eval --dataset "$DATA/ycbv" --results out/results_depth.csv --json out/eval_depth.json > /dev/null
scripts/accuracy_table.py "colour:out/eval.json" "depth:out/eval_depth.json"
./build/mcpose report --dataset "$DATA/ycbv" --results out/results.csv --detections out/detections.json \
  --detail out/results.json --gt --out out/report
echo "run_main: the report is $(pwd)/out/report/index.html (open it in a browser)"
