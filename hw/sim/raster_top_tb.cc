// Verilator testbench of hw/rtl/raster_top.sv (20 raster cores, the depth and object vertex
// distributors, the weight merger) on the real workload `mcpose-tools hw-workload` writes: each
// object's depth read once by the depth distributor, which writes its bounds to every core; its
// samples in batches of 20; every core's counts compared with the C++ model's, and every weight
// (and their sum) with hw::MergedWeight of the model's counts. Prints per object the clocks of the
// whole iteration (the depth's distribution, then every batch) and its time at 200 MHz; exits 1
// on a mismatch.
// Usage: raster_top_tb FILE
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "Vraster_top.h"
#include "verilated.h"
#include "hw/rtl_driver.h"
#include "workload.h"

namespace {

using mcpose::hw::Counts;
using mcpose::hw::rtl::SetBits;

constexpr int kCores = 20;  // the top's CORES
constexpr double kClockHz = 200e6;

struct Top {
  Vraster_top top;
  uint64_t cycles = 0;
  Top() {
    top.rst = 1;
    Tick();
    Tick();
    top.rst = 0;
  }
  void Tick() {
    top.clk = 0;
    top.eval();
    top.clk = 1;
    top.eval();
    ++cycles;
  }
};

uint32_t Word(const VlWide<20>& w, int c) { return w[c]; }

}  // namespace

