// The SIMD colour test: CountColour (colour.cc) a vector of pixels at a time with Highway,
// compiled for every target Highway knows here and dispatched at run time. The same float
// operations in the same order pick the same pixels and cells, and the sums are integers, so
// the results equal the reference's.
#include <cmath>
#include <cstdint>

#include "score/colour.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "score/colour_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace mcpose::score {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
using VI = hn::Vec<DI>;

// Per-lane sums of one row (int32: a lane sees at most one pixel in `lanes` of a row, each
// product at most 255^2), added to the int64 totals at the end of the row.
struct RowSums {
  VI n, m[3], o[3], mm[3], oo[3], mo[3];
};

HWY_INLINE void ClearRow(RowSums* r) {
  const DI di;
  r->n = hn::Zero(di);
  for (int c = 0; c < 3; ++c) r->m[c] = r->o[c] = r->mm[c] = r->oo[c] = r->mo[c] = hn::Zero(di);
}

HWY_INLINE void FlushRow(const RowSums& r, ColourStats* out) {
  const DI di;
  auto sum = [&](VI v) { return static_cast<int64_t>(hn::GetLane(hn::SumOfLanes(di, v))); };
  out->n += sum(r.n);
  for (int c = 0; c < 3; ++c) {
    out->m[c] += sum(r.m[c]), out->o[c] += sum(r.o[c]);
    out->mm[c] += sum(r.mm[c]), out->oo[c] += sum(r.oo[c]), out->mo[c] += sum(r.mo[c]);
  }
}

struct Constants {
  hn::Vec<DF> R[9], t[3], origin[3], inv_cell, n[3], grid_x0, cx, inv_fx, eps, inf, zero;
  VI nx, ny;
};

// The pixels [x, x + lanes) of row y whose lanes are in `lanes_in`.
template <class M>
HWY_INLINE void TestVector(const ColourLookup& g, const Constants& k, const float* zr,
                           const float* zo, const uint32_t* rgba, float v_row, int x, M lanes_in, RowSums* r) {
  const DF df;
  const DI di;
  const DU du;
  // A depth inlier (NaN marks invalid observed depth: the comparison is then false)...
  const auto z = hn::LoadU(df, zr + x);
  const auto o = hn::LoadU(df, zo + x);
  auto mask = hn::And(lanes_in, hn::And(hn::Ne(z, k.inf), hn::Lt(hn::Abs(hn::Sub(z, o)), k.eps)));
  // ... with an observed colour...
  const auto obs = hn::LoadU(du, rgba + x);
  mask = hn::And(mask, hn::RebindMask(df, hn::Ne(hn::ShiftRight<24>(obs), hn::Zero(du))));
  // ... whose surface point lies in a cell of known colour.
  const auto xf = hn::ConvertTo(df, hn::Iota(di, x));
  const auto u = hn::Mul(hn::Sub(hn::Add(k.grid_x0, xf), k.cx), k.inv_fx);
  const auto px = hn::Mul(u, z), py = hn::Mul(hn::Set(df, v_row), z);
  hn::Vec<DF> gcoord[3];
  for (int a = 0; a < 3; ++a) {
    auto m = hn::Add(hn::Mul(k.R[3 * a], px), hn::Mul(k.R[3 * a + 1], py));
    m = hn::Add(m, hn::Mul(k.R[3 * a + 2], z));
    m = hn::Sub(hn::Add(m, k.t[a]), k.origin[a]);
    gcoord[a] = hn::Mul(m, k.inv_cell);
    mask = hn::And(mask, hn::And(hn::Ge(gcoord[a], k.zero), hn::Lt(gcoord[a], k.n[a])));
  }
  if (hn::AllFalse(df, mask)) return;
  // Cell indices, computed on in-range values only (the others read cell 0, then drop out).
  VI idx[3];
  for (int a = 0; a < 3; ++a) idx[a] = hn::ConvertTo(di, hn::IfThenElseZero(mask, gcoord[a]));
  const VI index = hn::Add(hn::Mul(hn::Add(hn::Mul(idx[2], k.ny), idx[1]), k.nx), idx[0]);
  const auto cell = hn::BitCast(du, hn::GatherIndex(di, reinterpret_cast<const int32_t*>(g.cells), index));
  const VI alpha = hn::BitCast(di, hn::ShiftRight<24>(cell));  // 0-255: compared as signed
  mask = hn::And(mask, hn::RebindMask(df, hn::Gt(alpha, hn::Set(di, static_cast<int32_t>(kKnownAlpha) - 1))));
  const auto mi = hn::RebindMask(di, mask);
  r->n = hn::Sub(r->n, hn::VecFromMask(di, mi));
  const auto byte = hn::Set(du, 0xffu);
  for (int c = 0; c < 3; ++c) {
    const VI mc = hn::IfThenElseZero(mi, hn::BitCast(di, hn::And(hn::ShiftRightSame(cell, 8 * c), byte)));
    const VI oc = hn::IfThenElseZero(mi, hn::BitCast(di, hn::And(hn::ShiftRightSame(obs, 8 * c), byte)));
    r->m[c] = hn::Add(r->m[c], mc), r->o[c] = hn::Add(r->o[c], oc);
    r->mm[c] = hn::Add(r->mm[c], hn::Mul(mc, mc));
    r->oo[c] = hn::Add(r->oo[c], hn::Mul(oc, oc));
    r->mo[c] = hn::Add(r->mo[c], hn::Mul(mc, oc));
  }
}

