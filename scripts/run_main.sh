#!/usr/bin/env bash
# Installs the Debian packages, builds, and runs the main job on every real YCB-Video frame:
# detector-like boxes from the ground truth (10% jitter, 30% distractors), the Monte-Carlo
# estimator with default options, the YCB-Video accuracy table per object, and the HTML report
# (mcpose report) in out/report/.
# Usage: scripts/run_main.sh [extra `mcpose estimate` options, e.g. --threads 2]
# Outputs: out/detections.json, out/results.csv, out/results.json, out/eval.json, out/report/
set -euo pipefail
cd "$(dirname "$0")/.."
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}"
scripts/install_deps.sh
scripts/build.sh
mkdir -p out
./build/mcpose detections-from-gt --dataset "$DATA/ycbv" --out out/detections.json \
  --jitter 0.1 --distractors 0.3 --seed 0
./build/mcpose estimate --dataset "$DATA/ycbv" --detections out/detections.json \
  --out out/results.csv --out-json out/results.json "$@"
./build/mcpose eval --dataset "$DATA/ycbv" --results out/results.csv --json out/eval.json
./build/mcpose report --dataset "$DATA/ycbv" --results out/results.csv --detections out/detections.json \
  --detail out/results.json --gt --out out/report
echo "run_main: the report is $(pwd)/out/report/index.html (open it in a browser)"
