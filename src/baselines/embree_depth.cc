#include <cmath>
#include <limits>

#include "baselines/depth_baseline.h"

#ifdef MCPOSE_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace mcpose::baselines {

#ifdef MCPOSE_HAVE_EMBREE
namespace {

class EmbreeDepth final : public DepthBaseline {
 public:
  EmbreeDepth(RTCDevice device, RTCScene scene) : device_(device), scene_(scene) {}
  ~EmbreeDepth() override {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  const char* name() const override { return "embree"; }
  bool thread_safe() const override { return true; }

  void Render(const Eigen::Matrix3f& R, const Eigen::Vector3f& t, const render::RasterParams& p,
              float* zbuf) override {
    // Rays in the object frame: origin -R^T t, direction R^T d_cam with d_cam.z = 1, so the
    // hit distance along the ray is the camera depth.
    const Eigen::Matrix3f Rt = R.transpose();
    const Eigen::Vector3f origin = -(Rt * t);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    const int w = p.box.width();
    for (int y = p.box.y0; y < p.box.y1; ++y) {
      for (int x = p.box.x0; x < p.box.x1; ++x) {
        const Eigen::Vector3f d_cam((x - p.cx) / p.fx, (y - p.cy) / p.fy, 1.0f);
        const Eigen::Vector3f d = Rt * d_cam;
        RTCRayHit rh;
        rh.ray.org_x = origin.x(), rh.ray.org_y = origin.y(), rh.ray.org_z = origin.z();
        rh.ray.dir_x = d.x(), rh.ray.dir_y = d.y(), rh.ray.dir_z = d.z();
        rh.ray.tnear = p.z_near_m;
        rh.ray.tfar = std::numeric_limits<float>::infinity();
        rh.ray.mask = 0xFFFFFFFFu;
        rh.ray.time = 0.f;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene_, &context, &rh);
        float z = std::numeric_limits<float>::infinity();
        if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
          // Back-face culling as the raster cores do: the geometric normal (object frame,
          // counter-clockwise winding) must face the ray.
          const bool front = rh.hit.Ng_x * d.x() + rh.hit.Ng_y * d.y() + rh.hit.Ng_z * d.z() < 0.f;
          if (front || !p.cull_backfaces) z = rh.ray.tfar;
        }
        zbuf[(y - p.box.y0) * w + (x - p.box.x0)] = z;
      }
    }
  }

 private:
  RTCDevice device_;
  RTCScene scene_;
};

}  // namespace

StatusOr<std::unique_ptr<DepthBaseline>> CreateEmbreeDepth(const Mesh& mesh) {
  MCPOSE_RETURN_IF_ERROR(mesh.Validate("embree baseline mesh"));
  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) return Internal("embree: rtcNewDevice failed (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), mesh.vertices_m.size()));
  for (size_t i = 0; i < mesh.vertices_m.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + k] = mesh.vertices_m[i][k];
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), mesh.triangles.size()));
  for (size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) idx[3 * i + k] = mesh.triangles[i][k];
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE) {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    return Internal("embree: building the BVH failed");
  }
  return std::unique_ptr<DepthBaseline>(new EmbreeDepth(device, scene));
}
#else
StatusOr<std::unique_ptr<DepthBaseline>> CreateEmbreeDepth(const Mesh&) {
  return InvalidArgument("embree baseline not compiled in (install libembree-dev and rebuild)");
}
#endif

StatusOr<std::unique_ptr<DepthBaseline>> CreateDepthBaseline(const std::string& name, const Mesh& mesh,
                                                            int max_width, int max_height) {
  if (name == "embree") return CreateEmbreeDepth(mesh);
  if (name == "osmesa") return CreateOsMesaDepth(mesh, max_width, max_height);
  return InvalidArgument("unknown baseline '" + name + "' (expected embree or osmesa)");
}

}  // namespace mcpose::baselines
