// The raster core's RTL (hw/rtl/raster_core.sv) as Verilator compiles it, for `--engine rtl`:
// each sample through the simulated design, clock by clock. Built where Verilator is found
// (MCPOSE_HAVE_RTL); the memories are those of a VGA image's every box (2^19 words) and of the
// meshes' every vertex (2^14), larger than the synthesized core's (docs/hardware.md).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "hw/raster_core.h"

namespace mcpose::hw {

inline constexpr int kRtlBoxWordBits = 19;    // the Verilated core's AW
inline constexpr int kRtlVertexIndexBits = 14;  // its VW
inline constexpr int kRtlMaxBoxSide = 2047;   // box_w, box_h: 11 bits

class RtlCore {
 public:
  RtlCore();
  ~RtlCore();
  RtlCore(const RtlCore&) = delete;
  RtlCore& operator=(const RtlCore&) = delete;

  // Writes the box's bounds into the core unless they are the ones it holds.
  void SetBounds(std::span<const DepthBounds> bounds);
  // One sample; zbuf (box-sized) receives the z-buffer as the core counts it.
  Counts Run(const Pose& pose, const Camera& camera, bool cull, std::span<const ModelVertex> model,
             std::span<const std::array<uint32_t, 3>> triangles, std::span<uint32_t> zbuf, CoreStats* stats);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<DepthBounds> loaded_;
};

}  // namespace mcpose::hw
