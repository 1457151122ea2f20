// Verilator testbench of hw/rtl/raster_core.sv against the C++ model of the core
// (src/hw/raster_core.cc), every count (and, for random samples, every z-buffer word) compared
// bit for bit.
//   raster_core_tb [SAMPLES [SEED]]   random samples: a random triangle soup at a random pose in
//                                     front of a random box over random observed depth
//   raster_core_tb --workload FILE    the real workload `mcpose-tools hw-workload` writes: each
//                                     object's box, mesh and samples with the model's counts
// Prints "N samples, M mismatches, cycles per sample (median, max)" (per object for a
// workload, with the render + inlier time of a whole iteration on 20 cores at 200 MHz); exits 1
// on a mismatch.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "Vraster_core.h"
#include "hw/raster_core.h"
#include "workload.h"
#include "verilated.h"

namespace {

using mcpose::hw::Camera;
using mcpose::hw::CoreStats;
using mcpose::hw::Counts;
using mcpose::hw::DepthBounds;
using mcpose::hw::ModelVertex;
using mcpose::hw::Pose;
using Triangles = std::vector<std::array<uint32_t, 3>>;
using mcpose::hw::sim::SetBits;

constexpr int kBoxWords = 1 << 13;  // the core's AW

struct Bench {
  Vraster_core core;
  uint64_t cycles = 0;

  Bench() {
    core.rst = 1;
    Tick();
    Tick();
    core.rst = 0;
  }
  void Tick() {
    core.clk = 0;
    core.eval();
    core.clk = 1;
    core.eval();
    ++cycles;
  }
  // The depth distributor's writes of one box.
  void LoadBounds(const std::vector<DepthBounds>& bounds) {
    for (size_t i = 0; i < bounds.size(); ++i) {
      core.bnd_we = 1;
      core.bnd_addr = static_cast<uint32_t>(i);
      core.bnd_lo = bounds[i].lo;
      core.bnd_hi = bounds[i].hi;
      Tick();
    }
    core.bnd_we = 0;
  }
  // One item into the core's FIFO.
  void Push(int kind, uint64_t data) {
    while (!core.in_ready) Step();
    core.in_valid = 1;
    core.in_kind = static_cast<uint32_t>(kind);
    core.in_data = data;
    Step();
    core.in_valid = 0;
  }
  // A clock, keeping the z-buffer words the count reads.
  void Step() {
    Tick();
    if (core.cnt_valid && core.cnt_addr < zbuf.size()) zbuf[core.cnt_addr] = core.cnt_z;
  }
  // One sample: start, every vertex, every triangle, the end, done. Returns the clocks from
  // start to done; zbuf holds the z-buffer as the count read it.
  uint64_t Run(const Pose& pose, const Camera& camera, bool cull, const std::vector<ModelVertex>& model,
               const Triangles& triangles) {
    for (int i = 0; i < 9; ++i)
      SetBits(core.pose_r, 18 * i, 18, static_cast<uint64_t>(static_cast<int64_t>(pose.R[static_cast<size_t>(i)])));
    for (int i = 0; i < 3; ++i) SetBits(core.pose_t, 32 * i, 32, static_cast<uint32_t>(pose.t[static_cast<size_t>(i)]));
    core.cam_fx = static_cast<uint32_t>(camera.fx);
    core.cam_fy = static_cast<uint32_t>(camera.fy);
    core.cam_cx = static_cast<uint32_t>(camera.cx);
    core.cam_cy = static_cast<uint32_t>(camera.cy);
    core.cam_z_near = static_cast<uint32_t>(camera.z_near);
    core.box_w = static_cast<uint32_t>(camera.width);
    core.box_h = static_cast<uint32_t>(camera.height);
    core.cull = cull;
    zbuf.assign(static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height), 0xffffffffu);
    const uint64_t start = cycles;
    core.start = 1;
    Step();
    core.start = 0;
    for (const ModelVertex& v : model) Push(mcpose::hw::sim::kItemVertex, mcpose::hw::sim::VertexItem(v));
    for (const auto& tri : triangles) Push(mcpose::hw::sim::kItemTriangle, mcpose::hw::sim::TriangleItem(tri));
    Push(mcpose::hw::sim::kItemEnd, 0);
    while (!core.done) Step();
    return cycles - start;
  }
  Counts counts() const {
    return {static_cast<int32_t>(core.inliers), static_cast<int32_t>(core.rendered), static_cast<int32_t>(core.occluded)};
  }
  // Words of the z-buffer the count read that differ from `want`.
  int ZbufMismatches(const std::vector<uint32_t>& want) const {
    int bad = 0;
    for (size_t i = 0; i < want.size(); ++i) bad += zbuf[i] != want[i];
    return bad;
  }
  std::vector<uint32_t> zbuf;
};

