// Batched triangle setup of the fixed-point raster core (see raster_fixed.h): with the vertices
// snapped to the 1/16-pixel grid once per sample (SnapVertices, project_simd.cc), triangles
// classified a vector at a time with Highway, compiled for every target Highway knows here and
// dispatched at run time (once per call, not per triangle). SetupFixedTriangle
// (raster_fixed.cc) is its reference: every triangle this pass decides gets the reason
// SetupFixedTriangle gives it, and every other triangle is left to the per-triangle stage
// (SetupBatchedTriangle, raster_fixed.cc).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "render/raster_fixed.h"

#ifndef MCPOSE_RENDER_SETUP_SIMD_TABLES_
#define MCPOSE_RENDER_SETUP_SIMD_TABLES_
namespace mcpose::render::detail {
// For each mask of up to 8 lanes, the positions of its set lanes in order, one per nibble
// (the rest zero): the index table of CompressLanes below.
constexpr std::array<uint32_t, 256> MakeCompressNibbles() {
  std::array<uint32_t, 256> table{};
  for (uint32_t mask = 0; mask < 256; ++mask) {
    uint32_t packed = 0, k = 0;
    for (uint32_t lane = 0; lane < 8; ++lane) {
      if (mask & (1u << lane)) packed |= lane << (4 * k++);
    }
    table[mask] = packed;
  }
  return table;
}
inline constexpr std::array<uint32_t, 256> kCompressNibbles = MakeCompressNibbles();
}  // namespace mcpose::render::detail
#endif  // MCPOSE_RENDER_SETUP_SIMD_TABLES_

#include "render/simd_dispatch.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/setup_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace mcpose::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// hn::Compress(v, keep) for the lanes that matter here (the first CountTrue(keep); the others
// are unspecified). With 4 or 8 lanes, from the static nibble table: Highway's own table for
// them is a constexpr local array that GCC copies to the stack at every call (1 KiB with
// 8 lanes, a third of this function's instructions on the tomato can). AVX-512 compresses
// natively.
template <class DI>
HWY_INLINE hn::Vec<DI> CompressLanes(DI di, hn::Vec<DI> v, hn::Mask<DI> keep) {
  constexpr size_t kLanes = hn::MaxLanes(DI());
  if constexpr (kLanes == 4 || kLanes == 8) {
    const hn::RebindToUnsigned<DI> du;
    uint8_t bits[8] = {0};
    hn::StoreMaskBits(di, keep, bits);
    const auto packed = hn::Set(du, detail::kCompressNibbles[bits[0]]);
    const auto shifts = hn::Mul(hn::Iota(du, 0), hn::Set(du, 4));
    const auto idx = hn::And(hn::Shr(packed, shifts), hn::Set(du, kLanes - 1));
    return hn::TableLookupLanes(v, hn::IndicesFromVec(di, hn::BitCast(di, idx)));
  } else {
    return hn::Compress(v, keep);
  }
}

size_t ClassifyTrianglesImpl(const int32_t* packed, const uint32_t* tri, size_t n, int32_t box_w, int32_t box_h,
                             bool cull_backfaces, RasterCounters* stats, uint32_t* survivors) {
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
    // Compress in a register, then a plain whole-vector store (the buffer has the slack):
    // CompressStore's masked-store form (vpcompressd to memory) is slow on
    // AMD Zen 4, where it was 28 % of this function on the tomato can.
    const auto keep = hn::AndNot(decided, valid);
    hn::StoreU(CompressLanes(di, t, keep), di, reinterpret_cast<int32_t*>(survivors) + kept);
    kept += hn::CountTrue(di, keep);
  }
  stats->culled_backface += backface_n;
  stats->culled_outside_box += outside_n;
  stats->culled_between_pixels += between_n;
  return kept;
}

#if HWY_TARGET != HWY_SCALAR
// Stores the 128-bit blocks of v, block b at dst + b * block_stride (int32 units).
template <class DI>
HWY_INLINE void StoreBlocks(DI di, hn::Vec<DI> v, int32_t* dst, size_t block_stride) {
  constexpr size_t kLanes = hn::MaxLanes(DI());
  if constexpr (kLanes <= 4) {
    hn::StoreU(v, di, dst);
  } else {
    const hn::Half<DI> dh;
    StoreBlocks(dh, hn::LowerHalf(dh, v), dst, block_stride);
    StoreBlocks(dh, hn::UpperHalf(dh, v), dst + block_stride * (kLanes / 8), block_stride);
  }
}
#endif  // HWY_TARGET != HWY_SCALAR

