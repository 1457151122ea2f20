// The raster cores: a pool of worker threads, each a raster core with its own scratch, running
// one backend (src/backends/) over a batch of pose hypotheses. One InlierCounts per hypothesis
// comes out, the same at any thread count (each depends on its hypothesis only).
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "backends/backend.h"
#include "core/parallel_for.h"
#include "filter/particles.h"
#include "render/raster.h"
#include "score/inlier.h"

namespace mcpose::engine {

class RasterCores {
 public:
  // `scope`: what each thread runs around its work (ThreadPool).
  RasterCores(int threads, RasterBackend backend, ThreadScope scope = {});
  ~RasterCores();

  int threads() const { return pool_.size(); }
  ThreadPool& pool() { return pool_; }
  const backends::Backend& backend() const { return *backend_; }

  // counts[i] = the inlier counts of particle i rendered in boxes[particles.box[i]]. Adds the
  // raster statistics of the batch to *stats (when given).
  void Score(std::span<const backends::BoxTarget> boxes, const backends::SampleSettings& settings,
             const filter::ParticleSet& particles, std::span<score::InlierCounts> counts,
             RasterCounters* stats);

 private:
  struct Core {
    backends::Scratch scratch;
    RasterCounters stats;
  };
  ThreadPool pool_;
  std::unique_ptr<backends::Backend> backend_;
  std::vector<Core> cores_;
};

}  // namespace mcpose::engine
