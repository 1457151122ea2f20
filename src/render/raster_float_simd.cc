// The float raster core a SIMD vector at a time: RasterizeDepthFloatSimd (raster.h), with
// Highway, compiled for every target Highway knows here and dispatched at run time.
// RasterizeDepthReference (raster.cc) is its reference, and this kernel is that reference
// reorganised, not approximated: every float operation is the reference's, in the same order
// (the build contracts nothing into FMA), so z-buffers and statistics are bit-identical.
//  1. Classification, a vector of triangles at a time: the near plane, the signed area and
//     its sign, the box test and the pixel range, as the reference decides them one by one.
//  2. Pixels, a vector at a time, for each triangle with pixel centres in its range: blocks of
//     2 or 4 rows in a vector for triangles at most 4 or 8 pixels wide, rows of whole vectors
//     otherwise. At each pixel, the reference's three edge functions, the top-left rule, the
//     perspective-correct depth ((wa iza + wb izb) + wc izc) inv_area, 1 / that, and the depth
//     test.
// The last vector of a row may load and store back (unchanged) pixels past the triangle's last
// one: the z-buffer needs kSimdPadFloats of slack after the box.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "render/raster.h"

#include "render/simd_dispatch.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/raster_float_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "render/blocks-inl.h"

HWY_BEFORE_NAMESPACE();
namespace mcpose::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// One triangle that reached the rows: its vertices after the reference's back-face swap
// (edge functions positive inside), 1/z at each, 1 / -area, the top-left flags of the edges
// opposite a, b and c, and the range of pixel centres (absolute pixels, inclusive).
struct FloatTriangle {
  float au, av, bu, bv, cu, cv;
  float iza, izb, izc, inv_area;
  bool tl_bc, tl_ca, tl_ab;
  int32_t x_lo, x_hi, y_lo, y_hi;
};

// The reference's per-pixel operations on a vector of pixels, each lane at its own (px, py):
// the three edge functions (the row factors ra, rb, rc = (bx - ax)(py - ay) given), the
// top-left rule, and the depth 1 / (((wa iza + wb izb) + wc izc) inv_area) where covered.
template <class DF>
struct FloatLanes {
  hn::Vec<DF> ka, kb, kc, ox_a, ox_b, ox_c, iza, izb, izc, inv_area, one, zero;
  hn::Mask<DF> tl_a, tl_b, tl_c;
  FloatLanes(DF df, const FloatTriangle& t) {
    // Edge(a, b, p) = (bx - ax)(py - ay) - (by - ay)(px - ax) of the reference, for the edges
    // c -> b (the weight of a), a -> c (of b) and b -> a (of c).
    ka = hn::Set(df, t.bv - t.cv), kb = hn::Set(df, t.cv - t.av), kc = hn::Set(df, t.av - t.bv);
    ox_a = hn::Set(df, t.cu), ox_b = hn::Set(df, t.au), ox_c = hn::Set(df, t.bu);
    iza = hn::Set(df, t.iza), izb = hn::Set(df, t.izb), izc = hn::Set(df, t.izc);
    inv_area = hn::Set(df, t.inv_area), one = hn::Set(df, 1.0f), zero = hn::Zero(df);
    // The top-left rule: an edge that owns the pixels on it also accepts w == 0.
    const auto all = hn::Eq(zero, zero), none = hn::Lt(zero, zero);
    tl_a = t.tl_bc ? all : none, tl_b = t.tl_ca ? all : none, tl_c = t.tl_ab ? all : none;
  }
  // The covered lanes among `lanes_in`, and their depths in *z.
  HWY_INLINE hn::Mask<DF> Shade(hn::Vec<DF> ra, hn::Vec<DF> rb, hn::Vec<DF> rc, hn::Vec<DF> px,
                                hn::Mask<DF> lanes_in, hn::Vec<DF>* z) const {
    const auto wa = hn::Sub(ra, hn::Mul(ka, hn::Sub(px, ox_a)));
    const auto wb = hn::Sub(rb, hn::Mul(kb, hn::Sub(px, ox_b)));
    const auto wc = hn::Sub(rc, hn::Mul(kc, hn::Sub(px, ox_c)));
    const auto in_a = hn::Or(hn::Gt(wa, zero), hn::And(hn::Eq(wa, zero), tl_a));
    const auto in_b = hn::Or(hn::Gt(wb, zero), hn::And(hn::Eq(wb, zero), tl_b));
    const auto in_c = hn::Or(hn::Gt(wc, zero), hn::And(hn::Eq(wc, zero), tl_c));
    const auto inv_z = hn::Mul(hn::Add(hn::Add(hn::Mul(wa, iza), hn::Mul(wb, izb)), hn::Mul(wc, izc)), inv_area);
    *z = hn::Div(one, inv_z);
    return hn::And(hn::And(in_a, in_b), hn::And(in_c, lanes_in));
  }
};

