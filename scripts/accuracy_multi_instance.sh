#!/usr/bin/env bash
# Several instances of one class: `mcpose synth --copies 3` makes scenes (seed S, 20 frames by
# default; out/multi_instance/set_S_F, made once) in which one object of the 21 appears three times
# side by side, some copies touching, with boxes from the truth (jitter 0.1, no distractors).
# The estimator runs with default options, depth only and with the textured models
# ($DATA/ycbv_textured/models or $MODELS); as a control, each box is also estimated alone (one
# box an image per run, --max-instances 1, depth only). Prints per scene the copied object and
# each instance's ADD-S, then the scenes whose three instances are all within 2 cm ADD-S.
# Usage: scripts/accuracy_multi_instance.sh [SEED] [FRAMES] [mcpose estimate options for every run]
# Needs build/mcpose (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
SEED=${1:-0}
FRAMES=${2:-20}
[ $# -gt 0 ] && shift
[ $# -gt 0 ] && shift
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}"
MODELS=${MODELS:-$DATA/ycbv_textured/models}
dir=${MULTI_INSTANCE_DIR:-out/multi_instance}
set_dir="$dir/set_${SEED}_$FRAMES"
mkdir -p "$dir"
[ -d "$set_dir" ] || ./build/mcpose synth -q --models "$MODELS" --out "$set_dir" --frames "$FRAMES" --seed "$SEED" \
  --copies 3 --objects 3 3 --jitter 0.1 --distractors 0
run() {  # NAME DETECTIONS [options]
  local name=$1 dets=$2
  shift 2
  ./build/mcpose estimate -q --dataset "$set_dir" --detections "$dets" --out "$dir/${name}_$SEED.csv" --seed "$SEED" "$@"
}
run depth "$set_dir/detections.json" --appearance off "$@"
run colour "$set_dir/detections.json" --models "$MODELS" "$@"
# The control: the k-th box of each image alone.
/usr/bin/python3 - "$set_dir/detections.json" "$dir/alone_$SEED" <<'PY'
import json, sys
boxes, stem = json.load(open(sys.argv[1])), sys.argv[2]
by_image = {}
for b in boxes:
    by_image.setdefault((b["scene_id"], b["image_id"]), []).append(b)
for k in range(max(len(v) for v in by_image.values())):
    json.dump([v[k] for v in by_image.values() if len(v) > k], open(f"{stem}_{k}.json", "w"))
PY
alone=()
for dets in "$dir/alone_${SEED}"_[0-9].json; do
  k=${dets%.json}
  k=${k##*_}
  run "alone${k}" "$dets" --appearance off --max-instances 1 "$@"
  alone+=("$dir/alone${k}_$SEED.csv")
done
{ head -n 1 "${alone[0]}"; for f in "${alone[@]}"; do tail -n +2 "$f"; done; } > "$dir/alone_$SEED.csv"
for name in depth colour alone; do
  ./build/mcpose eval --dataset "$set_dir" --results "$dir/${name}_$SEED.csv" --json "$dir/${name}_$SEED.eval.json" > /dev/null
done
/usr/bin/python3 - "$dir" "$SEED" "$set_dir" <<'PY'
import csv, json, sys
d, seed, set_dir = sys.argv[1:]
runs = ("depth", "colour", "alone")
ev = {r: json.load(open(f"{d}/{r}_{seed}.eval.json")) for r in runs}
names = {o["obj_id"]: o["name"] for o in ev["depth"]["per_object"]}
rows = {r: {} for r in runs}
for r in runs:
    for row in csv.DictReader(open(f"{d}/{r}_{seed}.csv")):
        rows[r].setdefault(int(row["im_id"]), 0)
        rows[r][int(row["im_id"])] += 1

def scenes(run):
    out = {}
    for i in ev[run]["instances"]:
        e = i["adds_m"] if i.get("has_result") and i["adds_m"] is not None else float("inf")
        out.setdefault(i["im_id"], (i["obj_id"], []))[1].append(e)
    return out

s = {r: scenes(r) for r in runs}
print(f"Scenes of three instances of one object, seed {seed} ({set_dir}); ADD-S of each instance in mm; rows written")
print(f"{'image':>5} {'object':24} | {'depth':>20} {'rows':>4} | {'colour':>20} {'rows':>4} | {'each box alone':>20}")
fmt = lambda es: " ".join(f"{1000 * e:6.1f}" if e != float("inf") else "     -" for e in es)
for im in sorted(s["depth"]):
    obj = s["depth"][im][0]
    print(f"{im:5d} {names.get(obj, obj):24} | {fmt(s['depth'][im][1]):>20} {rows['depth'].get(im, 0):4d} | "
          f"{fmt(s['colour'][im][1]):>20} {rows['colour'].get(im, 0):4d} | {fmt(s['alone'][im][1]):>20}")
for r, label in (("depth", "depth only"), ("colour", "textured"), ("alone", "each box alone, depth only")):
    three = [im for im, (_, es) in s[r].items() if len(es) == 3]
    ok = sum(all(e < 0.02 for e in s[r][im][1]) for im in three)
    inst = [e for im in three for e in s[r][im][1]]
    print(f"{label:28}: all three within 2 cm ADD-S in {ok} of {len(three)} scenes "
          f"({100 * ok / max(1, len(three)):.0f} %); instances within 2 cm: "
          f"{sum(e < 0.02 for e in inst)} of {len(inst)}")
PY
