// The SIMD row kernel of the fixed-point raster core (see raster_fixed.h): a vector of pixels
// at a time, as blocks of rows for triangles at most 4 or 8 pixels wide and row by row for
// the others, with Highway, compiled for every target Highway knows here and dispatched at run
// time.
// FillTriangleScalar (raster_fixed.cc) is its reference.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/raster_fixed.h"
#include "mcpose/option_table.h"
#include "mcpose/simd.h"

#include "render/simd_dispatch.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/raster_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "render/blocks-inl.h"

HWY_BEFORE_NAMESPACE();
namespace mcpose::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The lanes of `lanes_in` inside the triangle: no edge function negative, i.e. the sign bit
// clear in E0 | E1 | E2.
template <class V, class M>
HWY_INLINE M Inside(V e0, V e1, V e2, M lanes_in) {
  return hn::AndNot(hn::Lt(hn::Or(hn::Or(e0, e1), e2), hn::Zero(hn::DFromV<V>())), lanes_in);
}

// The row kernels return their covered pixel counts per lane (summed by the caller).
template <class DF>
using LaneCounts = hn::Vec<hn::RebindToSigned<DF>>;

// The triangle's edge functions at (x_lo, y_lo), their steps per pixel in x and y, and its
// 1/z plane, each broadcast to every lane.
template <class DF>
struct TriangleLanes {
  hn::Vec<hn::RebindToSigned<DF>> w[3], sx[3], sy[3];
  hn::Vec<DF> a, b, c;
};

// w_row, step_x, step_y and A, B, C are 12 consecutive 32-bit fields: three 128-bit loads and
// a lane broadcast each (Set() of a field goes through a general register, three instructions).
static_assert(offsetof(CompactTriangle, step_x) == offsetof(CompactTriangle, w_row) + 12 &&
              offsetof(CompactTriangle, step_y) == offsetof(CompactTriangle, w_row) + 24 &&
              offsetof(CompactTriangle, A) == offsetof(CompactTriangle, w_row) + 36 &&
              offsetof(CompactTriangle, C) == offsetof(CompactTriangle, w_row) + 44);
template <class DF>
HWY_INLINE TriangleLanes<DF> BroadcastTriangle(DF df, const CompactTriangle& t) {
  const hn::RebindToSigned<DF> di;
  TriangleLanes<DF> v;
#if HWY_TARGET == HWY_SCALAR
  for (int k = 0; k < 3; ++k) {
    v.w[k] = hn::Set(di, t.w_row[k]);
    v.sx[k] = hn::Set(di, t.step_x[k]), v.sy[k] = hn::Set(di, t.step_y[k]);
  }
  v.a = hn::Set(df, t.A), v.b = hn::Set(df, t.B), v.c = hn::Set(df, t.C);
#else
  const int32_t* p =
      reinterpret_cast<const int32_t*>(reinterpret_cast<const char*>(&t) + offsetof(CompactTriangle, w_row));
  // The same 4 fields in every 128-bit block.
  const auto load4 = [di](const int32_t* q) {
    if constexpr (hn::MaxLanes(decltype(di)()) <= 4) {
      return hn::LoadU(di, q);
    } else {
      return hn::LoadDup128(di, q);
    }
  };
  // w0 w1 w2 sx0 | sx1 sx2 sy0 sy1 | sy2 A B C
  const auto q0 = load4(p), q1 = load4(p + 4), q2 = load4(p + 8);
  v.w[0] = hn::Broadcast<0>(q0), v.w[1] = hn::Broadcast<1>(q0), v.w[2] = hn::Broadcast<2>(q0);
  v.sx[0] = hn::Broadcast<3>(q0), v.sx[1] = hn::Broadcast<0>(q1), v.sx[2] = hn::Broadcast<1>(q1);
  v.sy[0] = hn::Broadcast<2>(q1), v.sy[1] = hn::Broadcast<3>(q1), v.sy[2] = hn::Broadcast<0>(q2);
  const auto f2 = hn::BitCast(df, q2);
  v.a = hn::Broadcast<1>(f2), v.b = hn::Broadcast<2>(f2), v.c = hn::Broadcast<3>(f2);
#endif
  return v;
}

