// The walk every dataset diagnostic makes: each ground-truth instance with a visible pixel, with
// its frame, its tight visible-mask box, its mesh and its evaluation points (each object's
// loaded once).
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/mesh.h"
#include "mcpose/status.h"

namespace mcpose::analysis {

struct VisibleInstance {
  const Frame& frame;
  const GtInstance& gt;
  Detection tight;  // the visible mask's box (BOP convention: x .. x + w - 1)
  const Mesh& mesh;
  const std::vector<Eigen::Vector3f>& points;
};

// Calls `visit` for every visible ground-truth instance of `dataset`'s frames, in order, the
// synthetic frames left out when `real_only`; `progress` (may be null) after each frame. The
// first error (loading, or one `visit` returns) ends the walk and is returned.
Status ForEachVisibleInstance(const Dataset& dataset, bool real_only,
                              const std::function<Status(const VisibleInstance&)>& visit,
                              void (*progress)(int done, int total) = nullptr);

}  // namespace mcpose::analysis
