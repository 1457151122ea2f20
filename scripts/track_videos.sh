#!/usr/bin/env bash
# Tracking against the single-frame estimator on the real videos: 0049 frames 1-10 and 0000,
# 0001, 0002 frames 1-5. Both start from the main job's detector-like boxes (out/detections.json,
# made as scripts/run_main.sh makes it when missing) and use leave-one-video-out colour models
# (scripts/capture_loo.sh; captured once into out/appearance/not_VVVV, delete it to capture
# again). Prints per frame and object the ADD(-S) and ADD-S of both and the tracker's time and
# state, then per video and overall: the median time of a tracked (frame, object) and ADD-S /
# ADD(-S) < 2 cm on the frames after each object's first. Files: out/track/.
# Usage: scripts/track_videos.sh [mcpose track options: the tracker's own, e.g. --track-iterations]
# Needs build/mcpose (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}/ycbv"
dir=out/track
mkdir -p "$dir"
if [ ! -f out/detections.json ]; then
  ./build/mcpose detections-from-gt --dataset "$DATA" --out out/detections.json --jitter 0.1 --distractors 0.3 --seed 0
fi
args=()
for vf in 49:1-10 0:1-5 1:1-5 2:1-5; do
  video=${vf%%:*} frames=${vf#*:}
  v=$(printf %04d "$video")
  [ -d "out/appearance/not_$v" ] || scripts/capture_loo.sh "$DATA" "$video"
  ./build/mcpose track -q --dataset "$DATA" --video "$video" --frames "$frames" --models "out/appearance/not_$v" \
    --detections out/detections.json --out "$dir/track_$v.csv" --out-json "$dir/track_$v.json" "$@"
  ./build/mcpose estimate -q --dataset "$DATA" --scene "$video" --models "out/appearance/not_$v" \
    --detections out/detections.json --out "$dir/single_$v.csv"
  for run in track single; do
    ./build/mcpose eval --dataset "$DATA" --results "$dir/${run}_$v.csv" --json "$dir/${run}_$v.eval.json" > /dev/null
  done
  args+=("$dir/track_$v.json" "$dir/track_$v.eval.json" "$dir/single_$v.eval.json")
done
/usr/bin/python3 - "${args[@]}" <<'PY'
import json, statistics, sys

def errors(path):
    return {(i["scene_id"], i["im_id"], i["obj_id"]): i for i in json.load(open(path))["instances"] if i["has_result"]}

print(f"{'video':>5} {'frame':>5} {'object':<24} {'state':<16} {'ms':>6}   tracked ADD(-S) ADD-S mm   single ADD(-S) ADD-S mm")
all_ms, totals = [], {"n": 0, "t_adds": 0, "s_adds": 0, "t_add": 0, "s_add": 0}
summary = []
a = sys.argv[1:]
for k in range(0, len(a), 3):
    steps = json.load(open(a[k]))["steps"]
    tracked, single = errors(a[k + 1]), errors(a[k + 2])
    first, ms, n, t = {}, [], 0, {"t_adds": 0, "s_adds": 0, "t_add": 0, "s_add": 0}
    for s in steps:
        key = (s["scene_id"], s["im_id"], s["obj_id"])
        state = "lost, restarted" if s["lost"] and s["initialised"] else "lost" if s["lost"] else \
            "started" if s["initialised"] else "tracked"
        if not s["initialised"]:
            ms.append(s["ms"])
        te, se = tracked.get(key), single.get(key)
        fmt = lambda e: f"{1000 * e['add_or_adds_m']:8.1f} {1000 * e['adds_m']:6.1f}" if e else f"{'-':>8} {'-':>6}"
        print(f"{key[0]:5d} {key[1]:5d} {s['name']:<24} {state:<16} {s['ms']:6.1f}   {fmt(te):>22}   {fmt(se):>21}")
        later = first.setdefault(s["obj_id"], s["im_id"]) != s["im_id"]
        if later and te and se:
            n += 1
            t["t_adds"] += te["adds_m"] < 0.02; t["s_adds"] += se["adds_m"] < 0.02
            t["t_add"] += te["add_or_adds_m"] < 0.02; t["s_add"] += se["add_or_adds_m"] < 0.02
    all_ms += ms
    totals["n"] += n
    for x in t: totals[x] += t[x]
    summary.append((steps[0]["scene_id"], len(ms), statistics.median(ms) if ms else float("nan"), n, t))
print()
print(f"{'video':>5} {'tracked':>7} {'median ms':>9}  {'later':>5}  ADD-S<2cm track single  ADD(-S)<2cm track single")
pct = lambda x, n: 100.0 * x / n if n else float("nan")
for v, m, med, n, t in summary + [("all", len(all_ms), statistics.median(all_ms), totals["n"], totals)]:
    print(f"{v:>5} {m:7d} {med:9.1f}  {n:5d}  {pct(t['t_adds'], n):15.1f} {pct(t['s_adds'], n):6.1f}"
          f"  {pct(t['t_add'], n):17.1f} {pct(t['s_add'], n):6.1f}")
PY
