#include "engine/instances.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "render/depth_image.h"

namespace mcpose::engine {

std::vector<std::vector<int>> ClusterBoxes(std::span<const Detection> boxes, double min_iou) {
  std::vector<int> order(boxes.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return boxes[i].score > boxes[j].score; });
  std::vector<std::vector<int>> clusters;
  for (int i : order) {
    auto home = std::find_if(clusters.begin(), clusters.end(), [&](const std::vector<int>& c) {
      return BoxIou(boxes[c.front()], boxes[i]) >= min_iou;
    });
    if (home != clusters.end())
      home->push_back(i);
    else
      clusters.push_back({i});
  }
  return clusters;
}

std::vector<int> ExplainedPixels(const Mesh& mesh, const SE3& T_cam_obj, const Intrinsics& K,
                                 const DepthImage& depth, double eps_m) {
  const DepthImage rendered = render::RenderDepth(mesh, T_cam_obj, K);
  std::vector<int> pixels;
  const int w = std::min(rendered.width, depth.width), h = std::min(rendered.height, depth.height);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float zr = rendered.at(x, y), zo = depth.at(x, y);
      if (zr > 0.f && zo > 0.f && std::fabs(zr - zo) < eps_m) pixels.push_back(y * depth.width + x);
    }
  return pixels;
}

double SharedShare(std::span<const int> a, std::span<const int> b) {
  if (a.empty()) return 1.0;
  size_t shared = 0;
  for (size_t i = 0, j = 0; i < a.size() && j < b.size();) {
    if (a[i] < b[j])
      ++i;
    else if (b[j] < a[i])
      ++j;
    else
      ++shared, ++i, ++j;
  }
  return static_cast<double>(shared) / static_cast<double>(a.size());
}

}  // namespace mcpose::engine
