// Detector-like 2D boxes made from ground-truth visible masks: jittered tight boxes plus
// same-class distractors, in the BOP detection format.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "mcpose/eval.h"

namespace mcpose {
namespace {

// SplitMix64 (Steele, Lea, Flood 2014): tiny, self-contained and fully specified, so the boxes
// are the same on every platform and standard library.
class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}

  uint64_t Next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }

 private:
  uint64_t state_;
};

// One stream per (seed, scene_id, image_id, gt_index): the boxes of an instance do not depend
// on which other frames or instances are processed.
uint64_t StreamSeed(uint64_t seed, const FrameKey& key, int gt_index) {
  uint64_t h = SplitMix64(seed).Next();
  for (int v : {key.scene_id, key.image_id, gt_index}) {
    h = SplitMix64(h ^ static_cast<uint64_t>(static_cast<uint32_t>(v))).Next();
  }
  return h;
}

std::string FrameName(const FrameKey& key) {
  return "scene " + std::to_string(key.scene_id) + " image " + std::to_string(key.image_id);
}

// Half-open pixel box [x0, x1) x [y0, y1).
struct Box {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
};

// Tight box of the nonzero pixels and their count (0 = empty mask, box undefined).
int TightBox(const MaskImage& mask, Box* box) {
  Detection d;
  const int count = MaskBox(mask, &d);
  if (count > 0) *box = Box{d.x, d.y, d.x + d.w, d.y + d.h};
  return count;
}

Status ValidateOptions(const GtDetectionOptions& options) {
  if (!(options.jitter >= 0.0) || !std::isfinite(options.jitter)) {
    return InvalidArgument("GtDetectionOptions.jitter must be finite and >= 0, got " +
                           std::to_string(options.jitter));
  }
  if (!(options.distractors >= 0.0 && options.distractors <= 1.0)) {
    return InvalidArgument("GtDetectionOptions.distractors must be a probability in [0, 1], got " +
                           std::to_string(options.distractors));
  }
  if (options.min_visible_pixels < 1) {
    return InvalidArgument("GtDetectionOptions.min_visible_pixels must be >= 1 (an empty mask "
                           "has no box), got " + std::to_string(options.min_visible_pixels));
  }
  return Status::Ok();
}

Detection MakeDetection(const FrameKey& key, int obj_id, double score, double x, double y,
                        double w, double h) {
  Detection d;
  d.scene_id = key.scene_id;
  d.image_id = key.image_id;
  d.obj_id = obj_id;
  d.score = score;
  d.x = x;
  d.y = y;
  d.w = w;
  d.h = h;
  d.time_s = -1;
  return d;
}

}  // namespace

// Random draws per instance, in this order: left, top, right, bottom jitter; score; distractor
// coin; then, for a distractor, its x, y and score.
int MaskBox(const MaskImage& mask, Detection* box) {
  int count = 0;
  int x_min = mask.width, y_min = mask.height, x_max = -1, y_max = -1;
  for (int y = 0; y < mask.height; ++y) {
    for (int x = 0; x < mask.width; ++x) {
      if (!mask.at(x, y)) continue;
      ++count;
      x_min = std::min(x_min, x);
      x_max = std::max(x_max, x);
      y_min = std::min(y_min, y);
      y_max = std::max(y_max, y);
    }
  }
  if (count > 0) {
    box->x = x_min, box->y = y_min;
    box->w = x_max - x_min + 1, box->h = y_max - y_min + 1;
  }
  return count;
}

StatusOr<std::vector<Detection>> DetectionsFromGroundTruth(const Dataset& dataset,
                                                           const GtDetectionOptions& options) {
  MCPOSE_RETURN_IF_ERROR(ValidateOptions(options));

  std::vector<FrameKey> frames = dataset.Frames();
  std::sort(frames.begin(), frames.end());

  const std::vector<int> ids = dataset.ObjectIds();
  const std::set<int> with_model(ids.begin(), ids.end());
  std::map<int, int> without_model;  // obj_id -> instances left out
  std::vector<Detection> out;
  for (const FrameKey& key : frames) {
    MCPOSE_ASSIGN_OR_RETURN(const Frame frame, dataset.LoadFrame(key));
    const double image_w = frame.K.width, image_h = frame.K.height;
    for (const GtInstance& gt : frame.gt) {
      // A box of a class the dataset has no model for could never be estimated.
      if (!with_model.contains(gt.obj_id)) {
        ++without_model[gt.obj_id];
        continue;
      }
      MCPOSE_ASSIGN_OR_RETURN(const MaskImage mask, dataset.LoadVisibleMask(key, gt));
      if (mask.width != frame.K.width || mask.height != frame.K.height ||
          mask.values.size() != static_cast<size_t>(mask.width) * mask.height) {
        return InvalidArgument(
            FrameName(key) + ", gt " + std::to_string(gt.gt_index) + ": visible mask is " +
            std::to_string(mask.width) + "x" + std::to_string(mask.height) + " with " +
            std::to_string(mask.values.size()) + " values, image is " +
            std::to_string(frame.K.width) + "x" + std::to_string(frame.K.height));
      }

      // Tight box of the visible mask.
      Box tight;
      if (TightBox(mask, &tight) < options.min_visible_pixels) continue;

      // Each side moves independently by up to jitter times the box size; then clip.
      SplitMix64 rng(StreamSeed(options.seed, key, gt.gt_index));
      const double j = options.jitter;
      Box box;
      box.x0 = tight.x0 + rng.Uniform(-j, j) * tight.width();
      box.y0 = tight.y0 + rng.Uniform(-j, j) * tight.height();
      box.x1 = tight.x1 + rng.Uniform(-j, j) * tight.width();
      box.y1 = tight.y1 + rng.Uniform(-j, j) * tight.height();
      box.x0 = std::clamp(box.x0, 0.0, image_w);
      box.x1 = std::clamp(box.x1, 0.0, image_w);
      box.y0 = std::clamp(box.y0, 0.0, image_h);
      box.y1 = std::clamp(box.y1, 0.0, image_h);
      if (box.width() < 1.0 || box.height() < 1.0) box = tight;  // jitter collapsed the box
      const double w = box.width(), h = box.height();
      out.push_back(MakeDetection(key, gt.obj_id, rng.Uniform(0.5, 1.0), box.x0, box.y0, w, h));

      // Distractor: same class and size, anywhere fully inside the image.
      if (rng.Uniform() < options.distractors) {
        const double x = rng.Uniform(0.0, image_w - w);
        const double y = rng.Uniform(0.0, image_h - h);
        out.push_back(MakeDetection(key, gt.obj_id, rng.Uniform(0.2, 0.7), x, y, w, h));
      }
    }
  }

  std::stable_sort(out.begin(), out.end(), [](const Detection& a, const Detection& b) {
    if (a.scene_id != b.scene_id) return a.scene_id < b.scene_id;
    if (a.image_id != b.image_id) return a.image_id < b.image_id;
    if (a.obj_id != b.obj_id) return a.obj_id < b.obj_id;
    return a.score > b.score;
  });
  for (const auto& [obj_id, instances] : without_model)
    spdlog::warn("{}: the ground truth names obj_id {} ({} instance(s)), which has no model in {}; no box is written "
                 "for it", dataset.root(), obj_id, instances, dataset.models_dir());
  return out;
}

}  // namespace mcpose