uint64_t Median(std::vector<uint64_t> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

int RandomSamples(int samples, unsigned seed) {
  std::mt19937_64 rng(seed);
  auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  Bench b;
  int mismatches = 0;
  std::vector<uint64_t> sample_cycles;
  int64_t triangles_total = 0, drawn_total = 0;
  for (int s = 0; s < samples; ++s) {
    // The box, the camera, the observed depth.
    const int W = static_cast<int>(uniform(4, 90)), H = static_cast<int>(uniform(4, 90));
    const double f = uniform(250, 1100);
    const double depth = uniform(0.3, 1.6);
    const Camera camera = mcpose::hw::QuantizeCamera(f, f * uniform(0.98, 1.02), uniform(-20, W + 20),
                                                     uniform(-20, H + 20), 0, 0, W, H, 0.05);
    const int32_t eps = static_cast<int32_t>(uniform(20, 300));
    std::vector<DepthBounds> bounds(static_cast<size_t>(W * H));
    for (auto& w : bounds) {
      const int32_t d = uniform(0, 1) < 0.1 ? 0 : static_cast<int32_t>((depth + uniform(-0.1, 0.1)) * 1e4);
      w = mcpose::hw::InlierBounds(d, eps);
    }
    // A triangle soup about the origin, at a random pose (now and then too near, or aside).
    const int n_tri = static_cast<int>(uniform(1, 60));
    const double size = uniform(0.01, 0.15);
    std::vector<ModelVertex> model;
    Triangles triangles;
    for (int t = 0; t < n_tri; ++t) {
      const Eigen::Vector3d c(uniform(-size, size), uniform(-size, size), uniform(-size, size));
      std::array<uint32_t, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d p = c + Eigen::Vector3d(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)) * size * 0.5;
        ModelVertex v;
        for (int a = 0; a < 3; ++a)
          v[static_cast<size_t>(a)] = static_cast<int16_t>(std::lround(p[a] / mcpose::hw::kPositionUnitM));
        tri[static_cast<size_t>(k)] = static_cast<uint32_t>(model.size());
        model.push_back(v);
      }
      triangles.push_back(tri);
    }
    const Eigen::Vector3f axis(static_cast<float>(uniform(-1, 1)), static_cast<float>(uniform(-1, 1)),
                               static_cast<float>(uniform(-1, 1)));
    const Eigen::Matrix3f R =
        Eigen::AngleAxisf(static_cast<float>(uniform(-3.14, 3.14)), axis.normalized()).toRotationMatrix();
    const double z = uniform(0, 1) < 0.05 ? uniform(0.0, 0.1) : depth;
    const double aside = uniform(0, 1) < 0.05 ? 3.0 : 0.05;
    const Eigen::Vector3f t(static_cast<float>(uniform(-aside, aside)), static_cast<float>(uniform(-aside, aside)),
                            static_cast<float>(z));
    const Pose pose = mcpose::hw::QuantizePose(R, t);
    const bool cull = uniform(0, 1) < 0.7;

    std::vector<mcpose::hw::Vertex> vertices;
    std::vector<uint32_t> zbuf(static_cast<size_t>(W * H));
    CoreStats stats;
    mcpose::hw::RenderSample(model, triangles, pose, camera, cull, &vertices, zbuf, &stats);
    const Counts want = mcpose::hw::CountBox(zbuf, bounds);

    b.LoadBounds(bounds);
    sample_cycles.push_back(b.Run(pose, camera, cull, model, triangles));
    triangles_total += stats.triangles;
    drawn_total += stats.drawn;
    const Counts got = b.counts();
    const bool bad = !(got == want) || b.core.drawn != static_cast<uint32_t>(stats.drawn) ||
                     b.core.fragments != static_cast<uint32_t>(stats.fragments);
    const int bad_words = b.ZbufMismatches(zbuf);
    if (bad || bad_words) {
      if (++mismatches <= 5)
        std::printf("sample %d: rtl N %d N_r %d occluded %d drawn %u fragments %u, model N %d N_r %d occluded %d "
                    "drawn %lld fragments %lld, %d z-buffer words differ\n",
                    s, got.inliers, got.rendered, got.occluded, b.core.drawn, b.core.fragments, want.inliers,
                    want.rendered, want.occluded, static_cast<long long>(stats.drawn),
                    static_cast<long long>(stats.fragments), bad_words);
    }
  }
  std::sort(sample_cycles.begin(), sample_cycles.end());
  std::printf("%d samples, %d mismatches, cycles per sample (median %llu, max %llu); %lld triangles, %lld drawn\n",
              samples, mismatches, static_cast<unsigned long long>(Median(sample_cycles)),
              static_cast<unsigned long long>(sample_cycles.back()), static_cast<long long>(triangles_total),
              static_cast<long long>(drawn_total));
  return mismatches == 0 ? 0 : 1;
}