// The row walk with vectors of tag DF: the same operations per lane at any width. Every vector
// of a row is written back, covered or not: a test per vector for skipping the empty ones
// (22 % mispredicted in valgrind's branch model on the tomato can) cost more than it saved.
template <class DF>
HWY_INLINE LaneCounts<DF> FillRows(DF df, const CompactTriangle& HWY_RESTRICT t, float* HWY_RESTRICT zbuf,
                                   int stride) {
  const hn::RebindToSigned<DF> di;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(di));
  const auto iota = hn::Iota(di, 0);
  // Per-lane offsets of the edge functions, and their step over a whole vector (32 bits fit:
  // spans <= kMaxSimdSpanPx keep |E| < 2^30 even for lanes past x_hi).
  decltype(hn::Zero(di)) lane_step[3], vec_step[3];
  for (int k = 0; k < 3; ++k) {
    lane_step[k] = hn::Mul(iota, hn::Set(di, t.step_x[k]));
    vec_step[k] = hn::Set(di, t.step_x[k] * lanes);
  }
  const auto fA = hn::Set(df, t.A);
  const auto one = hn::Set(df, 1.0f);
  auto covered_lanes = hn::Zero(di);  // per lane, as in FillBlocks
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
      const auto inside = Inside(w0, w1, w2, in_row);
      covered_lanes = hn::Sub(covered_lanes, hn::VecFromMask(di, inside));
      const auto xs = hn::ConvertTo(df, hn::Add(hn::Set(di, x), iota));
      // Same operations as the scalar kernel: 1 / (A x + row_c), multiply then add.
      const auto z = hn::Div(one, hn::Add(hn::Mul(fA, xs), row_c));
      const auto dst = hn::LoadU(df, row + x);
      const auto keep = hn::And(hn::RebindMask(df, inside), hn::Lt(z, dst));
      hn::StoreU(hn::IfThenElse(keep, z, dst), df, row + x);
      w0 = hn::Add(w0, vec_step[0]), w1 = hn::Add(w1, vec_step[1]), w2 = hn::Add(w2, vec_step[2]);
    }
    w_row[0] += t.step_y[0], w_row[1] += t.step_y[1], w_row[2] += t.step_y[2];
  }
  return covered_lanes;
}

#if HWY_TARGET != HWY_SCALAR  // one lane: no blocks
// Triangles at most kW pixels wide, lanes / kW rows per vector: lane i is pixel
// (x_lo + i % kW, y + i / kW). Same integer coverage and float operations per pixel as the
// scalar kernel. Rows past y_hi are masked out; their pointers alias row y_hi, so nothing
// outside the triangle's rows (and the kSimdPadFloats slack after a row) is touched.
template <size_t kW, class DF>
HWY_INLINE LaneCounts<DF> FillBlocks(DF df, const CompactTriangle& HWY_RESTRICT t, float* HWY_RESTRICT zbuf,
                                     int stride) {
  const hn::RebindToSigned<DF> di;
  constexpr size_t kLanes = hn::MaxLanes(DF());
  constexpr int32_t kRows = static_cast<int32_t>(kLanes / kW);
  static_assert(kRows >= 1 && kRows * kW == kLanes);
  const auto lane = hn::Iota(di, 0);
  const auto lx = hn::And(lane, hn::Set(di, static_cast<int32_t>(kW - 1)));
  const auto ly = hn::ShiftRight<hwy::CeilLog2(kW)>(lane);
  const TriangleLanes<DF> v = BroadcastTriangle(df, t);
  decltype(hn::Zero(di)) w[3], block_step[3];
  for (int k = 0; k < 3; ++k) {
    w[k] = hn::Add(v.w[k], hn::Add(hn::Mul(lx, v.sx[k]), hn::Mul(ly, v.sy[k])));
    block_step[k] = hn::ShiftLeft<hwy::CeilLog2(kRows)>(v.sy[k]);  // step_y * kRows
  }
  const auto in_span = hn::Lt(lx, hn::Set(di, t.x_hi - t.x_lo + 1));
  // A x per lane, rounded as the scalar kernel rounds it before adding B y + C.
  const auto ax = hn::Mul(v.a, hn::ConvertTo(df, hn::Add(lx, hn::Set(di, t.x_lo))));
  const auto fB = v.b, fC = v.c;
  const auto one = hn::Set(df, 1.0f);
  // Each lane's row, and the rows' end; covered pixels counted per lane (no lane exceeds the
  // triangle's pixel count, far below 2^31).
  auto y_lane = hn::Add(ly, hn::Set(di, t.y_lo));
  const auto y_end = hn::Set(di, t.y_hi + 1), rows_step = hn::Set(di, kRows);
  auto covered = hn::Zero(di);
  float* rows[kRows];
  float* row = zbuf + static_cast<size_t>(t.y_lo) * stride + t.x_lo;
  for (int32_t y = t.y_lo; y <= t.y_hi; y += kRows, row += static_cast<size_t>(kRows) * stride) {
    rows[0] = row;
    for (int32_t r = 1; r < kRows; ++r) rows[r] = y + r <= t.y_hi ? rows[r - 1] + stride : rows[r - 1];
    const auto inside = Inside(w[0], w[1], w[2], hn::And(in_span, hn::Lt(y_lane, y_end)));
    covered = hn::Sub(covered, hn::VecFromMask(di, inside));
    const auto row_c = hn::Add(hn::Mul(fB, hn::ConvertTo(df, y_lane)), fC);
    const auto z = hn::Div(one, hn::Add(ax, row_c));
    const auto dst = LoadBlock<kW>(df, rows);
    const auto keep = hn::And(hn::RebindMask(df, inside), hn::Lt(z, dst));
    StoreBlock<kW>(df, hn::IfThenElse(keep, z, dst), rows);
    for (int k = 0; k < 3; ++k) w[k] = hn::Add(w[k], block_step[k]);
    y_lane = hn::Add(y_lane, rows_step);
  }
  return covered;
}

