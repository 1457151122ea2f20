// The SIMD row kernel of the fixed-point raster core (see raster_fixed.h): N pixels of a row
// at a time with Highway, compiled for every target Highway knows here and dispatched at run
// time. FillTriangleScalar (raster_fixed.cc) is its reference.
#include <cstdint>
#include <string>

#include "render/raster_fixed.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/raster_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace mcpose::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The row walk with vectors of tag DF: the same operations per lane at any width.
template <class DF>
HWY_INLINE int64_t FillRows(DF df, const FixedTriangle& t, float* zbuf, int stride) {
  const hn::RebindToSigned<DF> di;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(di));
  const auto iota = hn::Iota(di, 0);
  // Per-lane offsets of the edge functions, and their step over a whole vector (32 bits fit:
  // spans <= kMaxSimdSpanPx keep |E| < 2^30 even for lanes past x_hi).
  decltype(hn::Zero(di)) lane_step[3], vec_step[3];
  for (int k = 0; k < 3; ++k) {
    lane_step[k] = hn::Mul(iota, hn::Set(di, static_cast<int32_t>(t.step_x[k])));
    vec_step[k] = hn::Set(di, static_cast<int32_t>(t.step_x[k] * lanes));
  }
  const auto fA = hn::Set(df, t.A);
  const auto one = hn::Set(df, 1.0f);
  const auto minus_one = hn::Set(di, -1);  // E >= 0  <=>  E > -1 (integers)
  int64_t covered = 0;
  int64_t w_row[3] = {t.w_row[0], t.w_row[1], t.w_row[2]};
  for (int32_t y = t.y_lo; y <= t.y_hi; ++y) {
    float* row = zbuf + static_cast<size_t>(y) * stride;
    const auto row_c = hn::Set(df, t.B * static_cast<float>(y) + t.C);
    auto w0 = hn::Add(hn::Set(di, static_cast<int32_t>(w_row[0])), lane_step[0]);
    auto w1 = hn::Add(hn::Set(di, static_cast<int32_t>(w_row[1])), lane_step[1]);
    auto w2 = hn::Add(hn::Set(di, static_cast<int32_t>(w_row[2])), lane_step[2]);
    // Whole vectors; lanes past x_hi are masked out of coverage and written back unchanged
    // (the caller's kSimdPadFloats of slack keep the last row's loads in bounds).
    for (int32_t x = t.x_lo; x <= t.x_hi; x += lanes) {
      const auto in_row = hn::FirstN(di, static_cast<size_t>(t.x_hi - x + 1));
      const auto inside = hn::And(in_row, hn::Gt(hn::Or(hn::Or(w0, w1), w2), minus_one));
      if (!hn::AllFalse(di, inside)) {
        covered += static_cast<int64_t>(hn::CountTrue(di, inside));
        const auto xs = hn::ConvertTo(df, hn::Add(hn::Set(di, x), iota));
        // Same operations as the scalar kernel: 1 / (A x + row_c), multiply then add.
        const auto z = hn::Div(one, hn::Add(hn::Mul(fA, xs), row_c));
        const auto dst = hn::LoadU(df, row + x);
        const auto keep = hn::And(hn::RebindMask(df, inside), hn::Lt(z, dst));
        hn::StoreU(hn::IfThenElse(keep, z, dst), df, row + x);
      }
      w0 = hn::Add(w0, vec_step[0]), w1 = hn::Add(w1, vec_step[1]), w2 = hn::Add(w2, vec_step[2]);
    }
    w_row[0] += t.step_y[0], w_row[1] += t.step_y[1], w_row[2] += t.step_y[2];
  }
  return covered;
}

// Narrow triangles take narrower vectors: a row of 8 pixels or fewer costs one 8-lane vector
// instead of a mostly empty 16-lane one. Bit-identical at every width.
int64_t FillTriangleRows(const FixedTriangle& t, float* zbuf, int stride) {
  const int32_t span = t.x_hi - t.x_lo + 1;
  if (span <= 4) return FillRows(hn::CappedTag<float, 4>(), t, zbuf, stride);
  if (span <= 8) return FillRows(hn::CappedTag<float, 8>(), t, zbuf, stride);
  return FillRows(hn::ScalableTag<float>(), t, zbuf, stride);
}

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mcpose::render {

HWY_EXPORT(FillTriangleRows);

int64_t FillTriangleSimd(const FixedTriangle& t, float* zbuf, int stride) {
  return HWY_DYNAMIC_DISPATCH(FillTriangleRows)(t, zbuf, stride);
}

std::string SimdTargetsAvailable() {
  std::string out;
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    if (!out.empty()) out += ' ';
    out += hwy::TargetName(target);
  }
  return out;
}

}  // namespace mcpose::render
#endif  // HWY_ONCE
