#!/usr/bin/env bash
# The synthetic stress set: `mcpose synth` makes a fixed set (100 frames of 3-7 of the 21
# objects at rest on a table, seed S; out/synth/set_S, made once), then the estimator with
# default options twice on its detector-like boxes: with colour (the textured models,
# $DATA/ycbv_textured/models or $MODELS) and depth only. Prints per object, over the instances at
# least 30 % visible: ADD-S < 2 cm depth only, ADD(-S) < 4 cm with colour (ADD-S for the symmetric
# set), the ADD-S AUC of both, how many answers beyond 2 cm are search failures and how many
# weight failures (mcpose-tools misses, colour run), and the median time per object.
# Usage: scripts/accuracy_synth.sh [SEED] [FRAMES] [mcpose estimate options for both runs]
# Needs build/mcpose and build/mcpose-tools (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
SEED=${1:-0}
FRAMES=${2:-100}
[ $# -gt 0 ] && shift
[ $# -gt 0 ] && shift
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}"
MODELS=${MODELS:-$DATA/ycbv_textured/models}
dir=${SYNTH_DIR:-out/synth}
set_dir="$dir/set_${SEED}_$FRAMES"
mkdir -p "$dir"
[ -d "$set_dir" ] || ./build/mcpose synth --models "$MODELS" --out "$set_dir" --frames "$FRAMES" --seed "$SEED"
for run in colour depth; do
  extra=(--models "$MODELS")
  [ $run = depth ] && extra=(--appearance off)
  ./build/mcpose estimate --dataset "$set_dir" --detections "$set_dir/detections.json" --out "$dir/${run}_$SEED.csv" \
    --out-json "$dir/${run}_$SEED.json" -q --seed "$SEED" "${extra[@]}" "$@"
  ./build/mcpose eval --dataset "$set_dir" --results "$dir/${run}_$SEED.csv" --json "$dir/${run}_$SEED.eval.json" > /dev/null
done
./build/mcpose-tools misses --dataset "$set_dir" --models "$MODELS" --detections "$set_dir/detections.json" \
  --results "$dir/colour_$SEED.csv" --min-adds-mm 20 --json "$dir/misses_$SEED.json" "$@" > /dev/null
/usr/bin/python3 - "$set_dir" "$dir" "$SEED" <<'PY'
import json, statistics, sys
set_dir, d, seed = sys.argv[1:]
info = json.load(open(f"{set_dir}/test/000000/scene_gt_info.json"))
vis = {(int(im), g): i["visib_fract"] for im, rows in info.items() for g, i in enumerate(rows)}
ev = {run: json.load(open(f"{d}/{run}_{seed}.eval.json")) for run in ("colour", "depth")}
names = {o["obj_id"]: o["name"] for o in ev["colour"]["per_object"]}
miss = json.load(open(f"{d}/misses_{seed}.json"))["misses"]
times = {}
for o in json.load(open(f"{d}/colour_{seed}.json"))["objects"]:
    times.setdefault(o["obj_id"], []).append(o["time_s"])

def auc(errs, m=0.1):
    below = [e for e in errs if e < m]
    return 100 * (len(below) - sum(below) / m) / len(errs) if errs else 0.0

def inst(run):
    return [i for i in ev[run]["instances"] if vis.get((i["im_id"], i["gt_index"]), 0) >= 0.3]

def err(i, k):
    return i[k] if i.get("has_result") and i[k] is not None else float("inf")

print(f"Synthetic set seed {seed} ({set_dir}): instances at least 30 % visible; % of them")
print(f"{'object':24} {'inst':>4} {'ADD-S<2 depth':>14} {'ADD(-S)<4 col':>14} {'AUC col':>8} {'AUC depth':>9}"
      f" {'search':>6} {'weight':>6} {'ms':>6}")
rows = {}
for run in ("colour", "depth"):
    for i in inst(run):
        rows.setdefault(i["obj_id"], {}).setdefault(run, []).append(i)
tot = {"n": 0, "d2": 0, "c4": 0, "ac": [], "ad": [], "s": 0, "w": 0}
for obj in sorted(rows):
    c, dd = rows[obj].get("colour", []), rows[obj].get("depth", [])
    n = len(c)
    d2 = sum(err(i, "adds_m") < 0.02 for i in dd)
    c4 = sum(err(i, "add_or_adds_m") < 0.04 for i in c)
    ac, ad = [err(i, "adds_m") for i in c], [err(i, "adds_m") for i in dd]
    s = sum(m["failure"] == "search" for m in miss if m["obj_id"] == obj)
    w = sum(m["failure"] == "weight" for m in miss if m["obj_id"] == obj)
    ms = 1000 * statistics.median(times[obj]) if obj in times else float("nan")
    print(f"{names[obj]:24} {n:4d} {100 * d2 / n:14.1f} {100 * c4 / n:14.1f} {auc(ac):8.1f} {auc(ad):9.1f} {s:6d} {w:6d} {ms:6.0f}")
    tot["n"] += n; tot["d2"] += d2; tot["c4"] += c4; tot["ac"] += ac; tot["ad"] += ad; tot["s"] += s; tot["w"] += w
all_ms = 1000 * statistics.median([t for v in times.values() for t in v])
n = tot["n"]
print(f"{'ALL':24} {n:4d} {100 * tot['d2'] / n:14.1f} {100 * tot['c4'] / n:14.1f} {auc(tot['ac']):8.1f} "
      f"{auc(tot['ad']):9.1f} {tot['s']:6d} {tot['w']:6d} {all_ms:6.0f}")
print("search/weight: answers beyond 2 cm ADD-S (colour run, every instance) whose truth, aligned to the depth,")
print("outweighs them (search) or not (weight); ms: median time per object of the colour run.")
PY