// Writes lane j of the 16 field rows o[f] to out[j], for every lane, by 4 x 4 transposes
// within each 128-bit block; false (nothing written) where the lanes are fewer than 4 int32.
template <class DI, size_t kMax>
HWY_INLINE bool StoreTransposed(DI di, const int32_t (&o)[16][kMax], CompactTriangle* out) {
#if HWY_TARGET == HWY_SCALAR
  (void)di, (void)o, (void)out;
  return false;
#else
  constexpr size_t kLanes = hn::MaxLanes(DI());
  if constexpr (kLanes >= 4 && kLanes % 4 == 0) {
    static_assert(sizeof(CompactTriangle) == 16 * sizeof(int32_t));
    const hn::Repartition<int64_t, DI> d64;
    int32_t* dst = reinterpret_cast<int32_t*>(out);
    for (int g = 0; g < 4; ++g) {
      const auto a = hn::Load(di, o[4 * g]), b = hn::Load(di, o[4 * g + 1]);
      const auto c = hn::Load(di, o[4 * g + 2]), d = hn::Load(di, o[4 * g + 3]);
      const auto ab_lo = hn::BitCast(d64, hn::InterleaveLower(di, a, b));
      const auto ab_hi = hn::BitCast(d64, hn::InterleaveUpper(di, a, b));
      const auto cd_lo = hn::BitCast(d64, hn::InterleaveLower(di, c, d));
      const auto cd_hi = hn::BitCast(d64, hn::InterleaveUpper(di, c, d));
      // Row r holds lane r's fields 4g..4g+3 in its first block, lane r + 4's in the next.
      const decltype(a) rows[4] = {hn::BitCast(di, hn::InterleaveLower(d64, ab_lo, cd_lo)),
                                   hn::BitCast(di, hn::InterleaveUpper(d64, ab_lo, cd_lo)),
                                   hn::BitCast(di, hn::InterleaveLower(d64, ab_hi, cd_hi)),
                                   hn::BitCast(di, hn::InterleaveUpper(d64, ab_hi, cd_hi))};
      for (int r = 0; r < 4; ++r) StoreBlocks(di, rows[r], dst + 16 * r + 4 * g, 4 * 16);
    }
    return true;
  } else {
    (void)di, (void)o, (void)out;
    return false;
  }
#endif
}

