#include "mcpose/estimator.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <numeric>
#include <string>

#include "core/check.h"
#include "core/rng.h"
#include "engine/initialize.h"
#include "engine/raster_cores.h"
#include "filter/diffuse.h"
#include "filter/particles.h"
#include "filter/resample.h"
#include "render/lod.h"

namespace mcpose {

namespace {

// Substream of the per-sample random streams used by resampling + diffusion.
constexpr uint64_t kStepStream = 0xD1FF05E;

}  // namespace

struct Estimator::Impl {
  EstimatorOptions options;
  engine::RasterCores cores;
  // LOD chains of the meshes seen so far, by content fingerprint (built once per mesh).
  std::mutex lod_mutex;
  std::map<uint64_t, std::shared_ptr<const render::LodChain>> lod_cache;
  Impl(const EstimatorOptions& o) : options(o), cores(o.threads, o.backend) {}

  // The chain of `mesh`, built on first use. Builds run outside the lock (PrepareMeshes runs
  // several at once); a chain built twice at the same time is the same chain, the first kept.
  std::shared_ptr<const render::LodChain> Lod(const Mesh& mesh) {
    const uint64_t key = render::MeshFingerprint(mesh);
    {
      std::lock_guard<std::mutex> lock(lod_mutex);
      if (auto it = lod_cache.find(key); it != lod_cache.end()) return it->second;
    }
    auto built = std::make_shared<const render::LodChain>(render::LodChain::Build(
        mesh, options.lod_unbiased ? render::LodVertices::kUnbiased : render::LodVertices::kKept));
    std::lock_guard<std::mutex> lock(lod_mutex);
    return lod_cache.emplace(key, std::move(built)).first->second;
  }
};

Estimator::Estimator(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Estimator::~Estimator() = default;

const EstimatorOptions& Estimator::options() const { return impl_->options; }

void Estimator::PrepareMeshes(std::span<const Mesh* const> meshes) {
  if (!(impl_->options.lod_error_px > 0) || meshes.empty()) return;
  // One mesh per chunk; Lod() builds outside any shared state but the cache (locked).
  impl_->cores.pool().ParallelFor(
      static_cast<int64_t>(meshes.size()),
      [&](int64_t begin, int64_t end, int) {
        for (int64_t i = begin; i < end; ++i) impl_->Lod(*meshes[static_cast<size_t>(i)]);
      },
      /*chunks_per_thread=*/static_cast<int>(meshes.size()));
}

StatusOr<std::unique_ptr<Estimator>> Estimator::Create(const EstimatorOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("invalid estimator options: " + error);
  return std::unique_ptr<Estimator>(new Estimator(std::make_unique<Impl>(options)));
}

StatusOr<ObjectEstimate> Estimator::Estimate(const Intrinsics& K, const DepthImage& depth,
                                             const Mesh& mesh, std::span<const Detection> boxes,
                                             uint64_t stream_id) {
  const EstimatorOptions& opt = impl_->options;
  engine::RasterCores& cores = impl_->cores;

  // ---- Validate the inputs at the boundary ---------------------------------------------
  std::string error;
  if (!K.IsValid(&error)) return InvalidArgument(error);
  if (depth.width != K.width || depth.height != K.height ||
      depth.depth_m.size() != static_cast<size_t>(depth.width) * depth.height) {
    return InvalidArgument("depth image is " + std::to_string(depth.width) + "x" +
                           std::to_string(depth.height) + " but the intrinsics say " +
                           std::to_string(K.width) + "x" + std::to_string(K.height));
  }
  MCPOSE_RETURN_IF_ERROR(mesh.Validate("mesh"));
  if (boxes.empty()) return InvalidArgument("no boxes given");
  const int obj_id = boxes[0].obj_id;
  for (size_t b = 0; b < boxes.size(); ++b) {
    const Detection& d = boxes[b];
    const std::string where = "box " + std::to_string(b) + " of obj_id " + std::to_string(obj_id);
    if (d.obj_id != obj_id) return InvalidArgument(where + ": boxes of different classes given");
    if (!(std::isfinite(d.score) && d.score >= 0))
      return InvalidArgument(where + ": score must be finite and >= 0");
    if (!(std::isfinite(d.x) && std::isfinite(d.y) && d.w > 0 && d.h > 0 && std::isfinite(d.w) &&
          std::isfinite(d.h)))
      return InvalidArgument(where + ": box must be finite with positive size");
    if (engine::ClipBox(d.x, d.y, d.w, d.h, K.width, K.height).empty())
      return InvalidArgument(where + ": box lies outside the " + std::to_string(K.width) + "x" +
                             std::to_string(K.height) + " image");
  }

  ObjectEstimate result;
  result.obj_id = obj_id;
  EngineCounters& counters = result.counters;

  // ---- Depth distributor: each box's observed depth, read once ---------------------------
  std::vector<engine::BoxDepth> box_depth;
  for (const Detection& d : boxes) {
    const render::PixelRect rect = engine::ClipBox(d.x, d.y, d.w, d.h, K.width, K.height);
    box_depth.push_back(
        engine::DistributeDepth(depth, K, rect, d.score, opt.inlier_mode, engine::BoxStride(rect, opt)));
  }

  // ---- Initialize: samples over boxes in proportion to score -----------------------------
  const int n = opt.samples;
  filter::ParticleSet particles[2];
  engine::InitializeSamples(K, mesh, boxes, box_depth, opt, stream_id, &particles[0]);
  particles[1].Resize(n);

  // ---- Level of detail: per box, the coarsest mesh within the pixel error budget ----------
  std::shared_ptr<const render::LodChain> lod;
  if (opt.lod_error_px > 0) lod = impl_->Lod(mesh);
  std::vector<const Mesh*> box_mesh;
  std::vector<const render::ClusterSet*> box_clusters;
  engine::ChooseBoxMeshes(lod.get(), K, mesh, boxes, box_depth, opt, &box_mesh, &box_clusters);
  for (const Mesh* m : box_mesh) result.box_triangles.push_back(static_cast<int>(m->triangles.size()));

  // ---- Iterate: score, keep the best, stop or resample + diffuse -------------------------
  engine::ScoreJob job;
  job.mesh = &mesh;
  job.box_mesh = box_mesh;
  job.box_clusters = box_clusters;
  job.K = K;
  job.boxes = box_depth;
  engine::SetEngineOptions(opt, &job);

  std::vector<score::InlierCounts> counts(n);
  filter::CdfSampler sampler;
  const Eigen::Vector3d flip_center = (0.5f * (mesh.BoundsMin() + mesh.BoundsMax())).cast<double>();
  std::vector<std::array<int64_t, 2>> worker_reads(static_cast<size_t>(cores.pool().size()));  // draws, naive
  int cur = 0;
  result.best_weight = -1;
  using Clock = std::chrono::steady_clock;
  auto ms_since = [](Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  };
  for (int iter = 0; iter < opt.max_iterations; ++iter) {
    filter::ParticleSet& p = particles[cur];
    const Clock::time_point iter_start = Clock::now();

    // Raster cores: render + inlier counts for every sample.
    render::RasterStats stats;
    cores.Score(job, p, counts, &stats);
    result.score_ms.push_back(ms_since(iter_start));
    result.fragments_per_iteration.push_back(stats.fragments);
    counters.triangles_full += static_cast<int64_t>(mesh.triangles.size()) * n;
    counters.triangles_in += stats.triangles;
    counters.culled_backface += stats.culled_backface;
    counters.culled_degenerate += stats.culled_degenerate;
    counters.culled_outside_box += stats.culled_outside_box;
    counters.culled_near += stats.culled_near;
    counters.culled_between_pixels += stats.culled_between_pixels;
    counters.triangles_rasterized += stats.rasterized;
    counters.fragments += stats.fragments;
    counters.clusters += stats.clusters;
    counters.clusters_culled_backface += stats.clusters_culled_backface;
    counters.clusters_culled_outside_box += stats.clusters_culled_outside_box;

    // Depth distributor traffic: the union of the boxes in use, versus a copy per sample.
    std::vector<char> box_used(boxes.size(), 0);
    for (int i = 0; i < n; ++i) {
      box_used[p.box[i]] = 1;
      counters.depth_bytes_read_naive += box_depth[p.box[i]].rect.area() * int64_t{sizeof(float)};
    }
    std::vector<const engine::BoxDepth*> used;
    for (size_t b = 0; b < boxes.size(); ++b)
      if (box_used[b]) used.push_back(&box_depth[b]);
    const int64_t depth_bytes = engine::UnionSamples(used) * int64_t{sizeof(float)};
    counters.depth_bytes_read += depth_bytes;
    result.depth_bytes_per_iteration.push_back(depth_bytes);

    // Weights, the best sample ever seen (ties: lowest index), the mean.
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      p.weight[i] = score::Weight(counts[i], box_depth[p.box[i]].score, opt.weight_a,
                                  opt.weight_b, opt.weight_c, opt.occlusion_aware);
      sum += p.weight[i];
      if (p.weight[i] > result.best_weight) {
        result.best_weight = p.weight[i];
        result.T_cam_obj = p.Pose(i);
        result.best_box = p.box[i];
      }
    }
    const double mean = sum / n;
    result.mean_weight_history.push_back(mean);
    result.final_mean_weight = mean;
    result.iterations = iter + 1;
    if (mean > opt.tau || iter + 1 == opt.max_iterations) {
      result.iteration_ms.push_back(ms_since(iter_start));  // the last iteration: no resampling
      break;
    }

    // Resample from the sorted CDF and diffuse into the other buffer.
    sampler.Build(p.weight, opt.keep_top_fraction, opt.cdf_table_size);
    const double sigma_t = std::max(opt.sigma_t_min_m, opt.sigma_t_m * std::pow(opt.anneal, iter));
    const double sigma_r = std::max(opt.sigma_r_min_rad, opt.sigma_r_rad * std::pow(opt.anneal, iter));
    // On the raster cores: each sample's draw and noise come from its own stream, so any split
    // gives the same particles; the read counts are summed per worker.
    filter::ParticleSet& next = particles[1 - cur];
    std::fill(worker_reads.begin(), worker_reads.end(), std::array<int64_t, 2>{0, 0});
    cores.pool().ParallelFor(n, [&](int64_t begin, int64_t end, int worker) {
      int64_t reads = 0, reads_naive = 0;
      for (int64_t i = begin; i < end; ++i) {
        Rng rng(opt.seed, stream_id, kStepStream + static_cast<uint64_t>(iter), static_cast<uint64_t>(i));
        const double u = rng.Uniform();
        const int parent = sampler.Draw(u, &reads);
        reads_naive += sampler.LinearSearchReads(u);
        Eigen::Matrix3d R = p.R_cam_obj[parent];
        Eigen::Vector3d t = p.t_cam_obj_m[parent];
        // A flip move draws only when enabled: flip_rate 0 gives the samples of a build without.
        if (opt.flip_rate > 0 && rng.Uniform() < opt.flip_rate)
          filter::Flip(std::min(2, static_cast<int>(3 * rng.Uniform())), flip_center, &R, &t);
        filter::Diffuse(R, t, sigma_r, sigma_t, rng, &next.R_cam_obj[i], &next.t_cam_obj_m[i]);
        next.box[i] = p.box[parent];
      }
      worker_reads[worker][0] += reads, worker_reads[worker][1] += reads_naive;
    });
    counters.cdf_draws += n;
    for (const auto& r : worker_reads) counters.cdf_reads += r[0], counters.cdf_reads_naive += r[1];
    cur = 1 - cur;
    result.iteration_ms.push_back(ms_since(iter_start));
  }
  return result;
}

}  // namespace mcpose
