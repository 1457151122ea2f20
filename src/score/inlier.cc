#include "score/inlier.h"

#include <cmath>
#include <vector>

#include <nanoflann.hpp>

namespace mcpose::score {

int32_t CountObserved(std::span<const float> observed) {
  int32_t n = 0;
  for (float d : observed) n += d > 0.f;
  return n;
}

std::vector<float> ObservedOrNaN(std::span<const float> observed) {
  std::vector<float> out(observed.begin(), observed.end());
  for (float& d : out)
    if (!(d > 0.f)) d = NAN;
  return out;
}

InlierCounts CountInliers1D(std::span<const float> rendered, std::span<const float> observed,
                            float eps_m) {
  InlierCounts c;
  for (size_t i = 0; i < rendered.size(); ++i) {
    const float zr = rendered[i], zo = observed[i];
    const bool drawn = zr != INFINITY;
    c.rendered += drawn;
    c.observed += zo > 0.f;
    c.inliers += drawn && zo > 0.f && std::fabs(zr - zo) < eps_m;
    c.occluded += drawn && zo > 0.f && zo <= zr - eps_m;
  }
  return c;
}

InlierCounts CountInliers1DInRect(const float* rendered, const float* observed, int stride,
                                  const render::PixelRect& rect, int32_t n_observed, float eps_m) {
  InlierCounts c;
  c.observed = n_observed;
  for (int y = rect.y0; y < rect.y1; ++y) {
    const float* zr = rendered + static_cast<size_t>(y) * stride;
    const float* zo = observed + static_cast<size_t>(y) * stride;
    int32_t drawn = 0, inliers = 0, occluded = 0;  // per row: lets the compiler vectorize
    for (int x = rect.x0; x < rect.x1; ++x) {
      const bool d = zr[x] != INFINITY, valid = zo[x] > 0.f;
      drawn += d;
      inliers += d & valid & (std::fabs(zr[x] - zo[x]) < eps_m);
      occluded += d & valid & (zo[x] <= zr[x] - eps_m);
    }
    c.rendered += drawn;
    c.inliers += inliers;
    c.occluded += occluded;
  }
  return c;
}

struct ObservedCloud::Impl {
  // nanoflann dataset adaptor over a flat xyz array.
  struct Points {
    std::vector<float> xyz;
    size_t kdtree_get_point_count() const { return xyz.size() / 3; }
    float kdtree_get_pt(size_t i, size_t dim) const { return xyz[3 * i + dim]; }
    template <class BBOX>
    bool kdtree_get_bbox(BBOX&) const { return false; }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<
      nanoflann::L2_Simple_Adaptor<float, Points>, Points, 3, uint32_t>;

  Intrinsics K;
  render::PixelRect box;
  Points points;
  std::vector<float> depth;  // the box's observed depth, for the occlusion count
  int32_t observed = 0;
  std::unique_ptr<Tree> tree;

  Eigen::Vector3f BackProject(int x, int y, float z) const {
    return {static_cast<float>((x - K.cx) / K.fx) * z, static_cast<float>((y - K.cy) / K.fy) * z, z};
  }
};

ObservedCloud::ObservedCloud(const Intrinsics& K, const render::PixelRect& box,
                             std::span<const float> observed)
    : impl_(std::make_unique<Impl>()) {
  impl_->K = K;
  impl_->box = box;
  impl_->depth.assign(observed.begin(), observed.end());
  for (int y = box.y0; y < box.y1; ++y) {
    for (int x = box.x0; x < box.x1; ++x) {
      const float z = observed[(y - box.y0) * box.width() + (x - box.x0)];
      if (!(z > 0.f)) continue;
      const Eigen::Vector3f p = impl_->BackProject(x, y, z);
      impl_->points.xyz.insert(impl_->points.xyz.end(), {p.x(), p.y(), p.z()});
    }
  }
  impl_->observed = static_cast<int32_t>(impl_->points.kdtree_get_point_count());
  impl_->tree = std::make_unique<Impl::Tree>(3, impl_->points,
                                             nanoflann::KDTreeSingleIndexAdaptorParams(16));
  if (impl_->observed > 0) impl_->tree->buildIndex();
}

ObservedCloud::~ObservedCloud() = default;

InlierCounts ObservedCloud::CountInliers3D(std::span<const float> rendered, float eps_m) const {
  InlierCounts c;
  c.observed = impl_->observed;
  const auto& box = impl_->box;
  for (int y = box.y0; y < box.y1; ++y) {
    for (int x = box.x0; x < box.x1; ++x) {
      const float z = rendered[(y - box.y0) * box.width() + (x - box.x0)];
      if (z == INFINITY) continue;
      ++c.rendered;
      if (impl_->observed == 0) continue;
      const Eigen::Vector3f p = impl_->BackProject(x, y, z);
      uint32_t index = 0;
      float dist2 = 0.f;
      impl_->tree->knnSearch(p.data(), 1, &index, &dist2);
      const bool inlier = dist2 < eps_m * eps_m;
      const float zo = impl_->depth[(y - box.y0) * box.width() + (x - box.x0)];
      c.inliers += inlier;
      c.occluded += !inlier && zo > 0.f && zo <= z - eps_m;
    }
  }
  return c;
}

}  // namespace mcpose::score