int main(int argc, char** argv) {
  Verilated::commandArgs(argc, argv);
  if (argc != 2) {
    std::fprintf(stderr, "usage: raster_top_tb WORKLOAD_FILE\n");
    return 2;
  }
  const auto objects = mcpose::hw::sim::ReadWorkload(argv[1], size_t{1} << 13);
  Top t;
  int total = 0, mismatches = 0;
  for (const auto& o : objects) {
    const uint64_t start = t.cycles;
    // Every core's box is the object's: the depth distributor reads it once for all of them.
    for (int c = 0; c < kCores; ++c) {
      SetBits(t.top.box_x0, 11 * c, 11, 0);
      SetBits(t.top.box_y0, 11 * c, 11, 0);
      SetBits(t.top.box_w, 11 * c, 11, static_cast<uint64_t>(o.camera.width));
      SetBits(t.top.box_h, 11 * c, 11, static_cast<uint64_t>(o.camera.height));
      SetBits(t.top.cam_cx, 32 * c, 32, static_cast<uint32_t>(o.camera.cx));
      SetBits(t.top.cam_cy, 32 * c, 32, static_cast<uint32_t>(o.camera.cy));
    }
    t.top.eps = static_cast<uint32_t>(o.eps);
    t.top.dist_start = 1;
    t.Tick();
    t.top.dist_start = 0;
    for (int y = 0; y < o.camera.height; ++y)
      for (int x = 0; x < o.camera.width; ++x) {
        while (!t.top.d_ready) t.Tick();
        t.top.d_valid = 1;
        t.top.d_x = static_cast<uint32_t>(x);
        t.top.d_y = static_cast<uint32_t>(y);
        t.top.d_depth = static_cast<uint32_t>(o.depth[static_cast<size_t>(y * o.camera.width + x)]);
        t.Tick();
        t.top.d_valid = 0;
      }
    while (!t.top.d_ready) t.Tick();
    t.Tick();  // the last pixel's write
    int32_t observed = 0;  // N_b: the words with an observed depth
    for (const auto& b : o.bounds) observed += b.lo != 0;
    t.top.coef_a = o.weight.a;
    t.top.coef_b = o.weight.b;
    t.top.coef_c = o.weight.c;
    t.top.score = o.weight.score;
    t.top.occlusion_aware = o.weight.occlusion_aware;
    t.top.sum_clear = 1;
    t.Tick();
    t.top.sum_clear = 0;
    uint64_t want_sum = 0;
    t.top.cam_fx = static_cast<uint32_t>(o.camera.fx);
    t.top.cam_fy = static_cast<uint32_t>(o.camera.fy);
    t.top.cam_z_near = static_cast<uint32_t>(o.camera.z_near);
    t.top.cull = o.cull;
    int object_mismatches = 0;
    std::vector<uint64_t> batch_cycles;
    for (size_t first = 0; first < o.samples.size(); first += kCores) {
      const int n = static_cast<int>(std::min<size_t>(kCores, o.samples.size() - first));
      uint32_t active = 0;
      for (int c = 0; c < n; ++c) {
        const auto& pose = o.samples[first + static_cast<size_t>(c)].pose;
        for (int i = 0; i < 9; ++i)
          SetBits(t.top.pose_r, 162 * c + 18 * i, 18, static_cast<uint64_t>(static_cast<int64_t>(pose.R[static_cast<size_t>(i)])));
        for (int i = 0; i < 3; ++i) SetBits(t.top.pose_t, 96 * c + 32 * i, 32, static_cast<uint32_t>(pose.t[static_cast<size_t>(i)]));
        active |= 1u << c;
      }
      const uint64_t batch_start = t.cycles;
      t.top.active = active;
      t.top.start = 1;
      t.Tick();
      t.top.start = 0;
      // The object vertex distributor: the mesh once, to every core of the batch.
      auto push = [&](int kind, uint64_t data) {
        while (!t.top.in_ready) t.Tick();
        t.top.in_valid = 1;
        t.top.in_kind = static_cast<uint32_t>(kind);
        t.top.in_data = data;
        t.Tick();
        t.top.in_valid = 0;
      };
      for (const auto& v : o.model) push(mcpose::hw::rtl::kItemVertex, mcpose::hw::rtl::VertexItem(v));
      for (const auto& tri : o.triangles) push(mcpose::hw::rtl::kItemTriangle, mcpose::hw::rtl::TriangleItem(tri, mcpose::hw::sim::kVertexIndexBits));
      push(mcpose::hw::rtl::kItemEnd, 0);
      std::vector<int64_t> weights(static_cast<size_t>(kCores), -1);
      while (!t.top.done) {
        t.Tick();
        if (t.top.w_valid && t.top.w_core < static_cast<uint32_t>(kCores)) weights[t.top.w_core] = t.top.w_data;
      }
      batch_cycles.push_back(t.cycles - batch_start);
      for (int c = 0; c < n; ++c) {
        const Counts got{static_cast<int32_t>(Word(t.top.inliers, c)), static_cast<int32_t>(Word(t.top.rendered, c)),
                         static_cast<int32_t>(Word(t.top.occluded, c))};
        const Counts& want = o.samples[first + static_cast<size_t>(c)].counts;
        const uint32_t want_weight = mcpose::hw::MergedWeight(want, observed, o.weight);
        want_sum += want_weight;
        if (weights[static_cast<size_t>(c)] != int64_t{want_weight} && ++object_mismatches <= 3)
          std::printf("%s sample %zu: rtl weight %lld, model %u\n", o.name.c_str(), first + static_cast<size_t>(c),
                      static_cast<long long>(weights[static_cast<size_t>(c)]), want_weight);
        if (!(got == want) && ++object_mismatches <= 3)
          std::printf("%s sample %zu: rtl N %d N_r %d occluded %d, model N %d N_r %d occluded %d\n", o.name.c_str(),
                      first + static_cast<size_t>(c), got.inliers, got.rendered, got.occluded, want.inliers,
                      want.rendered, want.occluded);
      }
    }
    if (t.top.w_sum != want_sum && ++object_mismatches <= 3)
      std::printf("%s: rtl weight sum %llu, model %llu\n", o.name.c_str(), static_cast<unsigned long long>(t.top.w_sum),
                  static_cast<unsigned long long>(want_sum));
    const uint64_t iteration = t.cycles - start;
    std::sort(batch_cycles.begin(), batch_cycles.end());
    std::printf("%-22s %4zu samples in %zu batches of %d cores, %d mismatches; clocks per batch (median %llu, max "
                "%llu); the iteration %llu clocks: %.2f ms at %.0f MHz\n",
                o.name.c_str(), o.samples.size(), batch_cycles.size(), kCores, object_mismatches,
                static_cast<unsigned long long>(batch_cycles[batch_cycles.size() / 2]),
                static_cast<unsigned long long>(batch_cycles.back()), static_cast<unsigned long long>(iteration),
                1e3 * static_cast<double>(iteration) / kClockHz, kClockHz / 1e6);
    total += static_cast<int>(o.samples.size());
    mismatches += object_mismatches;
  }
  std::printf("%d samples, %d mismatches\n", total, mismatches);
  return mismatches == 0 ? 0 : 1;
}
