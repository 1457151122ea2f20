// Batched triangle setup of the fixed-point raster core (see raster_fixed.h): vertices snapped
// to the 1/16-pixel grid once per sample, then triangles classified a vector at a time with
// Highway, compiled for every target Highway knows here and dispatched at run time (once per
// call, not per triangle). SetupFixedTriangle (raster_fixed.cc) is its reference: every
// triangle this pass decides gets the reason SetupFixedTriangle gives it, and every other
// triangle is left to the per-triangle stage (SetupBatchedTriangle, raster_fixed.cc).
#include <cmath>
#include <cstdint>

#include "render/raster_fixed.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/setup_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace mcpose::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Round half to even of |f| < 2^22 by the 1.5 * 2^23 trick: exact on every target, and equal
// to std::lrint (round to nearest even, the default mode) that SetupFixedTriangle uses. Larger
// values are outside kSnapBandPx (2^15 sub-pixels) and deferred, so their result is unused.
template <class DF, class V>
HWY_INLINE auto RoundToInt(DF df, V f) {
  const hn::RebindToSigned<DF> di;
  const auto magic = hn::Set(df, 12582912.0f);  // 1.5 * 2^23
  return hn::ConvertTo(di, hn::Sub(hn::Add(f, magic), magic));
}

void SnapVerticesImpl(const ScreenVertex* v, size_t n, float ox, float oy, float z_near, int32_t* packed) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const size_t lanes = hn::Lanes(df);
  const auto vox = hn::Set(df, ox), voy = hn::Set(df, oy), sub = hn::Set(df, static_cast<float>(kSubpixelOne));
  const auto band = hn::Set(df, kSnapBandPx), near = hn::Set(df, z_near);
  const auto low = hn::Set(di, 0xffff), deferred = hn::Set(di, kSnappedDeferred);
  const float* base = &v[0].u;
  size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    decltype(hn::Zero(df)) u, w, z;
    hn::LoadInterleaved3(df, base + 3 * i, u, w, z);
    const auto du = hn::Sub(u, vox), dv = hn::Sub(w, voy);
    // !(|d| < band) and !(z >= near): NaN coordinates and depths are deferred.
    const auto fast = hn::And(hn::And(hn::Lt(hn::Abs(du), band), hn::Lt(hn::Abs(dv), band)), hn::Ge(z, near));
    const auto X = RoundToInt(df, hn::Mul(du, sub)), Y = RoundToInt(df, hn::Mul(dv, sub));
    const auto p = hn::Or(hn::ShiftLeft<16>(X), hn::And(Y, low));
    hn::StoreU(hn::IfThenElse(hn::RebindMask(di, fast), p, deferred), di, packed + i);
  }
  for (; i < n; ++i) packed[i] = SnapVertexScalar(v[i], ox, oy, z_near);  // the tail
}

