// The per-vector projection shared by the SIMD vertex stage (project_simd.cc) and the SIMD
// cluster tests (clusters_simd.cc): X_cam = R X + t with Eigen's order of a 3 x 3 product,
// r0 x + (r1 y + r2 z), then + t; and u = (fx X) / Z + cx, v = (fy Y) / Z + cy as
// ProjectVertices computes them, so both kernels stay bit-identical to their scalar references.
// A Highway per-target header: include it after <hwy/highway.h> in a file compiled with
// foreach_target.
#if defined(MCPOSE_RENDER_PROJECT_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef MCPOSE_RENDER_PROJECT_INL_H_
#undef MCPOSE_RENDER_PROJECT_INL_H_
#else
#define MCPOSE_RENDER_PROJECT_INL_H_
#endif

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace mcpose::render {
namespace HWY_NAMESPACE {

template <class DF>
struct Projector {
  hwy::HWY_NAMESPACE::Vec<DF> r[9], t0, t1, t2, fx, fy, cx, cy, one;
  // R row-major.
  Projector(DF df, const float* R, const float* t, float fx_, float fy_, float cx_, float cy_) {
    namespace hn = hwy::HWY_NAMESPACE;
    for (int k = 0; k < 9; ++k) r[k] = hn::Set(df, R[k]);
    t0 = hn::Set(df, t[0]), t1 = hn::Set(df, t[1]), t2 = hn::Set(df, t[2]);
    fx = hn::Set(df, fx_), fy = hn::Set(df, fy_), cx = hn::Set(df, cx_), cy = hn::Set(df, cy_);
    one = hn::Set(df, 1.0f);
  }
  // Model-frame x, y, z to the camera frame.
  template <class V>
  HWY_INLINE void Transform(V x, V y, V z, V& px, V& py, V& pz) const {
    namespace hn = hwy::HWY_NAMESPACE;
    px = hn::Add(hn::Add(hn::Mul(r[0], x), hn::Add(hn::Mul(r[1], y), hn::Mul(r[2], z))), t0);
    py = hn::Add(hn::Add(hn::Mul(r[3], x), hn::Add(hn::Mul(r[4], y), hn::Mul(r[5], z))), t1);
    pz = hn::Add(hn::Add(hn::Mul(r[6], x), hn::Add(hn::Mul(r[7], y), hn::Mul(r[8], z))), t2);
  }
  // Model-frame x, y, z to pixel u, v and camera depth pz.
  template <class V>
  HWY_INLINE void Project(V x, V y, V z, V& u, V& v, V& pz) const {
    namespace hn = hwy::HWY_NAMESPACE;
    V px, py;
    Transform(x, y, z, px, py, pz);
    const auto inv_z = hn::Div(one, pz);
    u = hn::Add(hn::Mul(hn::Mul(fx, px), inv_z), cx);
    v = hn::Add(hn::Mul(hn::Mul(fy, py), inv_z), cy);
  }
};

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::render
HWY_AFTER_NAMESPACE();

#endif  // MCPOSE_RENDER_PROJECT_INL_H_ toggle
