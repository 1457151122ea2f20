// Comparison baselines for the raster cores (benchmarks only; never the estimator's renderer):
// the same hypotheses' depth rendered inside the same boxes by another engine, so that
// `mcpose bench` can time the same work and check that it *is* the same work (inlier counts).
//
//   EmbreeDepth  Embree 3 ray casting: one BVH of the mesh in the object frame, one primary ray
//                per box pixel centre transformed into the object frame per hypothesis
//                (rtcIntersect1, every ray's mask set), depth = camera z of the nearest hit.
//   OsMesaDepth  Mesa's llvmpipe OpenGL via OSMesa: the mesh drawn with a projection that maps
//                the box's pixel centres onto a box-sized viewport, back faces culled, then
//                the depth buffer read back (glReadPixels) and linearized.
// Both are optional at build time (MCPOSE_HAVE_EMBREE, MCPOSE_HAVE_OSMESA); Create fails with
// a clear message when the library was not compiled in.
#pragma once

#include <memory>
#include <span>
#include <string>

#include <Eigen/Core>

#include "mcpose/mesh.h"
#include "mcpose/status.h"
#include "render/raster.h"

namespace mcpose::baselines {

class DepthBaseline {
 public:
  virtual ~DepthBaseline() = default;
  virtual const char* name() const = 0;
  // Renders the mesh at X_cam = R X + t into `zbuf` (params.box sized, row-major), +inf where
  // nothing is hit. Not thread-safe unless thread_safe() (Embree is, an OSMesa context not).
  virtual void Render(const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                      const render::RasterParams& params, float* zbuf) = 0;
  virtual bool thread_safe() const = 0;
};

// `max_width` x `max_height` bounds the boxes OSMesa will render (the image size).
StatusOr<std::unique_ptr<DepthBaseline>> CreateEmbreeDepth(const Mesh& mesh);
StatusOr<std::unique_ptr<DepthBaseline>> CreateOsMesaDepth(const Mesh& mesh, int max_width,
                                                          int max_height);

// "embree" or "osmesa" -> the baseline; anything else is an InvalidArgument error.
StatusOr<std::unique_ptr<DepthBaseline>> CreateDepthBaseline(const std::string& name, const Mesh& mesh,
                                                            int max_width, int max_height);

}  // namespace mcpose::baselines
