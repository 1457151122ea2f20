#!/usr/bin/env bash
# Leave-one-video-out estimation with colour. For each real video V of a YCB-Video dataset, every
# object's appearance is captured (mcpose capture-appearance) from the real frames of all other
# videos and the synthetic frames, and V's detections are estimated with those models; models
# with colour of their own keep it (CAPTURE_OPTIONS=--replace-own-colour captures them too). No
# object's appearance comes from the video it is evaluated on; an object no other frame shows
# keeps depth only. The videos' results are merged into one results CSV (and one detail JSON).
# LOO_SYNTHETIC=0 leaves the synthetic frames out of the capture; LOO_KEEP_MODELS=1 uses models
# already captured (by a run with the same settings) instead of capturing again.
# Usage: scripts/estimate_loo.sh DATASET DETECTIONS OUT_CSV [--out-json FILE] [mcpose estimate options]
# Captured models go to $APPEARANCE_DIR/not_VVVV/ (default out/appearance; scripts/capture_loo.sh).
# Needs build/mcpose.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 3 ]; then sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; fi
DATASET=$1 DETECTIONS=$2 OUT=$3
shift 3
JSON=""
if [ "${1:-}" = "--out-json" ]; then JSON=$2; shift 2; fi
[ -d "$DATASET/data" ] || { echo "estimate_loo: $DATASET is not a YCB-Video dataset (no data/)" >&2; exit 1; }
work=${APPEARANCE_DIR:-out/appearance}
mkdir -p "$work"
videos=$(cd "$DATASET/data" && ls -d [0-9][0-9][0-9][0-9] | sort)
parts=()
jsons=()
for v in $videos; do
  scene=$((10#$v))
  [ "${LOO_KEEP_MODELS:-0}" = 1 ] && [ -d "$work/not_$v" ] || scripts/capture_loo.sh "$DATASET" "$v"
  # This video's detections (skipped when it has none).
  /usr/bin/python3 -c "import json, sys; sys.exit(0 if any(d['scene_id'] == $scene for d in json.load(open(sys.argv[1]))) else 1)" \
    "$DETECTIONS" || continue
  part="$work/results_$v.csv"
  extra=()
  [ -n "$JSON" ] && extra=(--out-json "$work/results_$v.json") && jsons+=("$work/results_$v.json")
  ./build/mcpose estimate --dataset "$DATASET" --models "$work/not_$v" --detections "$DETECTIONS" --scene "$scene" \
    --out "$part" "${extra[@]}" "$@"
  parts+=("$part")
done
# One CSV: the header once, then each video's rows (each sorted; the videos in order).
{ head -n 1 "${parts[0]}"; for p in "${parts[@]}"; do tail -n +2 "$p"; done; } > "$OUT.tmp" && mv "$OUT.tmp" "$OUT"
if [ -n "$JSON" ]; then
  /usr/bin/python3 - "$JSON" "${jsons[@]}" <<'PY'
import json, os, sys
out, parts = sys.argv[1], sys.argv[2:]
docs = [json.load(open(p)) for p in parts]
merged = dict(docs[0])
merged["models"] = [d["models"] for d in docs]
merged["objects"] = [o for d in docs for o in d["objects"]]
with open(out + ".tmp", "w") as f:
    json.dump(merged, f, indent=1)
os.replace(out + ".tmp", out)
PY
fi