// Triangles at most kVecs vectors wide (kVecs 1 to 4), a row at a time: the row's kVecs vectors
// unrolled, each with its span mask hoisted out of the row loop, no branches. The same lanes,
// integer tests and float operations as FillRows and the scalar kernel.
template <int kVecs, class DF>
HWY_INLINE LaneCounts<DF> FillWideRows(DF df, const CompactTriangle& HWY_RESTRICT t, float* HWY_RESTRICT zbuf,
                                       int stride) {
  const hn::RebindToSigned<DF> di;
  constexpr int32_t kLanes = static_cast<int32_t>(hn::MaxLanes(DF()));
  const auto iota = hn::Iota(di, 0);
  const TriangleLanes<DF> v = BroadcastTriangle(df, t);
  decltype(hn::Zero(di)) w[3], vec_step[3];
  for (int k = 0; k < 3; ++k) {
    vec_step[k] = hn::ShiftLeft<hwy::CeilLog2(kLanes)>(v.sx[k]);  // step_x * kLanes
    w[k] = hn::Add(v.w[k], hn::Mul(iota, v.sx[k]));
  }
  const int32_t span = t.x_hi - t.x_lo + 1;
  decltype(hn::FirstN(di, 0)) in_span[kVecs];
  decltype(hn::Zero(df)) ax[kVecs];
  const auto fA = v.a;
  for (int j = 0; j < kVecs; ++j) {
    in_span[j] = hn::FirstN(di, static_cast<size_t>(std::max(0, span - j * kLanes)));
    ax[j] = hn::Mul(fA, hn::ConvertTo(df, hn::Add(iota, hn::Set(di, t.x_lo + j * kLanes))));
  }
  const auto one = hn::Set(df, 1.0f);
  auto covered = hn::Zero(di);  // per lane, as in FillBlocks
  for (int32_t y = t.y_lo; y <= t.y_hi; ++y) {
    float* row = zbuf + static_cast<size_t>(y) * stride + t.x_lo;
    // row_c as the scalar kernel rounds it: B y + C in float, then A x + row_c.
    const auto row_c = hn::Set(df, t.B * static_cast<float>(y) + t.C);
    auto e0 = w[0], e1 = w[1], e2 = w[2];
    for (int j = 0; j < kVecs; ++j) {
      const auto inside = Inside(e0, e1, e2, in_span[j]);
      covered = hn::Sub(covered, hn::VecFromMask(di, inside));
      const auto z = hn::Div(one, hn::Add(ax[j], row_c));
      const auto dst = hn::LoadU(df, row + j * kLanes);
      const auto keep = hn::And(hn::RebindMask(df, inside), hn::Lt(z, dst));
      hn::StoreU(hn::IfThenElse(keep, z, dst), df, row + j * kLanes);
      e0 = hn::Add(e0, vec_step[0]), e1 = hn::Add(e1, vec_step[1]), e2 = hn::Add(e2, vec_step[2]);
    }
    for (int k = 0; k < 3; ++k) w[k] = hn::Add(w[k], v.sy[k]);
  }
  return covered;
}
#endif  // HWY_TARGET != HWY_SCALAR

