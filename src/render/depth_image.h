// A mesh's depth over a whole image: what the report draws and the VSD metric compares.
#pragma once

#include "mcpose/camera.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/se3.h"

namespace mcpose::render {

// The mesh's depth (metres) at pose T_cam_obj over the whole image, rendered by the scalar
// reference raster core with the estimator's camera convention (pixel centres at integer
// coordinates, back faces culled); 0 where the mesh does not cover a pixel.
DepthImage RenderDepth(const Mesh& mesh, const SE3& T_cam_obj, const Intrinsics& K);

}  // namespace mcpose::render
