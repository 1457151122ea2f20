#include "render/depth_image.h"

#include <cmath>
#include <vector>

#include "render/raster.h"

namespace mcpose::render {

DepthImage RenderDepth(const Mesh& mesh, const SE3& T_cam_obj, const Intrinsics& K) {
  RasterParams params;
  params.fx = static_cast<float>(K.fx), params.fy = static_cast<float>(K.fy);
  params.cx = static_cast<float>(K.cx), params.cy = static_cast<float>(K.cy);
  params.box = PixelRect{0, 0, K.width, K.height};
  params.cull_backfaces = true;
  std::vector<ScreenVertex> screen(mesh.vertices_m.size());
  ProjectVertices(mesh.vertices_m, T_cam_obj.R.cast<float>(), T_cam_obj.t.cast<float>(), params, screen);
  DepthImage out;
  out.width = K.width, out.height = K.height;
  out.depth_m.assign(static_cast<size_t>(params.box.area()), INFINITY);
  RasterizeDepthReference(screen, mesh.triangles, params, out.depth_m.data(), nullptr);
  for (float& z : out.depth_m)
    if (std::isinf(z)) z = 0;
  return out;
}

}  // namespace mcpose::render