template <class DF>
using LaneCounts = hn::Vec<hn::RebindToSigned<DF>>;

// A row at a time, a vector of the row's pixels at a time; covered pixels counted per lane.
template <class DF>
HWY_INLINE LaneCounts<DF> FillFloatRows(DF df, const FloatTriangle& t, const PixelRect& box, float* zbuf) {
  const hn::RebindToSigned<DF> di;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(df));
  const FloatLanes<DF> f(df, t);
  const auto iota = hn::Iota(di, 0);
  auto covered = hn::Zero(di);
  for (int32_t y = t.y_lo; y <= t.y_hi; ++y) {
    const float py = static_cast<float>(y);
    const auto ra = hn::Set(df, (t.bu - t.cu) * (py - t.cv));
    const auto rb = hn::Set(df, (t.cu - t.au) * (py - t.av));
    const auto rc = hn::Set(df, (t.au - t.bu) * (py - t.bv));
    float* row = zbuf + static_cast<ptrdiff_t>(y - box.y0) * box.width();
    for (int32_t x = t.x_lo; x <= t.x_hi; x += lanes) {
      const auto px = hn::ConvertTo(df, hn::Add(hn::Set(di, x), iota));
      const auto in_row = hn::RebindMask(df, hn::FirstN(di, static_cast<size_t>(t.x_hi - x + 1)));
      hn::Vec<DF> z;
      const auto inside = f.Shade(ra, rb, rc, px, in_row, &z);
      covered = hn::Sub(covered, hn::VecFromMask(di, hn::RebindMask(di, inside)));
      // Lanes past the row's end: the slack or the next row, loaded but not stored.
      const auto old = hn::LoadU(df, row + (x - box.x0));
      hn::BlendedStore(z, hn::And(inside, hn::Lt(z, old)), df, row + (x - box.x0));
    }
  }
  return covered;
}

#if HWY_TARGET != HWY_SCALAR  // one lane: no blocks
// Triangles at most kW pixels wide, lanes / kW rows per vector: lane i is pixel
// (x_lo + i % kW, y + i / kW), with the reference's operations at that pixel. Rows past y_hi
// are masked out and alias row y_hi; lanes past x_hi are stored back unchanged, which needs
// the z-buffer's rows at least kW pixels apart (a row's lanes past the triangle then end
// before the next row's pixels of the block) and its slack after the last row.
template <size_t kW, class DF>
HWY_INLINE LaneCounts<DF> FillFloatBlocks(DF df, const FloatTriangle& t, const PixelRect& box, float* zbuf) {
  const hn::RebindToSigned<DF> di;
  constexpr int32_t kRows = static_cast<int32_t>(hn::MaxLanes(DF()) / kW);
  const int stride = box.width();
  const FloatLanes<DF> f(df, t);
  const auto lane = hn::Iota(di, 0);
  const auto lx = hn::And(lane, hn::Set(di, static_cast<int32_t>(kW - 1)));
  const auto px = hn::ConvertTo(df, hn::Add(lx, hn::Set(di, t.x_lo)));
  const auto in_span = hn::Lt(lx, hn::Set(di, t.x_hi - t.x_lo + 1));
  const auto dua = hn::Set(df, t.bu - t.cu), dub = hn::Set(df, t.cu - t.au), duc = hn::Set(df, t.au - t.bu);
  const auto cv = hn::Set(df, t.cv), av = hn::Set(df, t.av), bv = hn::Set(df, t.bv);
  auto y_lane = hn::Add(hn::ShiftRight<hwy::CeilLog2(kW)>(lane), hn::Set(di, t.y_lo));
  const auto y_end = hn::Set(di, t.y_hi + 1), rows_step = hn::Set(di, kRows);
  auto covered = hn::Zero(di);
  float* rows[kRows];
  float* row = zbuf + static_cast<ptrdiff_t>(t.y_lo - box.y0) * stride + (t.x_lo - box.x0);
  for (int32_t y = t.y_lo; y <= t.y_hi; y += kRows, row += static_cast<ptrdiff_t>(kRows) * stride) {
    rows[0] = row;
    for (int32_t r = 1; r < kRows; ++r) rows[r] = y + r <= t.y_hi ? rows[r - 1] + stride : rows[r - 1];
    const auto py = hn::ConvertTo(df, y_lane);
    const auto ra = hn::Mul(dua, hn::Sub(py, cv)), rb = hn::Mul(dub, hn::Sub(py, av)),
               rc = hn::Mul(duc, hn::Sub(py, bv));
    hn::Vec<DF> z;
    const auto inside = f.Shade(ra, rb, rc, px, hn::RebindMask(df, hn::And(in_span, hn::Lt(y_lane, y_end))), &z);
    covered = hn::Sub(covered, hn::VecFromMask(di, hn::RebindMask(di, inside)));
    const auto old = LoadBlock<kW>(df, rows);
    StoreBlock<kW>(df, hn::IfThenElse(hn::And(inside, hn::Lt(z, old)), z, old), rows);
    y_lane = hn::Add(y_lane, rows_step);
  }
  return covered;
}
#endif  // HWY_TARGET != HWY_SCALAR

