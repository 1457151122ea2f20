// The SIMD vertex stage of the raster cores: ProjectVerticesSimd and CoverBoundSimd (raster.h)
// a vector of vertices at a time with Highway, dispatched at run time. ProjectVertices and
// CoverBound (raster.cc) are their references: the same float operations in the same order
// (Eigen's 3x3 product sums r0 x + (r1 y + r2 z)), so the results are bit-identical.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "render/raster.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/project_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace mcpose::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Whole vectors of vertices; returns how many were done (the caller does the rest).
size_t ProjectImpl(const float* xyz, size_t n, const float* R, const float* t, float fx, float fy, float cx,
                   float cy, float* uvz) {
  const hn::ScalableTag<float> df;
  const size_t lanes = hn::Lanes(df);
  decltype(hn::Zero(df)) r[9];
  for (int k = 0; k < 9; ++k) r[k] = hn::Set(df, R[k]);  // row-major
  const auto t0 = hn::Set(df, t[0]), t1 = hn::Set(df, t[1]), t2 = hn::Set(df, t[2]);
  const auto vfx = hn::Set(df, fx), vfy = hn::Set(df, fy), vcx = hn::Set(df, cx), vcy = hn::Set(df, cy);
  const auto one = hn::Set(df, 1.0f);
  size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    decltype(hn::Zero(df)) x, y, z;
    hn::LoadInterleaved3(df, xyz + 3 * i, x, y, z);
    const auto px = hn::Add(hn::Add(hn::Mul(r[0], x), hn::Add(hn::Mul(r[1], y), hn::Mul(r[2], z))), t0);
    const auto py = hn::Add(hn::Add(hn::Mul(r[3], x), hn::Add(hn::Mul(r[4], y), hn::Mul(r[5], z))), t1);
    const auto pz = hn::Add(hn::Add(hn::Mul(r[6], x), hn::Add(hn::Mul(r[7], y), hn::Mul(r[8], z))), t2);
    const auto inv_z = hn::Div(one, pz);
    const auto u = hn::Add(hn::Mul(hn::Mul(vfx, px), inv_z), vcx);
    const auto v = hn::Add(hn::Mul(hn::Mul(vfy, py), inv_z), vcy);
    hn::StoreInterleaved3(u, v, pz, df, uvz + 3 * i);
  }
  return i;
}

// Bounds of whole vectors of vertices: out = {min u, max u, min v, max v}; returns how many
// vertices were read, or SIZE_MAX if one of them has a coordinate that is not finite.
size_t BoundImpl(const float* uvz, size_t n, float* out) {
  const hn::ScalableTag<float> df;
  const size_t lanes = hn::Lanes(df);
  auto min_u = hn::Set(df, INFINITY), max_u = hn::Set(df, -INFINITY);
  auto min_v = min_u, max_v = max_u;
  const auto inf = hn::Set(df, INFINITY);
  auto finite = hn::Eq(min_u, min_u);  // all true
  size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    decltype(hn::Zero(df)) u, v, z;
    hn::LoadInterleaved3(df, uvz + 3 * i, u, v, z);
    // |x| < inf is false for infinities and NaN.
    finite = hn::And(finite, hn::And(hn::Lt(hn::Abs(u), inf), hn::Lt(hn::Abs(v), inf)));
    min_u = hn::Min(min_u, u), max_u = hn::Max(max_u, u);
    min_v = hn::Min(min_v, v), max_v = hn::Max(max_v, v);
  }
  if (!hn::AllTrue(df, finite)) return SIZE_MAX;
  out[0] = hn::GetLane(hn::MinOfLanes(df, min_u)), out[1] = hn::GetLane(hn::MaxOfLanes(df, max_u));
  out[2] = hn::GetLane(hn::MinOfLanes(df, min_v)), out[3] = hn::GetLane(hn::MaxOfLanes(df, max_v));
  return i;
}

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mcpose::render {

HWY_EXPORT(ProjectImpl);
HWY_EXPORT(BoundImpl);

void ProjectVerticesSimd(std::span<const Eigen::Vector3f> vertices_m, const Eigen::Matrix3f& R,
                         const Eigen::Vector3f& t, const RasterParams& params, std::span<ScreenVertex> out) {
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float) && sizeof(ScreenVertex) == 3 * sizeof(float));
  const size_t n = vertices_m.size();
  if (n == 0) return;
  const Eigen::Matrix<float, 3, 3, Eigen::RowMajor> rows = R;
  const size_t done = HWY_DYNAMIC_DISPATCH(ProjectImpl)(vertices_m.data()->data(), n, rows.data(), t.data(), params.fx,
                                                        params.fy, params.cx, params.cy, &out[0].u);
  ProjectVertices(vertices_m.subspan(done), R, t, params, out.subspan(done));
}

PixelRect CoverBoundSimd(std::span<const ScreenVertex> vertices, const PixelRect& box) {
  float b[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
  const size_t done = vertices.empty() ? 0 : HWY_DYNAMIC_DISPATCH(BoundImpl)(&vertices[0].u, vertices.size(), b);
  if (done == SIZE_MAX) return box;
  return CoverBoundFrom(vertices.subspan(done), box, b);
}

}  // namespace mcpose::render
#endif  // HWY_ONCE
