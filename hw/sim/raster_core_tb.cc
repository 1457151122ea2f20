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
#include "hw/rtl_driver.h"
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

constexpr int kBoxWords = 1 << 13;  // the core's AW

constexpr int kVertexIndexBits = 11;  // the core's VW

// The core and its driver (hw/rtl_driver.h), keeping the z-buffer each sample's count reads.
struct Bench {
  Vraster_core core;
  mcpose::hw::rtl::CoreDriver<Vraster_core> driver{&core, kVertexIndexBits};
  std::vector<uint32_t> zbuf;

  uint64_t Run(const Pose& pose, const Camera& camera, bool cull, const std::vector<ModelVertex>& model,
               const Triangles& triangles) {
    zbuf.assign(static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height), 0xffffffffu);
    return driver.Run(pose, camera, cull, model, triangles, zbuf);
  }
  // Words of the z-buffer the count read that differ from `want`.
  int ZbufMismatches(const std::vector<uint32_t>& want) const {
    int bad = 0;
    for (size_t i = 0; i < want.size(); ++i) bad += zbuf[i] != want[i];
    return bad;
  }
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

    b.driver.LoadBounds(bounds);
    sample_cycles.push_back(b.Run(pose, camera, cull, model, triangles));
    triangles_total += stats.triangles;
    drawn_total += stats.drawn;
    const Counts got = b.driver.counts();
    const bool bad = !(got == want) || b.driver.drawn() != stats.drawn || b.driver.fragments() != stats.fragments;
    const int bad_words = b.ZbufMismatches(zbuf);
    if (bad || bad_words) {
      if (++mismatches <= 5)
        std::printf("sample %d: rtl N %d N_r %d occluded %d drawn %u fragments %u, model N %d N_r %d occluded %d "
                    "drawn %lld fragments %lld, %d z-buffer words differ\n",
                    s, got.inliers, got.rendered, got.occluded, static_cast<unsigned>(b.driver.drawn()),
                    static_cast<unsigned>(b.driver.fragments()), want.inliers,
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
    b.driver.LoadBounds(o.bounds);
    std::vector<uint64_t> cycles;
    std::vector<uint64_t> core_cycles(kCores, 0);
    int object_mismatches = 0;
    for (size_t s = 0; s < o.samples.size(); ++s) {
      cycles.push_back(b.Run(o.samples[s].pose, o.camera, o.cull, o.model, o.triangles));
      core_cycles[s % kCores] += cycles.back();
      const Counts got = b.driver.counts(), want = o.samples[s].counts;
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
