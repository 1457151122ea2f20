#include "engine/context.h"

#include <string>

#include "core/check.h"
#include "mcpose/option_table.h"
#include "mcpose/simd.h"
#include "render/simd_dispatch.h"
#include "score/box_fit.h"

namespace mcpose::engine {

namespace {

// The threads of a context dispatch their SIMD kernels to its options' target (none to set for
// the best: the process's).
ThreadScope SimdScope(const EngineOptions& engine) {
  const hwy::ChosenTarget* target = render::CappedDispatchTarget(static_cast<int>(engine.simd_target));
  if (target == nullptr) return {};
  return {[target] { render::PushThreadDispatchTarget(target); }, [] { render::PopThreadDispatchTarget(); }};
}

}  // namespace

Status CheckSimdTarget(const EngineOptions& engine) {
  const int index = static_cast<int>(engine.simd_target);
  if (render::SimdTargetSupported(index)) return Status::Ok();
  return InvalidArgument("engine.simd_target " + std::string(SimdTargetNames()[static_cast<size_t>(index)]) +
                         ": this CPU does not have it (it has: " + render::SimdTargetsAvailable() + ")");
}

Context::Context(const EstimatorOptions& options)
    : options_(options), cores_(options.engine.threads, options.engine.backend, SimdScope(options.engine)) {
  MCPOSE_CHECK(options.IsValid(nullptr));
}

ThreadScope Context::simd_scope() const { return SimdScope(options_.engine); }

Context::Context(const EstimatorOptions& options, const Context& caches_from) : Context(options) {
  caches_ = caches_from.caches_;
}

namespace {

// The entry of `cache` under `key`, built by `build` (outside the lock: a mesh's chain or grid
// takes long) on first use; an entry built twice at once is the same, and the first is kept.
template <typename T, typename Build>
std::shared_ptr<const T> Cached(std::mutex& mutex, std::map<uint64_t, std::shared_ptr<const T>>& cache, uint64_t key,
                                Build build) {
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
  }
  std::shared_ptr<const T> built = build();
  std::lock_guard<std::mutex> lock(mutex);
  return cache.emplace(key, std::move(built)).first->second;
}

}  // namespace

std::shared_ptr<const render::LodChain> Context::Lod(const Mesh& mesh) {
  if (!(options_.engine.lod_error_px > 0)) return nullptr;
  return Cached(caches_->mutex, caches_->lod, render::MeshFingerprint(mesh), [&] {
    return std::make_shared<const render::LodChain>(render::LodChain::Build(
        mesh, options_.engine.lod_unbiased ? render::LodVertices::kUnbiased : render::LodVertices::kKept));
  });
}

std::shared_ptr<const appearance::ColourGrid> Context::Colour(const Mesh& mesh) {
  if (!options_.appearance.enabled || mesh.appearance.empty()) return nullptr;
  const uint64_t key = render::MeshFingerprint(mesh) ^ (appearance::AppearanceFingerprint(mesh.appearance) * 31);
  return Cached(caches_->mutex, caches_->colour, key, [&] { return appearance::ColourGrid::Build(mesh); });
}

std::shared_ptr<const std::vector<Eigen::Vector3d>> Context::Extremes(const Mesh& mesh) {
  if (!(options_.weight.box_fit > 0)) return nullptr;
  return Cached(caches_->mutex, caches_->extremes, render::MeshFingerprint(mesh), [&] {
    return std::make_shared<const std::vector<Eigen::Vector3d>>(score::ExtremePoints(mesh));
  });
}

std::shared_ptr<const MeshRests> Context::Rests(const Mesh& mesh) {
  if (!(options_.init.rest_share > 0)) return nullptr;
  return Cached(caches_->mutex, caches_->rests, render::MeshFingerprint(mesh), [&]() -> std::shared_ptr<const MeshRests> {
    StatusOr<std::vector<RestPose>> rests = StableRestPoses(mesh);
    if (!rests.ok() || rests->empty()) return nullptr;
    auto out = std::make_shared<MeshRests>();
    out->rests = std::move(*rests);
    out->centre_of_mass = CentreOfMass(mesh);
    double total = 0;
    for (const RestPose& r : out->rests) total += r.face_area;
    double sum = 0;
    for (const RestPose& r : out->rests) out->area_cdf.push_back(total > 0 ? (sum += r.face_area) / total : 1.0);
    out->area_cdf.back() = 1.0;
    return out;
  });
}

void Context::PrepareMeshes(std::span<const Mesh* const> meshes) {
  if (meshes.empty()) return;
  pool().ParallelFor(
      static_cast<int64_t>(meshes.size()),
      [&](int64_t begin, int64_t end, int) {
        for (int64_t i = begin; i < end; ++i) {
          Lod(*meshes[static_cast<size_t>(i)]);
          Colour(*meshes[static_cast<size_t>(i)]);
          Extremes(*meshes[static_cast<size_t>(i)]);
          Rests(*meshes[static_cast<size_t>(i)]);
        }
      },
      /*chunks_per_thread=*/static_cast<int>(meshes.size()));
}

}  // namespace mcpose::engine
