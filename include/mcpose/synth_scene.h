// Synthetic RGB-D frames of objects at rest on a table, as a structured-light camera sees them:
// the stress set of `mcpose synth` (a dataset in the BOP layout, synth/dataset.h).
//
// A frame: a table (a plane, plain or wood-grained) seen from 0.7-1.1 m at an elevation of
// 30-60 degrees, the floor beyond its edges; 3-7 objects drawn from the models, each resting on
// a stable face of its convex hull (core/rest_pose.h: the lowest, or with probability side_share
// another, lying on its side), turned at random about the vertical, 0.5-1.3 m from the camera,
// allowed to hide each other down to a visible fraction of min_visible.
// - Depth: the rendered depth (render/raster.h) plus noise of sigma = depth_noise * z^2, a
//   per-frame offset, no measurement where the surface is seen more grazing than grazing_deg,
//   at depth edges (with probability edge_dropout, a pixel each side) and beyond max_range_m;
//   in 0.1 mm units.
// - Colour: each surface point's albedo (its texture, vertex colour, or a plain colour per object
//   for a model without any) lit in linear light by one distant light of random direction,
//   colour temperature and intensity plus an ambient term (Lambert), sensor noise, and optionally
//   a JPEG round trip.
// Deterministic for (seed, frame index).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose::synth {

struct SceneOptions {
  int min_objects = 3, max_objects = 7;  // copies included
  // The first object drawn in a frame appears this many times (1 to 8), each copy beside the one
  // before it in its own rest pose and turn: several instances of one class, some touching.
  int copies = 1;
  double min_distance_m = 0.5, max_distance_m = 1.3;  // camera to each object's centre of mass
  double side_share = 0.3;     // objects resting on another stable face than their lowest
  double min_visible = 0.1;    // objects hidden more than this are taken out of the frame
  // The YCB-Video camera (its real frames' intrinsics).
  Intrinsics camera{1066.778, 1067.487, 312.9869, 241.3109, 640, 480};
  // Depth sensor.
  double depth_noise = 0.0015;     // sigma of the depth noise at z metres: depth_noise * z^2
  double depth_offset_m = 0.002;   // per-frame offset, uniform in [-this, this]
  double grazing_deg = 75;         // surfaces seen more grazing than this give no depth
  double edge_dropout = 0.5;       // probability that a pixel at a depth edge gives no depth
  double max_range_m = 3.0;
  // Colour sensor.
  double colour_noise = 2.0;  // sigma, 8-bit levels
  int jpeg_quality = 0;       // 0: none; else the colour image goes through JPEG of this quality

  bool IsValid(std::string* error) const;
};

// An object the frames may show: its mesh (metres) and obj_id.
struct SceneObject {
  int obj_id = 0;
  const Mesh* mesh = nullptr;
};

struct SynthInstance {
  int obj_id = 0;
  SE3 T_cam_obj;
  MaskImage visible;       // its visible pixels (255)
  int px_count_all = 0;    // pixels it covers, hidden or not
  int px_count_visib = 0;  // of them, visible
  int px_count_valid = 0;  // visible with a depth measurement
  int bbox_obj[4] = {0, 0, 0, 0};    // x, y, w, h of all its pixels (-1s when none)
  int bbox_visib[4] = {0, 0, 0, 0};  // of its visible pixels
  double visib_fract() const { return px_count_all > 0 ? static_cast<double>(px_count_visib) / px_count_all : 0.0; }
};

struct SynthFrame {
  Intrinsics K;
  SE3 T_cam_world;              // the table's frame: z up, the table top at z = 0
  std::vector<uint16_t> depth;  // 0.1 mm units, 0 = no measurement
  ColourImage colour;
  std::vector<SynthInstance> instances;
};

// Frames of the set made with `seed` from `objects` (each used at most once a frame); frame k is
// the same whatever frames were made before it. One thread at a time.
class SceneMaker {
 public:
  // Checks the options and prepares each model (its stable rest poses); an error names the model.
  static StatusOr<std::unique_ptr<SceneMaker>> Create(std::vector<SceneObject> objects, const SceneOptions& options,
                                                      uint64_t seed);
  ~SceneMaker();
  StatusOr<SynthFrame> MakeFrame(int index);

 private:
  SceneMaker() = default;
  struct Model;
  std::vector<Model> models_;
  SceneOptions options_;
  uint64_t seed_ = 0;
};

// The depth sensor alone, for tests: `depth_m` (metres, +inf where nothing) and the surface
// normal at each pixel (camera frame), measured as SceneOptions says.
std::vector<uint16_t> MeasureDepth(const std::vector<float>& depth_m, const std::vector<Eigen::Vector3f>& normals,
                                   const Intrinsics& K, const SceneOptions& options, uint64_t seed);

}  // namespace mcpose::synth
