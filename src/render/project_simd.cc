// The SIMD vertex stage of the raster cores: ProjectVerticesSimd and CoverBoundSimd (raster.h),
// SnapVertices and ProjectSnapBoundSimd (raster_fixed.h), a vector of vertices at a time with
// Highway, dispatched at run time. ProjectVertices, CoverBound (raster.cc) and
// SnapVertexScalar (raster_fixed.h) are their references: the same float operations in the
// same order (Eigen's 3x3 product sums r0 x + (r1 y + r2 z)), so the results are bit-identical.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "render/raster.h"
#include "render/raster_fixed.h"

#include "render/simd_dispatch.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/project_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "render/project-inl.h"

HWY_BEFORE_NAMESPACE();
namespace mcpose::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The per-vector steps of the kernels below (Projector: render/project-inl.h).
template <class DF>
struct Bounds {
  hn::Vec<DF> min_u, max_u, min_v, max_v, inf;
  hn::Mask<DF> finite;
  explicit Bounds(DF df) {
    min_u = min_v = inf = hn::Set(df, INFINITY);
    max_u = max_v = hn::Set(df, -INFINITY);
    finite = hn::Eq(inf, inf);  // all true
  }
  HWY_INLINE void Add(hn::Vec<DF> u, hn::Vec<DF> v) {
    // |x| < inf is false for infinities and NaN.
    finite = hn::And(finite, hn::And(hn::Lt(hn::Abs(u), inf), hn::Lt(hn::Abs(v), inf)));
    min_u = hn::Min(min_u, u), max_u = hn::Max(max_u, u);
    min_v = hn::Min(min_v, v), max_v = hn::Max(max_v, v);
  }
  // out = {min u, max u, min v, max v}; false if a coordinate was not finite.
  HWY_INLINE bool Store(DF df, float* out) const {
    out[0] = hn::GetLane(hn::MinOfLanes(df, min_u)), out[1] = hn::GetLane(hn::MaxOfLanes(df, max_u));
    out[2] = hn::GetLane(hn::MinOfLanes(df, min_v)), out[3] = hn::GetLane(hn::MaxOfLanes(df, max_v));
    return hn::AllTrue(df, finite);
  }
};

// Round half to even of |f| < 2^22 by the 1.5 * 2^23 trick: exact on every target, and equal
// to std::lrint (round to nearest even, the default mode) that SnapVertexScalar uses. Larger
// values are outside kSnapBandPx (2^15 sub-pixels) and deferred, so their result is unused.
template <class DF, class V>
HWY_INLINE auto RoundToInt(DF df, V f) {
  const hn::RebindToSigned<DF> di;
  const auto magic = hn::Set(df, 12582912.0f);  // 1.5 * 2^23
  const auto rounded = hn::Sub(hn::Add(f, magic), magic);
  // Lanes beyond int (or NaN) are zeroed first: their result is unused, and converting them is
  // undefined on the scalar target.
  const auto in_int_range = hn::Lt(hn::Abs(rounded), hn::Set(df, 2147483520.0f));
  return hn::ConvertTo(di, hn::IfThenElseZero(in_int_range, rounded));
}

template <class DF>
struct Snapper {
  hn::Vec<DF> ox, oy, sub, band, near;
  hn::Vec<hn::RebindToSigned<DF>> low, deferred;
  Snapper(DF df, float ox_, float oy_, float z_near) {
    const hn::RebindToSigned<DF> di;
    ox = hn::Set(df, ox_), oy = hn::Set(df, oy_), sub = hn::Set(df, static_cast<float>(kSubpixelOne));
    band = hn::Set(df, kSnapBandPx), near = hn::Set(df, z_near);
    low = hn::Set(di, 0xffff), deferred = hn::Set(di, kSnappedDeferred);
  }
  // SnapVertexScalar of each lane.
  HWY_INLINE hn::Vec<hn::RebindToSigned<DF>> Snap(DF df, hn::Vec<DF> u, hn::Vec<DF> v, hn::Vec<DF> z) const {
    const hn::RebindToSigned<DF> di;
    const auto du = hn::Sub(u, ox), dv = hn::Sub(v, oy);
    // !(|d| < band) and !(z >= near): NaN coordinates and depths are deferred.
    const auto fast = hn::And(hn::And(hn::Lt(hn::Abs(du), band), hn::Lt(hn::Abs(dv), band)), hn::Ge(z, near));
    const auto X = RoundToInt(df, hn::Mul(du, sub)), Y = RoundToInt(df, hn::Mul(dv, sub));
    const auto p = hn::Or(hn::ShiftLeft<16>(X), hn::And(Y, low));
    return hn::IfThenElse(hn::RebindMask(di, fast), p, deferred);
  }
};

// The vertex pass over whole vectors of vertices: projected into uvz and, with kSnapBound,
// snapped into packed with their bounds in out[0..3] and in *finite whether all were finite.
// Returns how many were done (the caller does the rest).
template <bool kSnapBound>
HWY_INLINE size_t VertexPass(const float* xyz, size_t n, const float* R, const float* t, float fx, float fy,
                             float cx, float cy, float ox, float oy, float z_near, float* uvz, int32_t* packed,
                             float* out, bool* finite) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const size_t lanes = hn::Lanes(df);
  const Projector<decltype(df)> proj(df, R, t, fx, fy, cx, cy);
  const Snapper<decltype(df)> snap(df, ox, oy, z_near);
  Bounds<decltype(df)> bounds(df);
  size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    decltype(hn::Zero(df)) x, y, z, u, v, pz;
    hn::LoadInterleaved3(df, xyz + 3 * i, x, y, z);
    proj.Project(x, y, z, u, v, pz);
    hn::StoreInterleaved3(u, v, pz, df, uvz + 3 * i);
    if constexpr (kSnapBound) {
      hn::StoreU(snap.Snap(df, u, v, pz), di, packed + i);
      bounds.Add(u, v);
    }
  }
  if constexpr (kSnapBound) *finite = bounds.Store(df, out);
  return i;
}

