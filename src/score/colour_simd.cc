// The SIMD colour test: CountColour (colour.cc) a vector of pixels at a time with Highway,
// compiled for every target Highway knows here and dispatched at run time. The same float
// operations in the same order pick the same pixels and cells, and the sums are integers, so
// the results equal the reference's. With a step of 2 to 4 a vector holds every step-th pixel
// of a row (de-interleaved loads).
#include <cmath>
#include <cstdint>

#include "score/colour.h"

#include "render/simd_dispatch.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "score/colour_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace mcpose::score {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Per-lane sums (int32: a lane sees at most one pixel in `lanes` of a row, each product at most
// 255^2), added to the int64 totals at the end of each row.
template <class DI>
struct RowSums {
  hn::Vec<DI> n, m[3], o[3], mm[3], oo[3], mo[3];
  explicit RowSums(DI di) : n(hn::Zero(di)) {
    for (int c = 0; c < 3; ++c) m[c] = o[c] = mm[c] = oo[c] = mo[c] = hn::Zero(di);
  }
  void FlushTo(DI di, ColourStats* out) const {
    auto sum = [&](hn::Vec<DI> v) { return static_cast<int64_t>(hn::GetLane(hn::SumOfLanes(di, v))); };
    out->n += sum(n);
    for (int c = 0; c < 3; ++c) {
      out->m[c] += sum(m[c]), out->o[c] += sum(o[c]);
      out->mm[c] += sum(mm[c]), out->oo[c] += sum(oo[c]), out->mo[c] += sum(mo[c]);
    }
  }
};

// The lanes' values of one row, from pixel x on, every `Step`-th pixel.
template <int Step, class D, class T>
HWY_INLINE hn::Vec<D> LoadRow(D d, const T* row, int x) {
  hn::Vec<D> v0, v1, v2, v3;
  if constexpr (Step == 1) {
    v0 = hn::LoadU(d, row + x);
  } else if constexpr (Step == 2) {
    hn::LoadInterleaved2(d, row + x, v0, v1);
  } else if constexpr (Step == 3) {
    hn::LoadInterleaved3(d, row + x, v0, v1, v2);
  } else {
    static_assert(Step == 4);
    hn::LoadInterleaved4(d, row + x, v0, v1, v2, v3);
  }
  return v0;
}

// Per-row constants of the model-point arithmetic (see CountColour).
struct RowConstants {
  float rv[3];  // R_a1 v + R_a2
  float c[3];   // (t_a - origin_a) inv_cell
};

// The lanes' pixels x, x + Step, ... of row `row` (y with v_row = its ray's y) that `lanes_in`
// holds.
template <int Step, class DF, class M>
HWY_INLINE void TestVector(DF df, const ColourSample& s, const ColourLookup& g, const float* zr, const float* zo,
                           const uint32_t* rgba, const RowConstants& k, int x, M lanes_in,
                           RowSums<hn::RebindToSigned<DF>>* r) {
  const hn::RebindToSigned<DF> di;
  const hn::RebindToUnsigned<DF> du;
  // A depth inlier (NaN marks invalid observed depth: the comparison is then false)...
  const auto z = LoadRow<Step>(df, zr, x);
  const auto o = LoadRow<Step>(df, zo, x);
  auto mask = hn::And(lanes_in, hn::And(hn::Ne(z, hn::Set(df, INFINITY)),
                                        hn::Lt(hn::Abs(hn::Sub(z, o)), hn::Set(df, s.eps_m))));
  // ... with an observed colour...
  const auto obs = LoadRow<Step>(du, rgba, x);
  mask = hn::And(mask, hn::RebindMask(df, hn::Ne(hn::ShiftRight<24>(obs), hn::Zero(du))));
  if (hn::AllFalse(df, mask)) return;
  // ... whose surface point lies in a cell of known colour.
  const auto xf = hn::ConvertTo(df, hn::Add(hn::Mul(hn::Iota(di, 0), hn::Set(di, Step)), hn::Set(di, x)));
  const auto u = hn::Mul(hn::Sub(hn::Add(hn::Set(df, s.grid_x0), xf), hn::Set(df, s.cx)), hn::Set(df, s.inv_fx));
  const float n[3] = {static_cast<float>(g.nx), static_cast<float>(g.ny), static_cast<float>(g.nz)};
  hn::Vec<DF> gcoord[3];
  for (int a = 0; a < 3; ++a) {
    const auto ka = hn::Mul(hn::Add(hn::Mul(hn::Set(df, s.R_model_cam[3 * a]), u), hn::Set(df, k.rv[a])),
                            hn::Set(df, g.inv_cell));
    gcoord[a] = hn::Add(hn::Mul(ka, z), hn::Set(df, k.c[a]));
    mask = hn::And(mask, hn::And(hn::Ge(gcoord[a], hn::Zero(df)), hn::Lt(gcoord[a], hn::Set(df, n[a]))));
  }
  if (hn::AllFalse(df, mask)) return;
  // Cell indices, computed on in-range values only (the others read cell 0, then drop out).
  hn::Vec<decltype(di)> idx[3];
  for (int a = 0; a < 3; ++a) idx[a] = hn::ConvertTo(di, hn::IfThenElseZero(mask, gcoord[a]));
  const auto index =
      hn::Add(hn::Mul(hn::Add(hn::Mul(idx[2], hn::Set(di, g.ny)), idx[1]), hn::Set(di, g.nx)), idx[0]);
  const auto cell = hn::BitCast(du, hn::GatherIndex(di, reinterpret_cast<const int32_t*>(g.cells), index));
  const auto alpha = hn::BitCast(di, hn::ShiftRight<24>(cell));  // 0-255: compared as signed
  mask = hn::And(mask, hn::RebindMask(df, hn::Gt(alpha, hn::Set(di, static_cast<int32_t>(kKnownAlpha) - 1))));
  const auto mi = hn::RebindMask(di, mask);
  r->n = hn::Sub(r->n, hn::VecFromMask(di, mi));
  const auto byte = hn::Set(du, 0xffu);
  for (int c = 0; c < 3; ++c) {
    const auto mc = hn::IfThenElseZero(mi, hn::BitCast(di, hn::And(hn::ShiftRightSame(cell, 8 * c), byte)));
    const auto oc = hn::IfThenElseZero(mi, hn::BitCast(di, hn::And(hn::ShiftRightSame(obs, 8 * c), byte)));
    r->m[c] = hn::Add(r->m[c], mc), r->o[c] = hn::Add(r->o[c], oc);
    r->mm[c] = hn::Add(r->mm[c], hn::Mul(mc, mc));
    r->oo[c] = hn::Add(r->oo[c], hn::Mul(oc, oc));
    r->mo[c] = hn::Add(r->mo[c], hn::Mul(mc, oc));
  }
}

