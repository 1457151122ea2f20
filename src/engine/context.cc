#include "engine/context.h"

#include "core/check.h"
#include "score/box_fit.h"

namespace mcpose::engine {

Context::Context(const EstimatorOptions& options)
    : options_(options), cores_(options.engine.threads, options.engine.backend) {
  MCPOSE_CHECK(options.IsValid(nullptr));
}

Context::Context(const EstimatorOptions& options, const Context& caches_from) : Context(options) {
  caches_ = caches_from.caches_;
}

std::shared_ptr<const render::LodChain> Context::Lod(const Mesh& mesh) {
  if (!(options_.engine.lod_error_px > 0)) return nullptr;
  const uint64_t key = render::MeshFingerprint(mesh);
  {
    std::lock_guard<std::mutex> lock(caches_->mutex);
    if (auto it = caches_->lod.find(key); it != caches_->lod.end()) return it->second;
  }
  auto built = std::make_shared<const render::LodChain>(render::LodChain::Build(
      mesh, options_.engine.lod_unbiased ? render::LodVertices::kUnbiased : render::LodVertices::kKept));
  std::lock_guard<std::mutex> lock(caches_->mutex);
  return caches_->lod.emplace(key, std::move(built)).first->second;
}

std::shared_ptr<const appearance::ColourGrid> Context::Colour(const Mesh& mesh) {
  if (!options_.appearance.enabled || mesh.appearance.empty()) return nullptr;
  const uint64_t key = render::MeshFingerprint(mesh) ^ (appearance::AppearanceFingerprint(mesh.appearance) * 31);
  {
    std::lock_guard<std::mutex> lock(caches_->mutex);
    if (auto it = caches_->colour.find(key); it != caches_->colour.end()) return it->second;
  }
  std::shared_ptr<const appearance::ColourGrid> built = appearance::ColourGrid::Build(mesh);
  std::lock_guard<std::mutex> lock(caches_->mutex);
  return caches_->colour.emplace(key, std::move(built)).first->second;
}

std::shared_ptr<const std::vector<Eigen::Vector3d>> Context::Extremes(const Mesh& mesh) {
  if (!(options_.weight.box_fit > 0)) return nullptr;
  const uint64_t key = render::MeshFingerprint(mesh);
  {
    std::lock_guard<std::mutex> lock(caches_->mutex);
    if (auto it = caches_->extremes.find(key); it != caches_->extremes.end()) return it->second;
  }
  auto built = std::make_shared<const std::vector<Eigen::Vector3d>>(score::ExtremePoints(mesh));
  std::lock_guard<std::mutex> lock(caches_->mutex);
  return caches_->extremes.emplace(key, std::move(built)).first->second;
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
        }
      },
      /*chunks_per_thread=*/static_cast<int>(meshes.size()));
}

}  // namespace mcpose::engine