// SetupSnappedTriangle for many triangles, a vector of int32 and float lanes at a time: the
// same integer tests and the same float operations in the same order, lane by lane, so every
// triangle it sets up is bit-identical to the scalar setup, written in CompactTriangle form.
// Integer arithmetic wraps in lanes whose spans exceed the SIMD rows' (those are not ready);
// in the others every value is exact in 32 bits (|X|, |Y| < 2^15, spans <= 2^14 sub-pixels:
// products below 2^29, edge functions below 2^31). Lanes that are not ready (a deferred
// vertex, degenerate, back-facing, outside the box, between pixels, too wide for the SIMD
// rows) get ready[j] = 0.
void SetupSurvivorsImpl(const int32_t* packed, const ScreenVertex* vertices, const uint32_t* tri,
                        const uint32_t* survivors, size_t count, int32_t box_w, int32_t box_h, bool cull_backfaces,
                        CompactTriangle* out, uint8_t* ready) {
  const hn::ScalableTag<int32_t> di;
  const hn::RebindToFloat<decltype(di)> df;
  const size_t lanes = hn::Lanes(di);
  constexpr size_t kMax = HWY_MAX_BYTES / sizeof(int32_t);
  static_assert(sizeof(ScreenVertex) == 3 * sizeof(float));
  const int32_t* tri_i = reinterpret_cast<const int32_t*>(tri);
  const int32_t* surv_i = reinterpret_cast<const int32_t*>(survivors);
  const float* z_base = &vertices[0].z;
  const auto three = hn::Set(di, 3), deferred = hn::Set(di, kSnappedDeferred);
  // The results in CompactTriangle's field order, a row of lanes per field (A, B, C as bits).
  constexpr int kFields = sizeof(CompactTriangle) / sizeof(int32_t);
  HWY_ALIGN int32_t o[kFields][kMax];
  HWY_ALIGN int32_t o_ready[kMax];
  const auto zero = hn::Zero(di), one = hn::Set(di, 1);
  const auto fzero = hn::Zero(df), fone = hn::Set(df, 1.0f);
  const auto x_last = hn::Set(di, box_w - 1), y_last = hn::Set(di, box_h - 1);
  const auto x_max = hn::Set(di, (box_w - 1) * kSubpixelOne), y_max = hn::Set(di, (box_h - 1) * kSubpixelOne);
  const auto simd_span = hn::Set(di, kMaxSimdSpanPx * kSubpixelOne + 1);
  const auto round_up = hn::Set(di, kSubpixelOne - 1);
  for (size_t first = 0; first < count; first += lanes) {
    // The survivors' vertices, gathered; lanes past the end repeat the last survivor.
    decltype(hn::Zero(di)) sv;
    if (first + lanes <= count) {
      sv = hn::LoadU(di, surv_i + first);
    } else {
      HWY_ALIGN int32_t tail[kMax];
      for (size_t j = 0; j < lanes; ++j) tail[j] = surv_i[std::min(first + j, count - 1)];
      sv = hn::Load(di, tail);
    }
    const auto t3 = hn::Mul(sv, three);
    const decltype(t3) v[3] = {hn::GatherIndex(di, tri_i, t3), hn::GatherIndex(di, tri_i, hn::Add(t3, one)),
                               hn::GatherIndex(di, tri_i, hn::Add(t3, hn::Set(di, 2)))};
    decltype(hn::Zero(di)) x[3], y[3];
    decltype(hn::Zero(df)) z[3];
    auto any_deferred = hn::Lt(zero, zero);
    for (int k = 0; k < 3; ++k) {
      const auto p = hn::GatherIndex(di, packed, v[k]);
      any_deferred = hn::Or(any_deferred, hn::Eq(p, deferred));
      x[k] = hn::ShiftRight<16>(p);
      y[k] = hn::ShiftRight<16>(hn::ShiftLeft<16>(p));
      z[k] = hn::GatherIndex(df, z_base, hn::Mul(v[k], three));
    }
    const auto X0 = x[0], Y0 = y[0];
    const auto Z0 = z[0];
    auto X1 = x[1], Y1 = y[1], X2 = x[2], Y2 = y[2];
    auto Z1 = z[1], Z2 = z[2];
    // Orientation; back faces swap b and c when not culled.
    auto area = hn::Sub(hn::Mul(hn::Sub(X1, X0), hn::Sub(Y2, Y0)), hn::Mul(hn::Sub(Y1, Y0), hn::Sub(X2, X0)));
    const auto pos = hn::Gt(area, zero);
    auto ok = hn::AndNot(any_deferred, hn::Ne(area, zero));
    if (cull_backfaces) {
      ok = hn::AndNot(pos, ok);
    } else {
      const auto sx = hn::IfThenElse(pos, X2, X1), sy = hn::IfThenElse(pos, Y2, Y1);
      const auto sz = hn::IfThenElse(hn::RebindMask(df, pos), Z2, Z1);
      X2 = hn::IfThenElse(pos, X1, X2), Y2 = hn::IfThenElse(pos, Y1, Y2);
      Z2 = hn::IfThenElse(hn::RebindMask(df, pos), Z1, Z2);
      X1 = sx, Y1 = sy, Z1 = sz;
      area = hn::IfThenElse(pos, hn::Neg(area), area);
    }
    // Bounding box, box and span tests, the pixel range (ceil and floor of multiples of 1/16).
    const auto min_x = hn::Min(hn::Min(X0, X1), X2), max_x = hn::Max(hn::Max(X0, X1), X2);
    const auto min_y = hn::Min(hn::Min(Y0, Y1), Y2), max_y = hn::Max(hn::Max(Y0, Y1), Y2);
    ok = hn::AndNot(hn::Or(hn::Or(hn::Lt(max_x, zero), hn::Gt(min_x, x_max)),
                           hn::Or(hn::Lt(max_y, zero), hn::Gt(min_y, y_max))), ok);
    const auto fits = hn::And(hn::Lt(hn::Sub(max_x, min_x), simd_span), hn::Lt(hn::Sub(max_y, min_y), simd_span));
    const auto x_lo = hn::Max(zero, hn::ShiftRight<kSubpixelBits>(hn::Add(min_x, round_up)));
    const auto x_hi = hn::Min(x_last, hn::ShiftRight<kSubpixelBits>(max_x));
    const auto y_lo = hn::Max(zero, hn::ShiftRight<kSubpixelBits>(hn::Add(min_y, round_up)));
    const auto y_hi = hn::Min(y_last, hn::ShiftRight<kSubpixelBits>(max_y));
    ok = hn::AndNot(hn::Or(hn::Gt(x_lo, x_hi), hn::Gt(y_lo, y_hi)), ok);

    // Edge functions of c->b, a->c, b->a (opposite a, b, c) and the 1/z plane, as the scalar.
    const decltype(X0) P0x[3] = {X2, X0, X1}, P0y[3] = {Y2, Y0, Y1}, P1x[3] = {X1, X2, X0}, P1y[3] = {Y1, Y2, Y0};
    const decltype(Z0) iz[3] = {hn::Div(fone, Z0), hn::Div(fone, Z1), hn::Div(fone, Z2)};
    const auto px0 = hn::ShiftLeft<kSubpixelBits>(x_lo), py0 = hn::ShiftLeft<kSubpixelBits>(y_lo);
    const auto inv_area = hn::Div(fone, hn::ConvertTo(df, hn::Neg(area)));
    auto A = fzero, B = fzero, C = fzero;
    for (int k = 0; k < 3; ++k) {
      const auto dx = hn::Sub(P1x[k], P0x[k]), dy = hn::Sub(P1y[k], P0y[k]);
      // The top-left bias: -1 unless dy > 0, or dy == 0 and dx < 0.
      const auto top_left = hn::Or(hn::And(hn::Eq(dy, zero), hn::Lt(dx, zero)), hn::Gt(dy, zero));
      const auto w = hn::Sub(hn::Sub(hn::Mul(dx, hn::Sub(py0, P0y[k])), hn::Mul(dy, hn::Sub(px0, P0x[k]))),
                             hn::IfThenZeroElse(top_left, one));
      const auto step_x = hn::ShiftLeft<kSubpixelBits>(hn::Neg(dy)), step_y = hn::ShiftLeft<kSubpixelBits>(dx);
      hn::Store(w, di, o[4 + k]);
      hn::Store(step_x, di, o[7 + k]);
      hn::Store(step_y, di, o[10 + k]);
      const auto wk = hn::Mul(iz[k], inv_area);
      A = hn::Add(A, hn::Mul(hn::ConvertTo(df, step_x), wk));
      B = hn::Add(B, hn::Mul(hn::ConvertTo(df, step_y), wk));
      const auto e_origin = hn::Sub(hn::Mul(dy, P0x[k]), hn::Mul(dx, P0y[k]));
      C = hn::Add(C, hn::Mul(hn::ConvertTo(df, e_origin), wk));
    }
    hn::Store(hn::BitCast(di, A), di, o[13]);
    hn::Store(hn::BitCast(di, B), di, o[14]);
    hn::Store(hn::BitCast(di, C), di, o[15]);
    hn::Store(x_lo, di, o[0]), hn::Store(x_hi, di, o[1]);
    hn::Store(y_lo, di, o[2]), hn::Store(y_hi, di, o[3]);
    hn::Store(hn::IfThenElseZero(hn::And(ok, fits), one), di, o_ready);
    if (first + lanes <= count && StoreTransposed(di, o, out + first)) {
      for (size_t j = 0; j < lanes; ++j) ready[first + j] = o_ready[j] != 0;
      continue;
    }
    for (size_t j = 0; j < lanes && first + j < count; ++j) {
      ready[first + j] = o_ready[j] != 0;
      if (!o_ready[j]) continue;
      int32_t* dst = reinterpret_cast<int32_t*>(&out[first + j]);
      for (int f = 0; f < kFields; ++f) dst[f] = o[f][j];
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mcpose::render {

HWY_EXPORT(ClassifyTrianglesImpl);
HWY_EXPORT(SetupSurvivorsImpl);

void SetupSurvivors(const SnappedVertices& snapped, std::span<const ScreenVertex> vertices,
                    std::span<const std::array<uint32_t, 3>> triangles, const RasterParams& params,
                    std::span<const uint32_t> survivors, CompactTriangle* out, uint8_t* ready) {
  if (survivors.empty()) return;
  MCPOSE_DYNAMIC_DISPATCH(SetupSurvivorsImpl)(snapped.packed.data(), vertices.data(), triangles.data()->data(),
                                          survivors.data(), survivors.size(), params.box.width(),
                                          params.box.height(), params.cull_backfaces, out, ready);
}

size_t ClassifyTriangles(const SnappedVertices& snapped, std::span<const std::array<uint32_t, 3>> triangles,
                         const RasterParams& params, RasterCounters* stats, std::vector<uint32_t>* survivors) {
  survivors->resize(triangles.size() + kSimdPadFloats);  // whole vectors are stored
  if (triangles.empty()) return 0;
  return MCPOSE_DYNAMIC_DISPATCH(ClassifyTrianglesImpl)(snapped.packed.data(), triangles.data()->data(),
                                                     triangles.size(), params.box.width(), params.box.height(),
                                                     params.cull_backfaces, stats, survivors->data());
}

}  // namespace mcpose::render
#endif  // HWY_ONCE
