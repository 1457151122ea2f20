// The SIMD inlier counter: CountInliers1DInRect (inlier.cc) a vector of pixels at a time with
// Highway, compiled for every target Highway knows here and dispatched at run time. The scalar
// CountInliers1DInRect is its reference; the same float operations give the same counts.
#include <cmath>
#include <cstdint>

#include "score/inlier.h"

#include "render/simd_dispatch.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "score/inlier_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace mcpose::score {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The tests of the pixels [x, x + lanes of DF) of one row: drawn, inlier, occluded. `zo` is
// NaN where the observed depth is invalid, so both depth comparisons are false there; an
// undrawn pixel (+inf) is no inlier either (|inf - o| is not below eps).
template <class DF>
struct PixelMasks {
  decltype(hn::FirstN(DF(), 0)) drawn, inlier, occluded;
};
template <class DF>
HWY_INLINE PixelMasks<DF> TestVector(DF df, const float* zr, const float* zo, int x, float eps_m) {
  const auto r = hn::LoadU(df, zr + x);
  const auto o = hn::LoadU(df, zo + x);
  const auto eps = hn::Set(df, eps_m);
  const auto d = hn::Ne(r, hn::Set(df, INFINITY));
  return {d, hn::Lt(hn::Abs(hn::Sub(r, o)), eps), hn::And(d, hn::Le(o, hn::Sub(r, eps)))};
}

// Counts them (the row tails).
template <class DF>
HWY_INLINE void CountVector(DF df, const float* zr, const float* zo, int x, float eps_m, int64_t* drawn,
                            int64_t* inliers, int64_t* occluded) {
  const PixelMasks<DF> m = TestVector(df, zr, zo, x, eps_m);
  *drawn += static_cast<int64_t>(hn::CountTrue(df, m.drawn));
  *inliers += static_cast<int64_t>(hn::CountTrue(df, m.inlier));
  *occluded += static_cast<int64_t>(hn::CountTrue(df, m.occluded));
}

// Whole vectors of the full width: per-lane counts (a lane's mask is -1 where true), summed
// once per rect.
template <class DF, class VI>
HWY_INLINE void Accumulate(DF, const PixelMasks<DF>& m, VI* drawn, VI* inliers, VI* occluded) {
  const hn::RebindToSigned<DF> di;
  *drawn = hn::Sub(*drawn, hn::VecFromMask(di, hn::RebindMask(di, m.drawn)));
  *inliers = hn::Sub(*inliers, hn::VecFromMask(di, hn::RebindMask(di, m.inlier)));
  *occluded = hn::Sub(*occluded, hn::VecFromMask(di, hn::RebindMask(di, m.occluded)));
}

// The masks of the lanes in `lanes_in` only.
template <class DF, class M>
HWY_INLINE PixelMasks<DF> Only(PixelMasks<DF> m, M lanes_in) {
  m.drawn = hn::And(lanes_in, m.drawn), m.inlier = hn::And(lanes_in, m.inlier);
  m.occluded = hn::And(lanes_in, m.occluded);
  return m;
}

void CountRect(const float* rendered, const float* observed, int stride, int x0, int y0, int x1, int y1,
               float eps_m, int64_t* out) {
  const hn::ScalableTag<float> df;
  const hn::CappedTag<float, 8> d8;
  const hn::CappedTag<float, 4> d4;
  const int lanes = static_cast<int>(hn::Lanes(df)), lanes8 = static_cast<int>(hn::Lanes(d8)),
            lanes4 = static_cast<int>(hn::Lanes(d4));
  const hn::RebindToSigned<decltype(df)> di;
  // Per-lane counts stay below 2^31: a lane sees at most one pixel in `lanes` of a row, and one
  // more per row (the tail vector).
  auto v_drawn = hn::Zero(di), v_inliers = hn::Zero(di), v_occluded = hn::Zero(di);
  int64_t drawn = 0, inliers = 0, occluded = 0;
  // A row at least one vector wide ends in one more vector ending at x1, its lanes before the
  // tail masked off (never read past x1): the lanes of that vector still to count.
  const int tail = (x1 - x0) % lanes;
  const auto tail_lanes = hn::RebindMask(df, hn::Gt(hn::Iota(di, 0), hn::Set(di, lanes - tail - 1)));
  for (int y = y0; y < y1; ++y) {
    const float* zr = rendered + static_cast<size_t>(y) * stride;
    const float* zo = observed + static_cast<size_t>(y) * stride;
    int x = x0;
    for (; x + lanes <= x1; x += lanes) {
      Accumulate(df, TestVector(df, zr, zo, x, eps_m), &v_drawn, &v_inliers, &v_occluded);
    }
    if (x > x0 && x < x1) {
      Accumulate(df, Only(TestVector(df, zr, zo, x1 - lanes, eps_m), tail_lanes), &v_drawn, &v_inliers,
                 &v_occluded);
      continue;
    }
    // A row narrower than a vector: narrower whole vectors (never past x1), then one pixel at a time.
    if (lanes8 < lanes && x + lanes8 <= x1) CountVector(d8, zr, zo, x, eps_m, &drawn, &inliers, &occluded), x += lanes8;
    if (lanes4 < lanes8 && x + lanes4 <= x1) CountVector(d4, zr, zo, x, eps_m, &drawn, &inliers, &occluded), x += lanes4;
    for (; x < x1; ++x) {  // as the reference does it (NaN > 0 is false)
      const bool d = zr[x] != INFINITY, valid = zo[x] > 0.f;
      drawn += d;
      inliers += d & valid & (std::fabs(zr[x] - zo[x]) < eps_m);
      occluded += d & valid & (zo[x] <= zr[x] - eps_m);
    }
  }
  drawn += hn::GetLane(hn::SumOfLanes(di, v_drawn));
  inliers += hn::GetLane(hn::SumOfLanes(di, v_inliers));
  occluded += hn::GetLane(hn::SumOfLanes(di, v_occluded));
  out[0] = drawn, out[1] = inliers, out[2] = occluded;
}

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::score
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mcpose::score {

HWY_EXPORT(CountRect);

InlierCounts CountInliers1DInRectSimd(const float* rendered, const float* observed_or_nan, int stride,
                                      const render::PixelRect& rect, int32_t n_observed, float eps_m) {
  int64_t n[3];
  MCPOSE_DYNAMIC_DISPATCH(CountRect)(rendered, observed_or_nan, stride, rect.x0, rect.y0, rect.x1, rect.y1, eps_m, n);
  InlierCounts c;
  c.observed = n_observed;
  c.rendered = static_cast<int32_t>(n[0]);
  c.inliers = static_cast<int32_t>(n[1]);
  c.occluded = static_cast<int32_t>(n[2]);
  return c;
}

}  // namespace mcpose::score
#endif  // HWY_ONCE
