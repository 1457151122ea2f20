#!/usr/bin/env bash
# The paper's hardware (hw/rtl/, docs/hardware.md): lint, simulation against the C++ model, and
# synthesis for the ZCU102's UltraScale+ part.
# Usage:
#   scripts/hw.sh lint                 Verilator's lint (-Wall) of the RTL: the core and the top
#   scripts/hw.sh sim [SAMPLES [SEED]] Verilates the raster core with its testbench (hw/sim/) into
#                                      build-hw/ and runs SAMPLES random samples (default 2000, seed 1)
#                                      through the RTL and the C++ model (src/hw/): prints
#                                      "N samples, M mismatches, cycles per sample (median, max)";
#                                      then the depth distributor's testbench on SAMPLES / 10 random
#                                      batches of 20 overlapping boxes against the model's bounds;
#                                      fails on a mismatch
#   scripts/hw.sh workload [FILE]      The real workload: `mcpose-tools hw-workload` (the initial
#                                      hypotheses of one `mcpose bench` iteration of the paper's
#                                      five objects, HW_SAMPLES of them (default 620), with the C++
#                                      model's counts) through the 20-core top (hw/rtl/raster_top.sv):
#                                      per object, mismatches and the iteration's clocks and time
#                                      at 200 MHz ($MCPOSE_TOOLS: the mcpose-tools to use)
#   scripts/hw.sh synth                Yosys synth_xilinx -family xcup of one raster core and of the
#                                      20-core top (8192-pixel box memories, as simulated): LUTs,
#                                      flip-flops, DSP48E2, block RAM beside the paper's; the logs in
#                                      build-hw/synth_*.log. No vendor tool: no timing, no power.
# Verilator and Yosys are Debian packages (scripts/install_deps.sh installs them). Outputs go to
# build-hw/ (or $MCPOSE_HW_BUILD).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${MCPOSE_HW_BUILD:-build-hw}
RTL=(hw/rtl/udiv.sv hw/rtl/sfloordiv.sv hw/rtl/raster_core.sv)
TOP=(hw/rtl/depth_distributor.sv hw/rtl/weight_merger.sv hw/rtl/raster_top.sv)
need() { command -v "$1" > /dev/null || { echo "hw.sh: $1 is not installed (scripts/install_deps.sh)" >&2; exit 1; }; }
case "${1:-}" in
  lint)
    need verilator
    verilator --lint-only -Wall --top-module raster_core "${RTL[@]}"
    verilator --lint-only -Wall --top-module raster_top "${RTL[@]}" "${TOP[@]}"
    echo "hw.sh: lint clean (${RTL[*]} ${TOP[*]})"
    ;;
  sim)
    need verilator
    mkdir -p "$OUT"
    verilator --cc --exe --build -j 2 -O2 --top-module raster_core \
      --Mdir "$OUT/raster_core" -o raster_core_tb "${RTL[@]}" "$(pwd)/hw/sim/raster_core_tb.cc" \
      "$(pwd)/src/hw/raster_core.cc" \
      -CFLAGS "-std=c++20 -O2 -I$(pwd)/src -I/usr/include/eigen3" > "$OUT"/verilate.log 2>&1 ||
      { cat "$OUT"/verilate.log >&2; exit 1; }
    "$OUT"/raster_core/raster_core_tb "${2:-2000}" "${3:-1}"
    verilator --cc --exe --build -j 2 -O2 --top-module depth_distributor \
      --Mdir "$OUT/depth_distributor" -o depth_distributor_tb hw/rtl/udiv.sv hw/rtl/depth_distributor.sv \
      "$(pwd)/hw/sim/depth_distributor_tb.cc" "$(pwd)/src/hw/raster_core.cc" \
      -CFLAGS "-std=c++20 -O2 -I$(pwd)/src -I/usr/include/eigen3" > "$OUT"/verilate_dist.log 2>&1 ||
      { cat "$OUT"/verilate_dist.log >&2; exit 1; }
    "$OUT"/depth_distributor/depth_distributor_tb "$(( (${2:-2000} + 9) / 10 ))" "${3:-1}"
    ;;
  workload)
    need verilator
    mkdir -p "$OUT"
    file=${2:-$OUT/workload.txt}
    if [ -z "${2:-}" ]; then
      DATA="${MCPOSE_DATA_DIR:-$(cd .. && pwd)/shared/data}"
      tools=${MCPOSE_TOOLS:-build/mcpose-tools}
      [ -x "$tools" ] || { echo "hw.sh: $tools is missing (scripts/build.sh)" >&2; exit 1; }
      "$tools" hw-workload --dataset "$DATA/ycbv" --out "$file" --samples "${HW_SAMPLES:-620}"
    fi
    verilator --cc --exe --build -j 2 -O2 --top-module raster_top \
      --Mdir "$OUT/raster_top" -o raster_top_tb "${RTL[@]}" "${TOP[@]}" "$(pwd)/hw/sim/raster_top_tb.cc" \
      "$(pwd)/src/hw/weight_merger.cc" "$(pwd)/src/hw/raster_core.cc" \
      -CFLAGS "-std=c++20 -O2 -I$(pwd)/src -I/usr/include/eigen3" > "$OUT"/verilate_top.log 2>&1 ||
      { cat "$OUT"/verilate_top.log >&2; exit 1; }
    "$OUT"/raster_top/raster_top_tb "$file"
    ;;
  synth)
    need yosys
    mkdir -p "$OUT"
    # Hierarchy kept (synth_xilinx does not flatten): the top's cores are one module, counted
    # once per instance in the totals after "design hierarchy".
    for top in raster_core raster_top; do
      yosys -q -q -l "$OUT/synth_$top.log" -p "read_verilog -sv ${RTL[*]} ${TOP[*]};
        synth_xilinx -family xcup -top $top; tee -o $OUT/synth_$top.txt stat" > /dev/null
      awk -v top="$top" '/design hierarchy/ { total = 1 } !total { next }
           $1 ~ /^LUT[1-6]$/ { lut += $2 } $1 ~ /^FD/ { ff += $2 } $1 == "DSP48E2" { dsp += $2 }
           $1 == "RAMB36E2" { b36 += $2 } $1 == "RAMB18E2" { b18 += $2 } $1 ~ /^RAM(32|64)/ { lutram += $2 }
           END { printf "%-11s (yosys synth_xilinx -family xcup): %d LUT, %d FF, %d DSP48E2, %d RAMB36E2, %d RAMB18E2 (%.1f BRAM36), %d LUTRAM cells\n",
                 top, lut, ff, dsp, b36, b18, b36 + b18 / 2, lutram }' "$OUT/synth_$top.txt"
    done
    echo "the paper's 20 raster cores: 146000 LUT, 172780 FF, 920 DSP48E2, 480 BRAM36; the XCZU9EG: 274080 LUT, 548160 FF, 2520 DSP48E2, 912 BRAM36"
    ;;
  *)
    sed -n '2,/^set -euo/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//' >&2
    exit 2
    ;;
esac
