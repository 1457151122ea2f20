// Drives a Verilated hw/rtl/raster_core.sv (any AW, VW) through one sample, as the object vertex
// and depth distributors would: the header-only half of `--engine rtl` (hw/rtl_core.cc) and of
// the testbenches (hw/sim/). Templated on the Verilated model so that it needs no Verilator
// header itself.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "hw/raster_core.h"

namespace mcpose::hw::rtl {

// The core's items (hw/README.md).
inline constexpr int kItemVertex = 0, kItemTriangle = 1, kItemEnd = 2;
inline uint64_t VertexItem(const ModelVertex& v) {
  return uint64_t{static_cast<uint16_t>(v[0])} | uint64_t{static_cast<uint16_t>(v[1])} << 16 |
         uint64_t{static_cast<uint16_t>(v[2])} << 32;
}
inline uint64_t TriangleItem(const std::array<uint32_t, 3>& t, int vertex_index_bits) {
  return uint64_t{t[0]} | uint64_t{t[1]} << vertex_index_bits | uint64_t{t[2]} << (2 * vertex_index_bits);
}

// Bits [bit, bit + width) of a Verilated wide port.
template <typename Wide>
void SetBits(Wide& w, int bit, int width, uint64_t value) {
  for (int i = 0; i < width; ++i) {
    const int b = bit + i;
    const uint32_t mask = 1u << (b % 32);
    if ((value >> i) & 1) w[b / 32] |= mask; else w[b / 32] &= ~mask;
  }
}

template <typename Model>
class CoreDriver {
 public:
  // `core` with VW vertex index bits; resets it.
  CoreDriver(Model* core, int vertex_index_bits) : core_(*core), vw_(vertex_index_bits) {
    core_.rst = 1;
    Tick();
    Tick();
    core_.rst = 0;
  }
  uint64_t cycles() const { return cycles_; }

  // The depth distributor's writes of one box (row-major).
  void LoadBounds(std::span<const DepthBounds> bounds) {
    for (size_t i = 0; i < bounds.size(); ++i) {
      core_.bnd_we = 1;
      core_.bnd_addr = static_cast<uint32_t>(i);
      core_.bnd_lo = bounds[i].lo;
      core_.bnd_hi = bounds[i].hi;
      Tick();
    }
    core_.bnd_we = 0;
  }

  // One sample: start, every vertex, every triangle, the end, done. The z-buffer words the count
  // reads land in zbuf (box-sized; IZ, 0 = nothing drawn). Returns the clocks from start to done.
  uint64_t Run(const Pose& pose, const Camera& camera, bool cull, std::span<const ModelVertex> model,
               std::span<const std::array<uint32_t, 3>> triangles, std::span<uint32_t> zbuf) {
    for (int i = 0; i < 9; ++i)
      SetBits(core_.pose_r, 18 * i, 18, static_cast<uint64_t>(static_cast<int64_t>(pose.R[static_cast<size_t>(i)])));
    for (int i = 0; i < 3; ++i) SetBits(core_.pose_t, 32 * i, 32, static_cast<uint32_t>(pose.t[static_cast<size_t>(i)]));
    core_.cam_fx = static_cast<uint32_t>(camera.fx);
    core_.cam_fy = static_cast<uint32_t>(camera.fy);
    core_.cam_cx = static_cast<uint32_t>(camera.cx);
    core_.cam_cy = static_cast<uint32_t>(camera.cy);
    core_.cam_z_near = static_cast<uint32_t>(camera.z_near);
    core_.box_w = static_cast<uint32_t>(camera.width);
    core_.box_h = static_cast<uint32_t>(camera.height);
    core_.cull = cull;
    zbuf_ = zbuf;
    const uint64_t start = cycles_;
    core_.start = 1;
    Step();
    core_.start = 0;
    for (const ModelVertex& v : model) Push(kItemVertex, VertexItem(v));
    for (const auto& t : triangles) Push(kItemTriangle, TriangleItem(t, vw_));
    Push(kItemEnd, 0);
    while (!core_.done) Step();
    zbuf_ = {};
    return cycles_ - start;
  }
  Counts counts() const {
    return {static_cast<int32_t>(core_.inliers), static_cast<int32_t>(core_.rendered),
            static_cast<int32_t>(core_.occluded)};
  }
  int64_t drawn() const { return core_.drawn; }
  int64_t fragments() const { return core_.fragments; }

 private:
  void Tick() {
    core_.clk = 0;
    core_.eval();
    core_.clk = 1;
    core_.eval();
    ++cycles_;
  }
  // A clock, keeping the z-buffer word the count reads.
  void Step() {
    Tick();
    if (core_.cnt_valid && core_.cnt_addr < zbuf_.size()) zbuf_[core_.cnt_addr] = core_.cnt_z;
  }
  void Push(int kind, uint64_t data) {
    while (!core_.in_ready) Step();
    core_.in_valid = 1;
    core_.in_kind = static_cast<uint32_t>(kind);
    core_.in_data = data;
    Step();
    core_.in_valid = 0;
  }

  Model& core_;
  int vw_;
  uint64_t cycles_ = 0;
  std::span<uint32_t> zbuf_;
};

}  // namespace mcpose::hw::rtl
