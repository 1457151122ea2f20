#!/usr/bin/env bash
# Accuracy over seeds: `mcpose estimate` and `mcpose eval` on the main job's boxes
# (out/detections.json) for seeds FIRST..LAST with the given engine options. Prints each seed's
# ADD(-S) < 4 cm and ADD-S < 4 cm (% of the instances), then the mean (standard deviation;
# standard error) of every seed recorded for TAG. Each seed's results go to
# out/seeds/TAG/seed_S.csv and one line per seed to out/seeds/summary.tsv (TAG, seed,
# ADD(-S) < 4, ADD-S < 4, seconds, options; a seed run again replaces its line), which
# scripts/accuracy_compare.sh reads. Each instance's result goes to out/seeds/instances.tsv
# (scripts/accuracy_instances.py compares two tags object by object).
# DETECTIONS=FILE runs a subset of out/detections.json (e.g. one class's boxes: each (image,
# class) has its own random streams, so its poses are those of the whole run); summary.tsv
# then records the shares of the subset's instances, under a tag of their own.
# Usage: scripts/accuracy_seeds.sh TAG FIRST LAST [mcpose estimate options]
#   scripts/accuracy_seeds.sh reference 0 9 --engine float-simd --lod-px 0 --pixel-stride 1 --max-grid-pixels 0
#   scripts/accuracy_seeds.sh defaults 0 9
# Needs build/mcpose and out/detections.json: scripts/run_main.sh makes both.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 3 ]; then
  sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
TAG=$1 FIRST=$2 LAST=$3
shift 3
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}"
case "$TAG" in *[!A-Za-z0-9_.-]*|"") echo "accuracy_seeds: TAG must be letters, digits, '_', '.', '-'" >&2; exit 2 ;; esac
DETECTIONS=${DETECTIONS:-out/detections.json}
for f in build/mcpose "$DETECTIONS"; do
  [ -e "$f" ] || { echo "accuracy_seeds: $f is missing (run scripts/run_main.sh first)" >&2; exit 1; }
done
mkdir -p "out/seeds/$TAG"
SUMMARY=out/seeds/summary.tsv
touch "$SUMMARY"
for ((s = FIRST; s <= LAST; s++)); do
  csv="out/seeds/$TAG/seed_$s.csv"
  start=$(date +%s)
  ./build/mcpose estimate --dataset "$DATA/ycbv" --detections "$DETECTIONS" --out "$csv" --seed "$s" -q "$@"
  seconds=$(($(date +%s) - start))
  # The eval table's ALL row: ... | ADD-S <2 <4 AUC | ADD(-S) <2 <4 AUC.
  all=$(./build/mcpose eval --dataset "$DATA/ycbv" --results "$csv" --json "${csv%.csv}.eval.json" | awk '$1 == "ALL"')
  add_s=$(echo "$all" | awk '{print $14}') adds=$(echo "$all" | awk '{print $10}')
  [ -n "$add_s" ] || { echo "accuracy_seeds: no ALL row in the eval of $csv" >&2; exit 1; }
  # summary.tsv and instances.tsv are rewritten whole: one run at a time holds the lock (runs
  # of several tags at once lost and cut lines without it).
  exec 9> out/seeds/.lock
  flock 9
  subset=$(/usr/bin/python3 scripts/accuracy_instances.py record "$TAG" "$s" "${csv%.csv}.eval.json" "$DETECTIONS")
  if [ "$DETECTIONS" != out/detections.json ]; then
    add_s=$(echo "$subset" | awk '{print $1}') adds=$(echo "$subset" | awk '{print $2}')
  fi
  awk -F'\t' -v t="$TAG" -v s="$s" '!($1 == t && $2 == s)' "$SUMMARY" > "$SUMMARY.tmp"
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$TAG" "$s" "$add_s" "$adds" "$seconds" "$*" >> "$SUMMARY.tmp"
  mv "$SUMMARY.tmp" "$SUMMARY"
  flock -u 9
  printf '%s seed %d: ADD(-S) < 4 cm %s %%, ADD-S < 4 cm %s %% (%d s)\n' "$TAG" "$s" "$add_s" "$adds" "$seconds"
done
awk -F'\t' -v t="$TAG" '$1 == t { n++; x += $3; xx += $3 * $3 }
  END { m = x / n; sd = n > 1 ? sqrt((xx - n * m * m) / (n - 1)) : 0;
        printf "%s: %d seeds, ADD(-S) < 4 cm mean %.1f %% (SD %.1f; SE %.2f)\n", t, n, m, sd, sd / sqrt(n) }' "$SUMMARY"