size_t ProjectImpl(const float* xyz, size_t n, const float* R, const float* t, float fx, float fy, float cx,
                   float cy, float* uvz) {
  return VertexPass<false>(xyz, n, R, t, fx, fy, cx, cy, 0.f, 0.f, 0.f, uvz, nullptr, nullptr, nullptr);
}

// Bounds of whole vectors of vertices: out = {min u, max u, min v, max v}; returns how many
// vertices were read, or SIZE_MAX if one of them has a coordinate that is not finite.
size_t BoundImpl(const float* uvz, size_t n, float* out) {
  const hn::ScalableTag<float> df;
  const size_t lanes = hn::Lanes(df);
  Bounds<decltype(df)> bounds(df);
  size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    decltype(hn::Zero(df)) u, v, z;
    hn::LoadInterleaved3(df, uvz + 3 * i, u, v, z);
    bounds.Add(u, v);
  }
  return bounds.Store(df, out) ? i : SIZE_MAX;
}

void SnapVerticesImpl(const ScreenVertex* v, size_t n, float ox, float oy, float z_near, int32_t* packed) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const size_t lanes = hn::Lanes(df);
  const Snapper<decltype(df)> snap(df, ox, oy, z_near);
  const float* base = &v[0].u;
  size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    decltype(hn::Zero(df)) u, w, z;
    hn::LoadInterleaved3(df, base + 3 * i, u, w, z);
    hn::StoreU(snap.Snap(df, u, w, z), di, packed + i);
  }
  for (; i < n; ++i) packed[i] = SnapVertexScalar(v[i], ox, oy, z_near);  // the tail
}

// ProjectImpl, SnapVerticesImpl and BoundImpl in one pass.
size_t ProjectSnapBoundImpl(const float* xyz, size_t n, const float* R, const float* t, float fx, float fy, float cx,
                            float cy, float ox, float oy, float z_near, float* uvz, int32_t* packed, float* out,
                            bool* finite) {
  return VertexPass<true>(xyz, n, R, t, fx, fy, cx, cy, ox, oy, z_near, uvz, packed, out, finite);
}

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mcpose::render {

HWY_EXPORT(ProjectImpl);
HWY_EXPORT(BoundImpl);
HWY_EXPORT(SnapVerticesImpl);
HWY_EXPORT(ProjectSnapBoundImpl);

void ProjectVerticesSimd(std::span<const Eigen::Vector3f> vertices_m, const Eigen::Matrix3f& R,
                         const Eigen::Vector3f& t, const RasterParams& params, std::span<ScreenVertex> out) {
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float) && sizeof(ScreenVertex) == 3 * sizeof(float));
  const size_t n = vertices_m.size();
  if (n == 0) return;
  const Eigen::Matrix<float, 3, 3, Eigen::RowMajor> rows = R;
  const size_t done = MCPOSE_DYNAMIC_DISPATCH(ProjectImpl)(vertices_m.data()->data(), n, rows.data(), t.data(), params.fx,
                                                        params.fy, params.cx, params.cy, &out[0].u);
  ProjectVertices(vertices_m.subspan(done), R, t, params, out.subspan(done));
}

void SnapVertices(std::span<const ScreenVertex> vertices, const RasterParams& params, SnappedVertices* out) {
  const size_t n = vertices.size();
  out->packed.resize(n);
  if (n == 0) return;
  MCPOSE_DYNAMIC_DISPATCH(SnapVerticesImpl)(vertices.data(), n, static_cast<float>(params.box.x0),
                                         static_cast<float>(params.box.y0), params.z_near_m, out->packed.data());
}

PixelRect ProjectSnapBoundSimd(std::span<const Eigen::Vector3f> vertices_m, const Eigen::Matrix3f& R,
                               const Eigen::Vector3f& t, const RasterParams& params, std::span<ScreenVertex> out,
                               SnappedVertices* snapped) {
  const size_t n = vertices_m.size();
  snapped->packed.resize(n);
  if (n == 0) return PixelRect{};
  const Eigen::Matrix<float, 3, 3, Eigen::RowMajor> rows = R;
  const float ox = static_cast<float>(params.box.x0), oy = static_cast<float>(params.box.y0);
  float b[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
  bool finite = true;
  const size_t done = MCPOSE_DYNAMIC_DISPATCH(ProjectSnapBoundImpl)(
      vertices_m.data()->data(), n, rows.data(), t.data(), params.fx, params.fy, params.cx, params.cy, ox, oy,
      params.z_near_m, &out[0].u, snapped->packed.data(), b, &finite);
  ProjectVertices(vertices_m.subspan(done), R, t, params, out.subspan(done));
  for (size_t i = done; i < n; ++i) snapped->packed[i] = SnapVertexScalar(out[i], ox, oy, params.z_near_m);
  return finite ? CoverBoundFrom(out.subspan(done, n - done), params.box, b) : params.box;
}

PixelRect CoverBoundSimd(std::span<const ScreenVertex> vertices, const PixelRect& box) {
  float b[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
  const size_t done = vertices.empty() ? 0 : MCPOSE_DYNAMIC_DISPATCH(BoundImpl)(&vertices[0].u, vertices.size(), b);
  if (done == SIZE_MAX) return box;
  return CoverBoundFrom(vertices.subspan(done), box, b);
}

}  // namespace mcpose::render
#endif  // HWY_ONCE
