#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ (clang, ASan + UBSan with float-cast-overflow) into
# build-fuzz/ and runs each for SECONDS (default 60), two at a time, from a seed corpus taken from the data
# folder. Fails on any crash, leak, timeout or sanitizer report; the input that caused it is
# kept in build-fuzz/artifacts/<target>/. Prints executions per target.
# Usage: scripts/fuzz.sh [SECONDS]     Data: ../shared/data beside the repository, or $MCPOSE_DATA_DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
SECONDS_EACH="${1:-60}"
DATA="${MCPOSE_DATA_DIR:-$(pwd)/../shared/data}"
Y="$DATA/ycbv"
B="$DATA/bop_ycbv_subset"
OUT=build-fuzz

cmake -S . -B "$OUT" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DMCPOSE_FUZZ=ON -DMCPOSE_BUILD_TESTS=OFF -DMCPOSE_BUILD_BENCHMARKS=OFF >/dev/null
ninja -C "$OUT" mcpose_fuzzers

# ---- Seeds: a few real files per reader, plus small hand-written ones --------------------
SEEDS="$OUT/seeds"
rm -rf "$SEEDS"
seed() {  # seed TARGET FILE...: copies the files that exist
  local target="$1"; shift
  mkdir -p "$SEEDS/$target"
  local f
  for f in "$@"; do [ -f "$f" ] && cp "$f" "$SEEDS/$target/$(echo "$f" | md5sum | cut -c1-12)-$(basename "$f")"; done
  return 0
}
text_seed() {  # text_seed TARGET NAME: stdin becomes a seed
  mkdir -p "$SEEDS/$1"
  cat > "$SEEDS/$1/$2"
}
seed png_depth "$Y/data/0049/000001-depth.png" "$Y/data_syn/000001-depth.png" "$B/test/000049/depth/000001.png"
seed png_colour "$Y/data/0049/000001-color.png" "$Y/data_syn/000001-color.png"
seed png_label "$Y/data/0049/000001-label.png" "$B/test/000049/mask_visib/000001_000000.png"
seed jpeg "$Y"/models/*/texture_map.jpg
# A 16 x 12 colour JPEG (4:2:0, quality 75), so the fuzzer also mutates a small one.
echo "/9j/4AAQSkZJRgABAQAAAQABAAD/2wBDAAgGBgcGBQgHBwcJCQgKDBQNDAsLDBkSEw8UHRofHh0aHBwgJC4nICIsIxwcKDcpLDAxNDQ0Hyc5PTgyPC4zNDL/2wBDAQkJCQwLDBgNDRgyIRwhMjIyMjIyMjIyMjIyMjIyMjIyMjIyMjIyMjIyMjIyMjIyMjIyMjIyMjIyMjIyMjIyMjL/wAARCAAMABADASIAAhEBAxEB/8QAHwAAAQUBAQEBAQEAAAAAAAAAAAECAwQFBgcICQoL/8QAtRAAAgEDAwIEAwUFBAQAAAF9AQIDAAQRBRIhMUEGE1FhByJxFDKBkaEII0KxwRVS0fAkM2JyggkKFhcYGRolJicoKSo0NTY3ODk6Q0RFRkdISUpTVFVWV1hZWmNkZWZnaGlqc3R1dnd4eXqDhIWGh4iJipKTlJWWl5iZmqKjpKWmp6ipqrKztLW2t7i5usLDxMXGx8jJytLT1NXW19jZ2uHi4+Tl5ufo6erx8vP09fb3+Pn6/8QAHwEAAwEBAQEBAQEBAQAAAAAAAAECAwQFBgcICQoL/8QAtREAAgECBAQDBAcFBAQAAQJ3AAECAxEEBSExBhJBUQdhcRMiMoEIFEKRobHBCSMzUvAVYnLRChYkNOEl8RcYGRomJygpKjU2Nzg5OkNERUZHSElKU1RVVldYWVpjZGVmZ2hpanN0dXZ3eHl6goOEhYaHiImKkpOUlZaXmJmaoqOkpaanqKmqsrO0tba3uLm6wsPExcbHyMnK0tPU1dbX2Nna4uPk5ebn6Onq8vP09fb3+Pn6/9oADAMBAAIRAxEAPwCO2SCzcwabFaI8c4KppNj9pk2EEgGWX904AIyVwcjoORS6hsM0q6gLcy2twJPL1a8a4kVX/u2keDGTuU4UkBe2ORq/2atz4V1nUry7u7lobCWb7M0uy3cxoWUNEm1cZUZwBn61geGdRn1fasaw6bC8XltHYwqvXOWDsGdW56hhjAxg03pvu/6+Wwrq2h//2Q==" |
  base64 -d | text_seed jpeg small.jpg
seed meta_mat "$Y/data/0049/000001-meta.mat" "$Y/data/0000/000001-meta.mat" "$Y/data_syn/000001-meta.mat"
seed obj "$Y/models/040_large_marker/textured_simple.obj"
printf 'v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nvt 0 0\nvn 0 0 1\nf 1/1/1 3/1/1 2/1/1\nf 1//1 2//1 4//1\nf -4 -1 -2\n' |
  text_seed obj tetra.obj
seed mtl "$Y"/models/*/textured_simple.obj.mtl
seed ply "$B/models/obj_000018.ply"
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 255 0 0\n100 0 0 0 255 0\n0 100 0 0 0 255\n0 0 100 9 9 9\n3 0 2 1\n3 0 1 3\n' |
  text_seed ply tetra_ascii.ply
