// Appearance capture: a model's surface colour baked from posed frames, for models that come
// without colour. Each surface point (a texel centre of the mesh's texture layout, or a vertex
// when the mesh has none) takes its colour from every view in which it is visible: facing the
// camera, not hidden by the object itself (a z-buffer of the mesh at the view's pose), inside
// the object's visible mask (not hidden by others) and where the observed depth agrees with the
// rendered one. A point's colours from all views are combined by their per-channel median
// (robust to highlights and to a view's misregistered edge); a point no view saw stays unknown
// (alpha 0).
#pragma once

#include <span>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/dataset.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose::appearance {

struct CaptureOptions {
  double depth_agreement_m = 0.01;  // |observed - rendered depth| below this at a sampled pixel
  double visibility_m = 0.004;      // the point within this of the mesh's own z-buffer
  double max_view_angle_deg = 75;   // views more grazing than this are not used
  int texture_size = 512;           // texels a side of a captured texture
  bool IsValid(std::string* error) const;
};

// One frame's view of the object.
struct PosedView {
  Intrinsics K;
  const DepthImage* depth = nullptr;
  const ColourImage* colour = nullptr;  // same size as depth
  const MaskImage* visible = nullptr;   // the object's visible pixels (nonzero), same size
  SE3 T_cam_obj;
};

struct CaptureStats {
  int views = 0;         // views with at least one sample
  int64_t samples = 0;   // colour samples taken
  int points = 0;        // surface points (texels on the surface, or vertices)
  int known = 0;         // of them, seen at least once
};

// The appearance of `mesh` from `views`: a texture of options.texture_size texels a side in the
// mesh's texture layout when it has one (triangle_uv), else vertex colours. An error names the
// view whose images are inconsistent (sizes) or the invalid option.
StatusOr<MeshAppearance> CaptureFromViews(const Mesh& mesh, std::span<const PosedView> views,
                                          const CaptureOptions& options, CaptureStats* stats);

// Per object of the dataset: what capture did (for the report and the CLI's table).
struct ObjectCapture {
  int obj_id = 0;
  std::string name;
  enum class Source { kCaptured, kOwnColour, kNone } source = Source::kNone;
  CaptureStats stats;
};

// Captures the appearance of every object of `dataset` seen in `frames` (ground-truth poses)
// and writes a models folder in the dataset's layout to `out_dir` (created; must not be the
// dataset's own models folder): YCB-Video: <name>/textured_simple.obj (the model's own file),
// a material naming texture_map.png (RGBA, alpha 0 where unseen) and points.xyz; BOP:
// obj_NNNNNN.ply with vertex colours (red green blue alpha) and models_info.json. Objects whose
// model has colour of its own keep it (copied as they are) unless `replace_own_colour`; objects
// no frame shows are copied without colour (with `replace_own_colour`, their own colour dropped
// too: the OBJ without its material, the PLY without vertex colours). Nothing is written unless everything was read.
StatusOr<std::vector<ObjectCapture>> CaptureDataset(const Dataset& dataset, std::span<const FrameKey> frames,
                                                    const CaptureOptions& options, bool replace_own_colour,
                                                    const std::string& out_dir);

}  // namespace mcpose::appearance