// Triangles at most one vector wide take FillBlocks where the vector holds at least two rows
// of 4 or 8 pixels (AVX2: 4 x 2; AVX-512: 4 x 4, 8 x 2) and the box is at least that wide, and
// FillWideRows<1> (a row per vector) otherwise. Up to 4 vectors wide, FillWideRows; wider
// ones FillRows. Bit-identical at every width.
HWY_INLINE LaneCounts<hn::ScalableTag<float>> FillOneTriangle(const CompactTriangle& HWY_RESTRICT t,
                                                               float* HWY_RESTRICT zbuf, int stride) {
  const hn::ScalableTag<float> df;
#if HWY_TARGET != HWY_SCALAR
  const int32_t span = t.x_hi - t.x_lo + 1;
  constexpr size_t kLanes = hn::MaxLanes(df);
  if constexpr (kLanes >= 4 && kLanes <= 16) {
    // A block's rows share a vector only where the z-buffer's rows are at least the block's
    // width apart: a row's lanes past the triangle, stored back unchanged, then end before the
    // next row's pixels of the block.
    if constexpr (kLanes >= 8) {
      if (span <= 4 && stride >= 4) return FillBlocks<4>(df, t, zbuf, stride);
    }
    if constexpr (kLanes == 16) {
      if (span <= 8 && stride >= 8) return FillBlocks<8>(df, t, zbuf, stride);
    }
    if (span <= static_cast<int32_t>(kLanes)) return FillWideRows<1>(df, t, zbuf, stride);
    if (span <= static_cast<int32_t>(2 * kLanes)) return FillWideRows<2>(df, t, zbuf, stride);
    if (span <= static_cast<int32_t>(3 * kLanes)) return FillWideRows<3>(df, t, zbuf, stride);
    if (span <= static_cast<int32_t>(4 * kLanes)) return FillWideRows<4>(df, t, zbuf, stride);
  }
#endif
  return FillRows(df, t, zbuf, stride);
}

int64_t FillTriangleRows(const CompactTriangle& t, float* zbuf, int stride) {
  const hn::ScalableTag<int32_t> di;
  return hn::GetLane(hn::SumOfLanes(di, FillOneTriangle(t, zbuf, stride)));
}

const char* TargetNameImpl() { return hwy::TargetName(HWY_TARGET); }

// The kernels inlined into one loop over the ready triangles; the covered counts stay per
// lane and are summed every 256 triangles (no lane reaches 2^31), a triangle that covers
// nothing found by comparing its lanes with zero.
void FillBatch(const CompactTriangle* t, const uint8_t* ready, size_t n, float* zbuf, int stride,
               RasterCounters* stats) {
  const hn::ScalableTag<int32_t> di;
  const auto zero = hn::Zero(di);
  auto lanes = zero;
  int64_t filled = 0, between = 0, fragments = 0;
  for (size_t j = 0; j < n; ++j) {
    if (!ready[j]) continue;
    const auto covered = FillOneTriangle(t[j], zbuf, stride);
    between += hn::AllTrue(di, hn::Eq(covered, zero));
    lanes = hn::Add(lanes, covered);
    if (++filled % 256 == 0) fragments += hn::GetLane(hn::SumOfLanes(di, lanes)), lanes = zero;
  }
  fragments += hn::GetLane(hn::SumOfLanes(di, lanes));
  stats->triangles_rasterized += filled - between;
  stats->culled_between_pixels += between;
  stats->fragments += fragments;
}