void CountColourRect(const ColourSample& s, const ColourLookup& g, ColourStats* out) {
  const DF df;
  const DI di;
  const int lanes = static_cast<int>(hn::Lanes(df));
  Constants k;
  for (int i = 0; i < 9; ++i) k.R[i] = hn::Set(df, s.R_model_cam[i]);
  for (int a = 0; a < 3; ++a) {
    k.t[a] = hn::Set(df, s.t_model_cam[a]);
    k.origin[a] = hn::Set(df, g.origin[a]);
  }
  k.n[0] = hn::Set(df, static_cast<float>(g.nx));
  k.n[1] = hn::Set(df, static_cast<float>(g.ny));
  k.n[2] = hn::Set(df, static_cast<float>(g.nz));
  k.inv_cell = hn::Set(df, g.inv_cell);
  k.grid_x0 = hn::Set(df, s.grid_x0), k.cx = hn::Set(df, s.cx), k.inv_fx = hn::Set(df, s.inv_fx);
  k.eps = hn::Set(df, s.eps_m), k.inf = hn::Set(df, INFINITY), k.zero = hn::Zero(df);
  k.nx = hn::Set(di, g.nx), k.ny = hn::Set(di, g.ny);
  const int x0 = s.rect.x0, x1 = s.rect.x1;
  // A row at least one vector wide ends in one more vector ending at x1, its lanes before the
  // tail masked off (never read past x1); narrower rows go a pixel at a time.
  const int tail = (x1 - x0) % lanes;
  const auto tail_lanes = hn::RebindMask(df, hn::Gt(hn::Iota(di, 0), hn::Set(di, lanes - tail - 1)));
  const auto all_lanes = hn::FirstN(df, static_cast<size_t>(lanes));
  RowSums r;
  for (int y = s.rect.y0; y < s.rect.y1; ++y) {
    if (x1 - x0 < lanes) {
      ColourSample row = s;
      row.rect = render::PixelRect{x0, y, x1, y + 1};
      const ColourStats one = CountColour(row, g);
      out->n += one.n;
      for (int c = 0; c < 3; ++c) {
        out->m[c] += one.m[c], out->o[c] += one.o[c];
        out->mm[c] += one.mm[c], out->oo[c] += one.oo[c], out->mo[c] += one.mo[c];
      }
      continue;
    }
    const float v = (s.grid_y0 + static_cast<float>(y) - s.cy) * s.inv_fy;
    const float* zr = s.rendered + static_cast<size_t>(y) * s.stride;
    const float* zo = s.observed_or_nan + static_cast<size_t>(y) * s.stride;
    const uint32_t* rgba = s.observed_rgba + static_cast<size_t>(y) * s.stride;
    ClearRow(&r);
    int x = x0;
    for (; x + lanes <= x1; x += lanes) TestVector(g, k, zr, zo, rgba, v, x, all_lanes, &r);
    if (tail > 0) TestVector(g, k, zr, zo, rgba, v, x1 - lanes, tail_lanes, &r);
    FlushRow(r, out);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::score
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mcpose::score {

HWY_EXPORT(CountColourRect);

ColourStats CountColourSimd(const ColourSample& sample, const ColourLookup& lookup) {
  ColourStats out;
  HWY_DYNAMIC_DISPATCH(CountColourRect)(sample, lookup, &out);
  return out;
}

}  // namespace mcpose::score
#endif  // HWY_ONCE