seed points_xyz "$Y/models/040_large_marker/points.xyz"
printf '0.01 0.02 0.03\n-0.01 0 0.5\n' | text_seed points_xyz small.xyz
seed bop_models_info "$B/models/models_info.json"
seed bop19_models_info "$B/models/models_info.json"
seed bop19_targets "$B/test_targets_bop19.json"
seed bop_camera "$B/camera.json" "$B/camera_uw.json"
seed bop_scene_camera "$B/test/000049/scene_camera.json"
seed bop_scene_gt "$B/test/000049/scene_gt.json"
printf '[{"scene_id": 49, "image_id": 1, "category_id": 1, "score": 0.9, "bbox": [10, 20, 100, 80], "time": 0.5},\n {"scene_id": 0, "image_id": 2, "category_id": 21, "score": 0.1, "bbox": [0.5, 1.5, 2, 3]}]\n' |
  text_seed detections_json dets.json
printf 'scene_id,im_id,obj_id,score,R,t,time\n49,1,1,0.9,1 0 0 0 1 0 0 0 1,10.5 -3 800,0.25\n49,1,2,0.5,0 -1 0 1 0 0 0 0 1,0 0 1000,-1\n' |
  text_seed results_csv res.csv

# ---- Run each target for SECONDS_EACH seconds, two at a time (one a core) ------------------
run_target() {  # run_target TARGET: its log in $OUT/logs/, its exit status in $OUT/logs/TARGET.rc
  local target="$1" corpus="$OUT/corpus/$1" artifacts="$OUT/artifacts/$1/" rc=0
  mkdir -p "$corpus" "$artifacts" "$OUT/logs"
  "$OUT/fuzz/fuzz_$target" -max_total_time="$SECONDS_EACH" -timeout=25 -rss_limit_mb=2560 -max_len=1048576 \
    -print_final_stats=1 -artifact_prefix="$artifacts" "$corpus" "$SEEDS/$target" >"$OUT/logs/$target.log" 2>&1 || rc=$?
  echo "$rc" > "$OUT/logs/$target.rc"
}
targets=($(cat "$OUT/fuzz_targets.txt" | tr ';' ' '))
for ((i = 0; i < ${#targets[@]}; i += 2)); do
  echo "fuzz: ${targets[*]:i:2} for ${SECONDS_EACH}s"
  for target in "${targets[@]:i:2}"; do run_target "$target" & done
  wait
done
failed=()
summary=()
for target in "${targets[@]}"; do
  log="$OUT/logs/$target.log"
  rc=$(cat "$OUT/logs/$target.rc")
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  summary+=("$(printf '%-18s %10s execs  exit %d' "$target" "$execs" "$rc")")
  if [ "$rc" -ne 0 ] || grep -q -E 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:' "$log"; then
    failed+=("$target")
    echo "fuzz: $target FAILED, log $log:"
    tail -40 "$log"
  fi
done
echo "fuzz: executions per target (${SECONDS_EACH}s each)"
printf '  %s\n' "${summary[@]}"
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: FAILED: ${failed[*]} (inputs in $OUT/artifacts/)"
  exit 1
fi
echo "fuzz: no crash, leak or sanitizer report"