size_t ClassifyTrianglesImpl(const int32_t* packed, const uint32_t* tri, size_t n, int32_t box_w, int32_t box_h,
                             bool cull_backfaces, RasterStats* stats, uint32_t* survivors) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(di));
  const int32_t* tri_i = reinterpret_cast<const int32_t*>(tri);
  const auto iota = hn::Iota(di, 0), zero = hn::Zero(di);
  const auto last = hn::Set(di, static_cast<int32_t>(n) - 1), count = hn::Set(di, static_cast<int32_t>(n));
  const auto deferred_x = hn::Set(di, kSnappedDeferred >> 16);
  const auto x_max = hn::Set(di, (box_w - 1) * kSubpixelOne), y_max = hn::Set(di, (box_h - 1) * kSubpixelOne);
  const auto span_max = hn::Set(di, kMaxSpanPx * kSubpixelOne);
  const auto round_up = hn::Set(di, kSubpixelOne - 1);
  const auto last_x = hn::Set(di, box_w - 1), last_y = hn::Set(di, box_h - 1);
  // |area_float - area| <= 2^-23 (|p| + |q|) + ulp: a wider margin leaves the sign certain.
  const auto tol = hn::Set(df, 1.0f / (1 << 21));
  int64_t backface_n = 0, outside_n = 0, between_n = 0;
  size_t kept = 0;
  for (int32_t first = 0; first < static_cast<int32_t>(n); first += lanes) {
    const auto t = hn::Add(hn::Set(di, first), iota);
    const auto valid = hn::Lt(t, count);
    decltype(hn::Zero(di)) i0, i1, i2;
    if (first + lanes <= static_cast<int32_t>(n)) {
      hn::LoadInterleaved3(di, tri_i + 3 * first, i0, i1, i2);
    } else {  // the tail: gathered, its empty lanes repeating the last triangle
      const auto t3 = hn::Mul(hn::Min(t, last), hn::Set(di, 3));
      i0 = hn::GatherIndex(di, tri_i, t3);
      i1 = hn::GatherIndex(di, tri_i, hn::Add(t3, hn::Set(di, 1)));
      i2 = hn::GatherIndex(di, tri_i, hn::Add(t3, hn::Set(di, 2)));
    }
    const auto p0 = hn::GatherIndex(di, packed, i0), p1 = hn::GatherIndex(di, packed, i1),
               p2 = hn::GatherIndex(di, packed, i2);
    const auto x0 = hn::ShiftRight<16>(p0), x1 = hn::ShiftRight<16>(p1), x2 = hn::ShiftRight<16>(p2);
    const auto y0 = hn::ShiftRight<16>(hn::ShiftLeft<16>(p0)), y1 = hn::ShiftRight<16>(hn::ShiftLeft<16>(p1)),
               y2 = hn::ShiftRight<16>(hn::ShiftLeft<16>(p2));
    // A deferred vertex (near plane, far off the box, not finite) leaves the triangle to
    // SetupFixedTriangle, which tests the near plane first, as the reference order requires.
    const auto deferred = hn::Or(hn::Or(hn::Eq(x0, deferred_x), hn::Eq(x1, deferred_x)), hn::Eq(x2, deferred_x));
    const auto plain = hn::AndNot(deferred, valid);

    // Orientation: area = (X1 - X0)(Y2 - Y0) - (Y1 - Y0)(X2 - X0) in float; only a sign that
    // the rounding cannot flip is used (zero and near-zero areas are left to the scalar setup).
    const auto p = hn::Mul(hn::ConvertTo(df, hn::Sub(x1, x0)), hn::ConvertTo(df, hn::Sub(y2, y0)));
    const auto q = hn::Mul(hn::ConvertTo(df, hn::Sub(y1, y0)), hn::ConvertTo(df, hn::Sub(x2, x0)));
    const auto area = hn::Sub(p, q);
    const auto margin = hn::Mul(hn::Add(hn::Abs(p), hn::Abs(q)), tol);
    const auto pos = hn::RebindMask(di, hn::Gt(area, margin));
    const auto neg = hn::RebindMask(di, hn::Lt(area, hn::Neg(margin)));
    const auto backface = hn::And(plain, cull_backfaces ? pos : hn::Lt(iota, zero));
    const auto oriented = hn::And(plain, cull_backfaces ? neg : hn::Or(pos, neg));

    // The snapped bounding box against the box, then the pixel centres it holds.
    const auto min_x = hn::Min(hn::Min(x0, x1), x2), max_x = hn::Max(hn::Max(x0, x1), x2);
    const auto min_y = hn::Min(hn::Min(y0, y1), y2), max_y = hn::Max(hn::Max(y0, y1), y2);
    const auto off_box = hn::Or(hn::Or(hn::Lt(max_x, zero), hn::Gt(min_x, x_max)),
                                hn::Or(hn::Lt(max_y, zero), hn::Gt(min_y, y_max)));
    const auto outside = hn::And(oriented, off_box);
    const auto wide = hn::Or(hn::Gt(hn::Sub(max_x, min_x), span_max), hn::Gt(hn::Sub(max_y, min_y), span_max));
    const auto x_lo = hn::Max(zero, hn::ShiftRight<kSubpixelBits>(hn::Add(min_x, round_up)));
    const auto x_hi = hn::Min(last_x, hn::ShiftRight<kSubpixelBits>(max_x));
    const auto y_lo = hn::Max(zero, hn::ShiftRight<kSubpixelBits>(hn::Add(min_y, round_up)));
    const auto y_hi = hn::Min(last_y, hn::ShiftRight<kSubpixelBits>(max_y));
    const auto empty = hn::Or(hn::Gt(x_lo, x_hi), hn::Gt(y_lo, y_hi));
    const auto between = hn::AndNot(hn::Or(off_box, wide), hn::And(oriented, empty));

    const auto decided = hn::Or(backface, hn::Or(outside, between));
    backface_n += static_cast<int64_t>(hn::CountTrue(di, backface));
    outside_n += static_cast<int64_t>(hn::CountTrue(di, outside));
    between_n += static_cast<int64_t>(hn::CountTrue(di, between));
    kept += hn::CompressStore(t, hn::AndNot(decided, valid), di, reinterpret_cast<int32_t*>(survivors) + kept);
  }
  stats->culled_backface += backface_n;
  stats->culled_outside_box += outside_n;
  stats->culled_between_pixels += between_n;
  return kept;
}

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mcpose::render {

HWY_EXPORT(SnapVerticesImpl);
HWY_EXPORT(ClassifyTrianglesImpl);

void SnapVertices(std::span<const ScreenVertex> vertices, const RasterParams& params, SnappedVertices* out) {
  const size_t n = vertices.size();
  out->packed.resize(n);
  if (n == 0) return;
  HWY_DYNAMIC_DISPATCH(SnapVerticesImpl)(vertices.data(), n, static_cast<float>(params.box.x0),
                                         static_cast<float>(params.box.y0), params.z_near_m, out->packed.data());
}

size_t ClassifyTriangles(const SnappedVertices& snapped, std::span<const std::array<uint32_t, 3>> triangles,
                         const RasterParams& params, RasterStats* stats, std::vector<uint32_t>* survivors) {
  survivors->resize(triangles.size() + kSimdPadFloats);  // CompressStore writes whole vectors
  if (triangles.empty()) return 0;
  return HWY_DYNAMIC_DISPATCH(ClassifyTrianglesImpl)(snapped.packed.data(), triangles.data()->data(),
                                                     triangles.size(), params.box.width(), params.box.height(),
                                                     params.cull_backfaces, stats, survivors->data());
}

}  // namespace mcpose::render
#endif  // HWY_ONCE
