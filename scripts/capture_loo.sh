#!/usr/bin/env bash
# Captures, for real video V of a YCB-Video dataset, every object's appearance from the real
# frames of all other videos and the synthetic frames (LOO_SYNTHETIC=0 leaves those out), so that
# no colour used on V comes from V. Writes the models folder $APPEARANCE_DIR/not_V (V as 4 digits;
# default out/appearance) and the capture's report beside it; CAPTURE_OPTIONS passes options to
# capture-appearance.
# Usage: scripts/capture_loo.sh DATASET VIDEO
# Needs build/mcpose (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ne 2 ]; then sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; fi
DATASET=$1
v=$(printf %04d "$((10#$2))")
[ -d "$DATASET/data/$v" ] || { echo "capture_loo: $DATASET has no video $v (no data/$v)" >&2; exit 1; }
work=${APPEARANCE_DIR:-out/appearance}
mkdir -p "$work"
list="$work/frames_not_$v.txt"
: > "$list"
for w in $(cd "$DATASET/data" && ls -d [0-9][0-9][0-9][0-9] | sort); do
  [ "$w" = "$v" ] && continue
  for f in "$DATASET/data/$w"/*-meta.mat; do echo "$w/$(basename "$f" -meta.mat)" >> "$list"; done
done
if [ -d "$DATASET/data_syn" ] && [ "${LOO_SYNTHETIC:-1}" != 0 ]; then
  for f in "$DATASET/data_syn"/*-meta.mat; do echo "data_syn/$(basename "$f" -meta.mat)" >> "$list"; done
fi
rm -rf "$work/not_$v"
# shellcheck disable=SC2086  # CAPTURE_OPTIONS is a list of options
./build/mcpose capture-appearance --dataset "$DATASET" --frames "$list" --out "$work/not_$v" ${CAPTURE_OPTIONS:-} \
  > "$work/capture_not_$v.txt"