int Workload(const std::string& path) {
  const std::vector<mcpose::hw::sim::WorkloadObject> objects = mcpose::hw::sim::ReadWorkload(path, kBoxWords);
  Bench b;
  int total = 0, mismatches = 0;
  constexpr int kCores = 20;
  constexpr double kClockHz = 200e6;
  for (const auto& o : objects) {
    b.LoadBounds(o.bounds);
    std::vector<uint64_t> cycles;
    std::vector<uint64_t> core_cycles(kCores, 0);
    int object_mismatches = 0;
    for (size_t s = 0; s < o.samples.size(); ++s) {
      cycles.push_back(b.Run(o.samples[s].pose, o.camera, o.cull, o.model, o.triangles));
      core_cycles[s % kCores] += cycles.back();
      const Counts got = b.counts(), want = o.samples[s].counts;
      if (!(got == want) && ++object_mismatches <= 3)
        std::printf("%s sample %zu: rtl N %d N_r %d occluded %d, model N %d N_r %d occluded %d\n", o.name.c_str(), s,
                    got.inliers, got.rendered, got.occluded, want.inliers, want.rendered, want.occluded);
    }
    // Each core runs every kCores-th sample on its own (no lockstep), after the bounds' writes.
    const uint64_t iteration = o.bounds.size() + *std::max_element(core_cycles.begin(), core_cycles.end());
    std::printf("%-22s %4zu samples, %d mismatches, cycles per sample (median %llu, max %llu); %zu triangles, box "
                "%dx%d; %d free-running cores at %.0f MHz: %.2f ms an iteration\n",
                o.name.c_str(), o.samples.size(), object_mismatches, static_cast<unsigned long long>(Median(cycles)),
                static_cast<unsigned long long>(*std::max_element(cycles.begin(), cycles.end())), o.triangles.size(),
                o.camera.width, o.camera.height, kCores, kClockHz / 1e6, 1e3 * static_cast<double>(iteration) / kClockHz);
    total += static_cast<int>(o.samples.size());
    mismatches += object_mismatches;
  }
  std::printf("%d samples, %d mismatches\n", total, mismatches);
  return mismatches == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Verilated::commandArgs(argc, argv);
  if (argc > 2 && std::string(argv[1]) == "--workload") return Workload(argv[2]);
  const int samples = argc > 1 ? std::atoi(argv[1]) : 200;
  const unsigned seed = argc > 2 ? static_cast<unsigned>(std::atoi(argv[2])) : 1u;
  if (samples < 1) {
    std::fprintf(stderr, "usage: raster_core_tb [SAMPLES [SEED]] | --workload FILE\n");
    return 2;
  }
  return RandomSamples(samples, seed);
}