void ClearRect(float* zbuf, int stride, int x0, int y0, int x1, int y1) {
  const hn::ScalableTag<float> df;
  const int lanes = static_cast<int>(hn::Lanes(df));
  const auto inf = hn::Set(df, INFINITY);
  const int width = x1 - x0;
  for (int y = y0; y < y1; ++y) {
    float* row = zbuf + static_cast<size_t>(y) * stride;
    if (width < lanes) {
      hn::BlendedStore(inf, hn::FirstN(df, static_cast<size_t>(width)), df, row + x0);
      continue;
    }
    for (int x = x0; x < x1 - lanes; x += lanes) hn::StoreU(inf, df, row + x);
    hn::StoreU(inf, df, row + x1 - lanes);  // the last vector, overlapping the one before
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mcpose::render {

HWY_EXPORT(FillTriangleRows);

int64_t FillCompactSimd(const CompactTriangle& t, float* zbuf, int stride) {
  return MCPOSE_DYNAMIC_DISPATCH(FillTriangleRows)(t, zbuf, stride);
}

HWY_EXPORT(FillBatch);

void FillCompactBatchSimd(const CompactTriangle* t, const uint8_t* ready, size_t n, float* zbuf, int stride,
                          RasterCounters* stats) {
  if (n == 0) return;
  MCPOSE_DYNAMIC_DISPATCH(FillBatch)(t, ready, n, zbuf, stride, stats);
}

HWY_EXPORT(ClearRect);

void ClearDepthRectSimd(float* zbuf, int stride, const PixelRect& rect) {
  if (rect.empty()) return;
  MCPOSE_DYNAMIC_DISPATCH(ClearRect)(zbuf, stride, rect.x0, rect.y0, rect.x1, rect.y1);
}

int64_t FillTriangleSimd(const FixedTriangle& t, float* zbuf, int stride) {
  return FillCompactSimd(Compact(t), zbuf, stride);
}

namespace {

// The targets the thread's open scopes replaced (ThreadDispatchScope), innermost last.
thread_local std::vector<const hwy::ChosenTarget*> t_replaced;

// The bit of SimdTargetNames()[index] (index >= 1), 0 if none.
int64_t TargetBit(int index) {
  const auto names = SimdTargetNames();
  if (index < 1 || static_cast<size_t>(index) >= names.size()) return 0;
  for (int64_t bits = HWY_TARGETS; bits != 0; bits &= bits - 1)
    if (std::string(hwy::TargetName(bits & -bits)) == names[static_cast<size_t>(index)]) return bits & -bits;
  return 0;
}

}  // namespace

HWY_EXPORT(TargetNameImpl);

thread_local const hwy::ChosenTarget* t_dispatch_target = nullptr;

void PushThreadDispatchTarget(const hwy::ChosenTarget* target) {
  t_replaced.push_back(t_dispatch_target);
  t_dispatch_target = target;
}

void PopThreadDispatchTarget() {
  t_dispatch_target = t_replaced.back();
  t_replaced.pop_back();
}

bool SimdTargetSupported(int index) {
  if (index == 0) return true;
  const int64_t bit = TargetBit(index);
  return bit != 0 && (hwy::SupportedTargets() & bit) != 0;
}

const hwy::ChosenTarget* CappedDispatchTarget(int index) {
  // One ChosenTarget per name, made on first use: the CPU's targets no better than it.
  static std::vector<std::unique_ptr<hwy::ChosenTarget>> targets = [] {
    std::vector<std::unique_ptr<hwy::ChosenTarget>> t(SimdTargetNames().size());
    const int64_t supported = hwy::SupportedTargets();
    for (size_t i = 1; i < t.size(); ++i) {
      const int64_t bit = TargetBit(static_cast<int>(i));
      if (bit == 0 || (supported & bit) == 0) continue;
      t[i] = std::make_unique<hwy::ChosenTarget>();
      t[i]->Update(supported & ~(bit - 1));  // better targets have lower bits
    }
    return t;
  }();
  if (index < 1 || static_cast<size_t>(index) >= targets.size()) return nullptr;
  return targets[static_cast<size_t>(index)].get();
}

std::string SimdTargetsAvailable() {
  std::string out;
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    if (!out.empty()) out += ' ';
    out += hwy::TargetName(target);
  }
  return out;
}

std::string ThreadSimdTarget() { return MCPOSE_DYNAMIC_DISPATCH(TargetNameImpl)(); }

std::string DispatchedSimdTarget(SimdTarget target) {
  const ThreadDispatchScope scope(CappedDispatchTarget(static_cast<int>(target)));
  return MCPOSE_DYNAMIC_DISPATCH(TargetNameImpl)();
}

}  // namespace mcpose::render
#endif  // HWY_ONCE
