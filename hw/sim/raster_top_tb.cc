// Verilator testbench of hw/rtl/raster_top.sv (20 raster cores in lockstep, the depth and object
// vertex distributors, the weight merger) on the real workload `mcpose-tools hw-workload`
// writes: each object's bounds written once to every core, its samples in batches of 20, every
// core's counts compared with the C++ model's and every weight (and their sum) with
// hw::MergedWeight of the model's counts. Prints per object the clocks of the whole iteration (bounds, then every
// batch) and its time at 200 MHz; exits 1 on a mismatch.
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
    // The depth distributor: each word once, to every core.
    for (size_t i = 0; i < o.bounds.size(); ++i) {
      t.top.bnd_we = 1;
      t.top.bnd_cores = (1u << kCores) - 1;
      t.top.bnd_addr = static_cast<uint32_t>(i);
      t.top.bnd_lo = o.bounds[i].lo;
      t.top.bnd_hi = o.bounds[i].hi;
      t.Tick();
    }
    t.top.bnd_we = 0;
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
    t.top.cam_cx = static_cast<uint32_t>(o.camera.cx);
    t.top.cam_cy = static_cast<uint32_t>(o.camera.cy);
    t.top.cam_z_near = static_cast<uint32_t>(o.camera.z_near);
    t.top.box_w = static_cast<uint32_t>(o.camera.width);
    t.top.box_h = static_cast<uint32_t>(o.camera.height);
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
