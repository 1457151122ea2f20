#!/usr/bin/env bash
# The colour protocol over box seeds: for each seed S in FIRST..LAST, detector-like boxes
# (detections-from-gt --jitter 0.1 --distractors 0.3 --seed S), then the estimator with seed S
# twice on the same boxes: leave-one-video-out with colour (scripts/estimate_loo.sh) and depth
# only (--appearance off). Prints each seed's ADD(-S) < 4 cm and ADD-S < 4 cm, then per object
# and overall the mean over the seeds of both runs side by side. Files: out/loo_seeds/.
# Usage: scripts/accuracy_loo.sh FIRST LAST [mcpose estimate options for both runs]
# Needs build/mcpose (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ]; then sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; fi
FIRST=$1 LAST=$2
shift 2
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}/ycbv"
dir=out/loo_seeds
mkdir -p "$dir"
evals=()
for ((s = FIRST; s <= LAST; s++)); do
  ./build/mcpose detections-from-gt --dataset "$DATA" --out "$dir/dets_$s.json" --jitter 0.1 --distractors 0.3 --seed "$s" > /dev/null
  scripts/estimate_loo.sh "$DATA" "$dir/dets_$s.json" "$dir/colour_$s.csv" -q --seed "$s" "$@"
  ./build/mcpose estimate --dataset "$DATA" --detections "$dir/dets_$s.json" --out "$dir/depth_$s.csv" -q --seed "$s" \
    --appearance off "$@"
  for run in colour depth; do
    ./build/mcpose eval --dataset "$DATA" --results "$dir/${run}_$s.csv" --json "$dir/${run}_$s.eval.json" > /dev/null
    evals+=("$run:$dir/${run}_$s.eval.json")
  done
done
/usr/bin/python3 - "${evals[@]}" <<'PY'
import json, sys
runs = {}
for arg in sys.argv[1:]:
    run, path = arg.split(":", 1)
    runs.setdefault(run, []).append(json.load(open(path)))
for i, (c, d) in enumerate(zip(runs["colour"], runs["depth"])):
    print(f"seed run {i}: with colour ADD(-S) < 4 cm {100 * c['overall']['add_s_lt_4cm']:.1f} %, "
          f"ADD-S < 4 cm {100 * c['overall']['adds_lt_4cm']:.1f} %; depth only {100 * d['overall']['add_s_lt_4cm']:.1f} %, "
          f"{100 * d['overall']['adds_lt_4cm']:.1f} %")
def mean(docs, key, obj=None):
    vals = [(d["overall"] if obj is None else next(o for o in d["per_object"] if o["obj_id"] == obj))[key] for d in docs]
    return 100 * sum(vals) / len(vals)
n = len(runs["colour"])
print(f"\nMean over {n} seeds (shares in %):")
print(f"{'object':24} {'inst':>4} | {'ADD(-S)<4 colour':>16} {'depth':>7} | {'ADD-S<4 colour':>14} {'depth':>7}")
for o in runs["colour"][0]["per_object"]:
    k = o["obj_id"]
    print(f"{o['name']:24} {o['instances']:4d} | {mean(runs['colour'], 'add_s_lt_4cm', k):16.1f} {mean(runs['depth'], 'add_s_lt_4cm', k):7.1f} | "
          f"{mean(runs['colour'], 'adds_lt_4cm', k):14.1f} {mean(runs['depth'], 'adds_lt_4cm', k):7.1f}")
c, d = runs["colour"], runs["depth"]
print(f"{'ALL':24} {c[0]['overall']['instances']:4d} | {mean(c, 'add_s_lt_4cm'):16.1f} {mean(d, 'add_s_lt_4cm'):7.1f} | "
      f"{mean(c, 'adds_lt_4cm'):14.1f} {mean(d, 'adds_lt_4cm'):7.1f}")
PY
