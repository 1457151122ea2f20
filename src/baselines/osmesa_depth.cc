#include <cmath>
#include <limits>
#include <vector>

#include "baselines/depth_baseline.h"

#ifdef MCPOSE_HAVE_OSMESA
#include <GL/gl.h>
#include <GL/osmesa.h>
#endif

namespace mcpose::baselines {

#ifdef MCPOSE_HAVE_OSMESA
namespace {

constexpr double kNearM = 0.05, kFarM = 10.0;

class OsMesaDepth final : public DepthBaseline {
 public:
  OsMesaDepth(OSMesaContext ctx, int w, int h, const Mesh& mesh)
      : ctx_(ctx), color_(static_cast<size_t>(w) * h * 4), width_(w), height_(h) {
    vertices_.reserve(mesh.vertices_m.size() * 3);
    for (const auto& v : mesh.vertices_m) vertices_.insert(vertices_.end(), {v.x(), v.y(), v.z()});
    for (const auto& t : mesh.triangles) indices_.insert(indices_.end(), {t[0], t[1], t[2]});
  }
  ~OsMesaDepth() override { OSMesaDestroyContext(ctx_); }
  const char* name() const override { return "osmesa"; }
  bool thread_safe() const override { return false; }

  bool MakeCurrent() {
    return OSMesaMakeCurrent(ctx_, color_.data(), GL_UNSIGNED_BYTE, width_, height_) == GL_TRUE;
  }

  void Render(const Eigen::Matrix3f& R, const Eigen::Vector3f& t, const render::RasterParams& p,
              float* zbuf) override {
    const int bw = p.box.width(), bh = p.box.height();
    // Window coordinates (x_w, y_w) = (u - x0 + 0.5, v - y0 + 0.5): GL samples pixel centres
    // at half-integers, ours are at integers. GL row j is box row j (no flip), so front faces
    // (negative area in y-down pixels) are clockwise in window coordinates.
    const double A = (kFarM + kNearM) / (kFarM - kNearM), B = -2.0 * kFarM * kNearM / (kFarM - kNearM);
    Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
    P(0, 0) = 2.0 * p.fx / bw, P(0, 2) = 2.0 * (p.cx - p.box.x0 + 0.5) / bw - 1.0;
    P(1, 1) = 2.0 * p.fy / bh, P(1, 2) = 2.0 * (p.cy - p.box.y0 + 0.5) / bh - 1.0;
    P(2, 2) = A, P(2, 3) = B;
    P(3, 2) = 1.0;
    Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
    M.topLeftCorner<3, 3>() = R.cast<double>();
    M.topRightCorner<3, 1>() = t.cast<double>();
    const Eigen::Matrix4f PM = (P * M).cast<float>();  // column-major, as GL wants

    glViewport(0, 0, bw, bh);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    if (p.cull_backfaces) {
      glEnable(GL_CULL_FACE);
      glFrontFace(GL_CW);
      glCullFace(GL_BACK);
    } else {
      glDisable(GL_CULL_FACE);
    }
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixf(PM.data());
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, vertices_.data());
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(indices_.size()), GL_UNSIGNED_INT, indices_.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, bw, bh, GL_DEPTH_COMPONENT, GL_FLOAT, zbuf);
    // Window depth d in [0, 1] -> NDC z = 2d - 1 = A + B / z_cam.
    const size_t n = static_cast<size_t>(bw) * bh;
    for (size_t i = 0; i < n; ++i) {
      const float d = zbuf[i];
      zbuf[i] = d >= 1.0f ? std::numeric_limits<float>::infinity()
                          : static_cast<float>(B / (2.0 * d - 1.0 - A));
    }
  }

 private:
  OSMesaContext ctx_;
  std::vector<unsigned char> color_;
  int width_, height_;
  std::vector<float> vertices_;
  std::vector<unsigned> indices_;
};

}  // namespace

StatusOr<std::unique_ptr<DepthBaseline>> CreateOsMesaDepth(const Mesh& mesh, int max_width, int max_height) {
  MCPOSE_RETURN_IF_ERROR(mesh.Validate("osmesa baseline mesh"));
  if (max_width <= 0 || max_height <= 0) return InvalidArgument("osmesa: the buffer size must be positive");
  OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!ctx) return Internal("osmesa: OSMesaCreateContextExt failed");
  auto r = std::make_unique<OsMesaDepth>(ctx, max_width, max_height, mesh);
  if (!r->MakeCurrent()) return Internal("osmesa: OSMesaMakeCurrent failed");
  return std::unique_ptr<DepthBaseline>(std::move(r));
}
#else
StatusOr<std::unique_ptr<DepthBaseline>> CreateOsMesaDepth(const Mesh&, int, int) {
  return InvalidArgument("osmesa baseline not compiled in (install libosmesa6-dev and rebuild)");
}
#endif

}  // namespace mcpose::baselines