// Blocks for triangles at most 4 (or, with 16 lanes, 8) pixels wide where a vector holds at
// least two of their rows and the box is at least that wide; rows otherwise.
HWY_INLINE LaneCounts<hn::ScalableTag<float>> FillFloatTriangle(const FloatTriangle& t, const PixelRect& box,
                                                                float* zbuf) {
  const hn::ScalableTag<float> df;
#if HWY_TARGET != HWY_SCALAR
  constexpr size_t kLanes = hn::MaxLanes(df);
  const int32_t span = t.x_hi - t.x_lo + 1;
  if constexpr (kLanes >= 8 && kLanes <= 16) {
    if (span <= 4 && box.width() >= 4) return FillFloatBlocks<4>(df, t, box, zbuf);
  }
  if constexpr (kLanes == 16) {
    if (span <= 8 && box.width() >= 8) return FillFloatBlocks<8>(df, t, box, zbuf);
  }
#endif
  return FillFloatRows(df, t, box, zbuf);
}

// The classification of the reference, a vector of triangles at a time, then the rows of the
// triangles that reach them. `n` is a multiple of the lane count; uvz holds u, v, z per vertex.
void RasterizeFloatImpl(const float* uvz, const uint32_t* tri, size_t n, const RasterParams& p, float* zbuf,
                        RasterCounters* stats) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  using VI = hn::Vec<decltype(di)>;
  constexpr size_t kMaxLanes = hn::MaxLanes(df);
  const size_t lanes = hn::Lanes(df);
  const PixelRect& box = p.box;
  const int32_t* tri_i = reinterpret_cast<const int32_t*>(tri);
  const auto three = hn::Set(di, 3);
  const auto z_near = hn::Set(df, p.z_near_m), zero = hn::Zero(df), inf = hn::Set(df, INFINITY);
  const auto one = hn::Set(df, 1.0f);
  // The box in float, as the reference's int-to-float comparisons convert it.
  const auto fx0 = hn::Set(df, static_cast<float>(box.x0)), fy0 = hn::Set(df, static_cast<float>(box.y0));
  const auto fx_last = hn::Set(df, static_cast<float>(box.x1 - 1)), fy_last = hn::Set(df, static_cast<float>(box.y1 - 1));
  const auto fx0_m1 = hn::Set(df, box.x0 - 1.f), fy0_m1 = hn::Set(df, box.y0 - 1.f);
  const auto fx1 = hn::Set(df, static_cast<float>(box.x1)), fy1 = hn::Set(df, static_cast<float>(box.y1));
  const auto ix0 = hn::Set(di, box.x0), iy0 = hn::Set(di, box.y0);
  const auto ix_last = hn::Set(di, box.x1 - 1), iy_last = hn::Set(di, box.y1 - 1);

  HWY_ALIGN float lane_f[10][kMaxLanes];
  HWY_ALIGN int32_t lane_i[7][kMaxLanes];
  RasterCounters s;
  for (size_t first = 0; first < n; first += lanes) {
    VI i0, i1, i2;
    hn::LoadInterleaved3(di, tri_i + 3 * first, i0, i1, i2);
    i0 = hn::Mul(i0, three), i1 = hn::Mul(i1, three), i2 = hn::Mul(i2, three);
    const auto au = hn::GatherIndex(df, uvz, i0), av = hn::GatherIndex(df, uvz + 1, i0),
               az = hn::GatherIndex(df, uvz + 2, i0);
    auto bu = hn::GatherIndex(df, uvz, i1), bv = hn::GatherIndex(df, uvz + 1, i1), bz = hn::GatherIndex(df, uvz + 2, i1);
    auto cu = hn::GatherIndex(df, uvz, i2), cv = hn::GatherIndex(df, uvz + 1, i2), cz = hn::GatherIndex(df, uvz + 2, i2);

    // Near plane, then degenerate (zero or not finite area), then back faces.
    const auto near = hn::Or(hn::Or(hn::Lt(az, z_near), hn::Lt(bz, z_near)), hn::Lt(cz, z_near));
    auto area = hn::Sub(hn::Mul(hn::Sub(bu, au), hn::Sub(cv, av)), hn::Mul(hn::Sub(bv, av), hn::Sub(cu, au)));
    const auto degenerate = hn::AndNot(near, hn::Or(hn::Eq(area, zero), hn::Not(hn::Lt(hn::Abs(area), inf))));
    auto alive = hn::Not(hn::Or(near, degenerate));
    const auto back = hn::And(alive, hn::Gt(area, zero));
    auto backface = hn::Lt(zero, zero);
    if (p.cull_backfaces) {
      backface = back;
      alive = hn::AndNot(back, alive);
    } else {  // the back face drawn with b and c swapped, its area negated
      const auto su = hn::IfThenElse(back, cu, bu), sv = hn::IfThenElse(back, cv, bv),
                 sz = hn::IfThenElse(back, cz, bz);
      cu = hn::IfThenElse(back, bu, cu), cv = hn::IfThenElse(back, bv, cv), cz = hn::IfThenElse(back, bz, cz);
      bu = su, bv = sv, bz = sz;
      area = hn::IfThenElse(back, hn::Neg(area), area);
    }
    // (Non-degenerate areas have finite vertices: the bounds below are finite.)
    const auto min_u = hn::Min(hn::Min(au, bu), cu), max_u = hn::Max(hn::Max(au, bu), cu);
    const auto min_v = hn::Min(hn::Min(av, bv), cv), max_v = hn::Max(hn::Max(av, bv), cv);
    const auto outside = hn::And(alive, hn::Or(hn::Or(hn::Lt(max_u, fx0), hn::Gt(min_u, fx_last)),
                                               hn::Or(hn::Lt(max_v, fy0), hn::Gt(min_v, fy_last))));
    alive = hn::AndNot(outside, alive);
    const auto x_lo = hn::Max(ix0, hn::ConvertTo(di, hn::Ceil(hn::Max(min_u, fx0_m1))));
    const auto x_hi = hn::Min(ix_last, hn::ConvertTo(di, hn::Floor(hn::Min(max_u, fx1))));
    const auto y_lo = hn::Max(iy0, hn::ConvertTo(di, hn::Ceil(hn::Max(min_v, fy0_m1))));
    const auto y_hi = hn::Min(iy_last, hn::ConvertTo(di, hn::Floor(hn::Min(max_v, fy1))));
    // No pixel centre in the range: covers nothing (the reference's rows find none).
    const auto empty = hn::RebindMask(df, hn::Or(hn::Gt(x_lo, x_hi), hn::Gt(y_lo, y_hi)));
    const auto live = hn::AndNot(empty, alive);

    s.triangles_in += static_cast<int64_t>(lanes);
    s.culled_near += static_cast<int64_t>(hn::CountTrue(df, near));
    s.culled_degenerate += static_cast<int64_t>(hn::CountTrue(df, degenerate));
    s.culled_backface += static_cast<int64_t>(hn::CountTrue(df, backface));
    s.culled_outside_box += static_cast<int64_t>(hn::CountTrue(df, outside));
    s.culled_between_pixels += static_cast<int64_t>(hn::CountTrue(df, hn::And(alive, empty)));
    if (hn::AllFalse(df, live)) continue;

    // The per-triangle constants of the reference, for every lane (only live lanes are used).
    const auto tl = [&](hn::Vec<decltype(df)> dx, hn::Vec<decltype(df)> dy) {
      return hn::VecFromMask(di, hn::RebindMask(di, hn::Or(hn::And(hn::Eq(dy, zero), hn::Lt(dx, zero)), hn::Gt(dy, zero))));
    };
    hn::Store(au, df, lane_f[0]), hn::Store(av, df, lane_f[1]), hn::Store(bu, df, lane_f[2]);
    hn::Store(bv, df, lane_f[3]), hn::Store(cu, df, lane_f[4]), hn::Store(cv, df, lane_f[5]);
    hn::Store(hn::Div(one, az), df, lane_f[6]), hn::Store(hn::Div(one, bz), df, lane_f[7]);
    hn::Store(hn::Div(one, cz), df, lane_f[8]), hn::Store(hn::Div(one, hn::Neg(area)), df, lane_f[9]);
    hn::Store(x_lo, di, lane_i[0]), hn::Store(x_hi, di, lane_i[1]);
    hn::Store(y_lo, di, lane_i[2]), hn::Store(y_hi, di, lane_i[3]);
    hn::Store(tl(hn::Sub(bu, cu), hn::Sub(bv, cv)), di, lane_i[4]);  // IsTopLeft(c, b)
    hn::Store(tl(hn::Sub(cu, au), hn::Sub(cv, av)), di, lane_i[5]);  // IsTopLeft(a, c)
    hn::Store(tl(hn::Sub(au, bu), hn::Sub(av, bv)), di, lane_i[6]);  // IsTopLeft(b, a)
    // The live lanes in order, by their mask bits: no branch per lane (front and back faces
    // alternate too irregularly to predict). Covered pixels are counted per lane and summed
    // once a vector; a triangle that covers nothing is found by comparing its lanes with zero.
    uint8_t bytes[8] = {0};
    hn::StoreMaskBits(df, live, bytes);
    uint64_t bits = 0;
    for (size_t i = 0; i < (lanes + 7) / 8; ++i) bits |= uint64_t{bytes[i]} << (8 * i);
    auto covered_lanes = hn::Zero(di);
    int64_t filled = 0, between = 0;
    for (; bits != 0; bits &= bits - 1, ++filled) {
      const size_t k = static_cast<size_t>(hwy::Num0BitsBelowLS1Bit_Nonzero64(bits));
      const FloatTriangle t{lane_f[0][k], lane_f[1][k], lane_f[2][k], lane_f[3][k], lane_f[4][k],
                            lane_f[5][k], lane_f[6][k], lane_f[7][k], lane_f[8][k], lane_f[9][k],
                            lane_i[4][k] != 0, lane_i[5][k] != 0, lane_i[6][k] != 0,
                            lane_i[0][k], lane_i[1][k], lane_i[2][k], lane_i[3][k]};
      const auto covered = FillFloatTriangle(t, box, zbuf);
      between += hn::AllTrue(di, hn::Eq(covered, hn::Zero(di)));
      covered_lanes = hn::Add(covered_lanes, covered);
    }
    s.culled_between_pixels += between;
    s.triangles_rasterized += filled - between;
    s.fragments += hn::GetLane(hn::SumOfLanes(di, covered_lanes));
  }
  *stats += s;
}

