// Several instances of one class in an image: which boxes belong to one object, and whether two
// poses explain the same pixels.
//
// The class's first instance is the paper's answer: one filter over all the class's boxes,
// samples in proportion to their scores. Boxes of the class that lie apart from the box that
// answer came from (another cluster) may show other objects of the class: each such cluster gets
// a filter of its own, and its pose is kept as another instance unless it explains the same depth
// pixels as an instance kept before it. Where the boxes form one cluster, the first instance is
// the result, as with one instance per class.
#pragma once

#include <span>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/detection.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/se3.h"

namespace mcpose::engine {

// Boxes of one class grouped into objects, as non-maximum suppression groups them: boxes in
// order of score (ties: the earlier box first), each joins the first cluster whose leader (its
// highest-scored box) it overlaps with IoU >= min_iou, or leads a new one. Each cluster lists
// indices into `boxes`, its leader first; clusters in order of their leaders' scores.
std::vector<std::vector<int>> ClusterBoxes(std::span<const Detection> boxes, double min_iou = 0.5);

// The depth pixels a pose explains: pixels (y * width + x, ascending) where the mesh at
// T_cam_obj covers the image and its depth lies within eps_m of a valid observed depth.
std::vector<int> ExplainedPixels(const Mesh& mesh, const SE3& T_cam_obj, const Intrinsics& K,
                                 const DepthImage& depth, double eps_m);

// The share of `a`'s pixels that `b` explains too (both ascending); 1 when `a` is empty, for a
// pose that explains nothing adds nothing.
double SharedShare(std::span<const int> a, std::span<const int> b);

// A pose whose explained pixels are more than this share explained by an instance kept before
// it shows the same object.
inline constexpr double kSameObjectShare = 0.5;

}  // namespace mcpose::engine