// One row's pixels x0 .. x1 - 1 (every Step-th, x0 a multiple of Step) with vectors of `df` as
// far as whole vectors fit inside the row, then narrower ones, then a pixel at a time.
template <int Step, class DF>
HWY_INLINE int RowVectors(DF df, const ColourSample& s, const ColourLookup& g, const float* zr, const float* zo,
                          const uint32_t* rgba, const RowConstants& k, int x, int x1, ColourStats* out) {
  const hn::RebindToSigned<DF> di;
  const int span = static_cast<int>(hn::Lanes(df)) * Step;  // pixels a vector's loads cover
  if (x + span > x1) return x;
  RowSums<hn::RebindToSigned<DF>> sums(di);
  const auto all = hn::FirstN(df, hn::Lanes(df));
  for (; x + span <= x1; x += span) TestVector<Step>(df, s, g, zr, zo, rgba, k, x, all, &sums);
  sums.FlushTo(di, out);
  return x;
}

template <int Step>
void CountRows(const ColourSample& s, const ColourLookup& g, ColourStats* out) {
  const hn::ScalableTag<float> df;
  const hn::CappedTag<float, 4> d4;
  auto first = [](int v) { return (v + Step - 1) / Step * Step; };
  const int x0 = first(s.rect.x0), x1 = s.rect.x1;
  RowConstants k;
  for (int a = 0; a < 3; ++a) k.c[a] = (s.t_model_cam[a] - g.origin[a]) * g.inv_cell;
  for (int y = first(s.rect.y0); y < s.rect.y1; y += Step) {
    const float v = (s.grid_y0 + static_cast<float>(y) - s.cy) * s.inv_fy;
    for (int a = 0; a < 3; ++a) k.rv[a] = s.R_model_cam[3 * a + 1] * v + s.R_model_cam[3 * a + 2];
    const float* zr = s.rendered + static_cast<size_t>(y) * s.stride;
    const float* zo = s.observed_or_nan + static_cast<size_t>(y) * s.stride;
    const uint32_t* rgba = s.observed_rgba + static_cast<size_t>(y) * s.stride;
    int x = RowVectors<Step>(df, s, g, zr, zo, rgba, k, x0, x1, out);
    if (hn::Lanes(d4) < hn::Lanes(df)) x = RowVectors<Step>(d4, s, g, zr, zo, rgba, k, x, x1, out);
    if (x < x1) {  // the rest a pixel at a time, as the reference
      ColourSample rest = s;
      rest.rect = render::PixelRect{x, y, x1, y + 1};
      const ColourStats one = CountColour(rest, g);
      out->n += one.n;
      for (int c = 0; c < 3; ++c) {
        out->m[c] += one.m[c], out->o[c] += one.o[c];
        out->mm[c] += one.mm[c], out->oo[c] += one.oo[c], out->mo[c] += one.mo[c];
      }
    }
  }
}

void CountColourRect(const ColourSample& s, const ColourLookup& g, ColourStats* out) {
  switch (s.step) {
    case 1: CountRows<1>(s, g, out); break;
    case 2: CountRows<2>(s, g, out); break;
    case 3: CountRows<3>(s, g, out); break;
    default: CountRows<4>(s, g, out); break;
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
  if (sample.step < 1 || sample.step > 4) return CountColour(sample, lookup);
  MCPOSE_DYNAMIC_DISPATCH(CountColourRect)(sample, lookup, &out);
  return out;
}

}  // namespace mcpose::score
#endif  // HWY_ONCE