size_t LaneCount() { return hn::Lanes(hn::ScalableTag<float>()); }

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mcpose::render {

HWY_EXPORT(RasterizeFloatImpl);
HWY_EXPORT(LaneCount);

void RasterizeDepthFloatSimd(std::span<const ScreenVertex> vertices,
                             std::span<const std::array<uint32_t, 3>> triangles, const RasterParams& params,
                             float* zbuf, RasterCounters* stats) {
  static_assert(sizeof(ScreenVertex) == 3 * sizeof(float) && sizeof(std::array<uint32_t, 3>) == 3 * sizeof(uint32_t));
  RasterCounters s;
  // Whole vectors of triangles here, the few left over (and every triangle of an empty box)
  // by the reference itself.
  const size_t lanes = MCPOSE_DYNAMIC_DISPATCH(LaneCount)();
  const size_t n = params.box.empty() ? 0 : triangles.size() / lanes * lanes;
  if (n > 0) MCPOSE_DYNAMIC_DISPATCH(RasterizeFloatImpl)(&vertices[0].u, triangles[0].data(), n, params, zbuf, &s);
  RasterizeDepthReference(vertices, triangles.subspan(n), params, zbuf, &s);
  if (stats) *stats += s;
}

}  // namespace mcpose::render
#endif  // HWY_ONCE
