// Verilator testbench of hw/rtl/depth_distributor.sv against the C++ model's bounds
// (hw::InlierBounds): random batches of 20 overlapping boxes in a random union of random depth
// (some pixels without depth, some nearer than eps); every word each core receives, its address
// and N_b compared.
//   depth_distributor_tb [BATCHES [SEED]]
// Prints "N batches, M mismatches, clocks per pixel (mean)"; exits 1 on a mismatch.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "Vdepth_distributor.h"
#include "hw/raster_core.h"
#include "hw/rtl_driver.h"
#include "verilated.h"

namespace {

using mcpose::hw::DepthBounds;
using mcpose::hw::rtl::SetBits;

constexpr int kCores = 20;  // the module's CORES
constexpr int kAw = 13;     // its AW

struct Box {
  int x0 = 0, y0 = 0, w = 0, h = 0;
};

}  // namespace

int main(int argc, char** argv) {
  Verilated::commandArgs(argc, argv);
  const int batches = argc > 1 ? std::atoi(argv[1]) : 200;
  const unsigned seed = argc > 2 ? static_cast<unsigned>(std::atoi(argv[2])) : 1u;
  if (batches < 1) {
    std::fprintf(stderr, "usage: depth_distributor_tb [BATCHES [SEED]]\n");
    return 2;
  }
  std::mt19937_64 rng(seed);
  auto uniform = [&](int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); };
  Vdepth_distributor dist;
  uint64_t cycles = 0;
  auto tick = [&] {
    dist.clk = 0;
    dist.eval();
    dist.clk = 1;
    dist.eval();
    ++cycles;
  };
  dist.rst = 1;
  tick();
  tick();
  dist.rst = 0;
  int mismatches = 0;
  uint64_t pixels = 0, stream_cycles = 0;
  for (int batch = 0; batch < batches; ++batch) {
    const int W = uniform(1, 120), H = uniform(1, 100);
    const int32_t eps = uniform(1, 600);
    std::vector<int32_t> depth(static_cast<size_t>(W * H));
    for (int32_t& d : depth) d = uniform(0, 9) == 0 ? 0 : uniform(0, 9) == 0 ? uniform(1, 2 * eps) : uniform(1, 40000);
    std::vector<Box> boxes(kCores);
    for (Box& b : boxes) {
      b.x0 = uniform(0, W - 1), b.y0 = uniform(0, H - 1);
      b.w = uniform(1, W - b.x0), b.h = uniform(1, H - b.y0);
      while (b.w * b.h > (1 << kAw)) b.h = (b.h + 1) / 2;
    }
    dist.eps = static_cast<uint32_t>(eps);
    for (int c = 0; c < kCores; ++c) {
      SetBits(dist.box_x0, 11 * c, 11, static_cast<uint64_t>(boxes[static_cast<size_t>(c)].x0));
      SetBits(dist.box_y0, 11 * c, 11, static_cast<uint64_t>(boxes[static_cast<size_t>(c)].y0));
      SetBits(dist.box_w, 11 * c, 11, static_cast<uint64_t>(boxes[static_cast<size_t>(c)].w));
      SetBits(dist.box_h, 11 * c, 11, static_cast<uint64_t>(boxes[static_cast<size_t>(c)].h));
    }
    dist.start = 1;
    tick();
    dist.start = 0;
    // What each core receives, word by word.
    std::vector<std::vector<DepthBounds>> got(kCores);
    std::vector<int> bad_address(kCores, 0);
    auto collect = [&] {
      for (int c = 0; c < kCores; ++c) {
        if (!((dist.bnd_we >> c) & 1)) continue;
        uint32_t addr = 0;
        for (int b = 0; b < kAw; ++b) addr |= ((dist.bnd_addr[(kAw * c + b) / 32] >> ((kAw * c + b) % 32)) & 1u) << b;
        auto& words = got[static_cast<size_t>(c)];
        bad_address[static_cast<size_t>(c)] += addr != words.size();
        words.push_back({dist.bnd_lo, dist.bnd_hi});
      }
    };
    const uint64_t start = cycles;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        while (!dist.d_ready) {
          tick();
          collect();
        }
        dist.d_valid = 1;
        dist.d_x = static_cast<uint32_t>(x);
        dist.d_y = static_cast<uint32_t>(y);
        dist.d_depth = static_cast<uint32_t>(depth[static_cast<size_t>(y * W + x)]);
        tick();
        collect();
        dist.d_valid = 0;
      }
    while (!dist.d_ready) {
      tick();
      collect();
    }
    tick();
    collect();
    stream_cycles += cycles - start;
    pixels += static_cast<uint64_t>(W * H);
    for (int c = 0; c < kCores; ++c) {
      const Box& b = boxes[static_cast<size_t>(c)];
      std::vector<DepthBounds> want;
      int32_t observed = 0;
      for (int y = b.y0; y < b.y0 + b.h; ++y)
        for (int x = b.x0; x < b.x0 + b.w; ++x) {
          want.push_back(mcpose::hw::InlierBounds(depth[static_cast<size_t>(y * W + x)], eps));
          observed += want.back().lo != 0;
        }
      const auto& g = got[static_cast<size_t>(c)];
      bool same = g.size() == want.size() && bad_address[static_cast<size_t>(c)] == 0;
      for (size_t i = 0; same && i < want.size(); ++i) same = g[i].lo == want[i].lo && g[i].hi == want[i].hi;
      const auto got_observed = dist.observed[c];
      if (!same || got_observed != static_cast<uint32_t>(observed)) {
        if (++mismatches <= 5)
          std::printf("batch %d core %d: %zu words (want %zu), %d misaddressed, N_b %u (want %d)\n", batch, c, g.size(),
                      want.size(), bad_address[static_cast<size_t>(c)], got_observed, observed);
      }
    }
  }
  std::printf("depth distributor: %d batches of %d overlapping boxes, %d mismatches, %.1f clocks per pixel (mean)\n",
              batches, kCores, mismatches, static_cast<double>(stream_cycles) / static_cast<double>(pixels));
  return mismatches == 0 ? 0 : 1;
}
