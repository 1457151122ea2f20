// Loads and stores of a block of z-buffer rows in one vector, shared by the SIMD row kernels of
// the fixed-point core (raster_simd.cc) and of the float core (raster_float_simd.cc): a block of
// kW pixels x (lanes / kW) rows, row r of the block at rows[r] (the first row in the lowest
// lanes). Loads and stores split the vector into halves until a half is one row wide.
// A Highway per-target header: include it after <hwy/highway.h> in a file compiled with
// foreach_target.
#if defined(MCPOSE_RENDER_BLOCKS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef MCPOSE_RENDER_BLOCKS_INL_H_
#undef MCPOSE_RENDER_BLOCKS_INL_H_
#else
#define MCPOSE_RENDER_BLOCKS_INL_H_
#endif

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace mcpose::render {
namespace HWY_NAMESPACE {

#if HWY_TARGET != HWY_SCALAR  // one lane: no blocks
template <size_t kW, class D>
HWY_INLINE hwy::HWY_NAMESPACE::Vec<D> LoadBlock(D d, float* const* rows) {
  namespace hn = hwy::HWY_NAMESPACE;
  if constexpr (hn::MaxLanes(D()) == kW) {
    return hn::LoadU(d, rows[0]);
  } else {
    const hn::Half<D> dh;
    constexpr size_t kHalfRows = hn::MaxLanes(D()) / 2 / kW;
    return hn::Combine(d, LoadBlock<kW>(dh, rows + kHalfRows), LoadBlock<kW>(dh, rows));
  }
}
// Stores the rows last to first: rows past the triangle's last one alias it (the callers point
// them there), hold its old values, and must be overwritten by it.
template <size_t kW, class D>
HWY_INLINE void StoreBlock(D d, hwy::HWY_NAMESPACE::Vec<D> v, float* const* rows) {
  namespace hn = hwy::HWY_NAMESPACE;
  if constexpr (hn::MaxLanes(D()) == kW) {
    hn::StoreU(v, d, rows[0]);
  } else {
    const hn::Half<D> dh;
    constexpr size_t kHalfRows = hn::MaxLanes(D()) / 2 / kW;
    StoreBlock<kW>(dh, hn::UpperHalf(dh, v), rows + kHalfRows);
    StoreBlock<kW>(dh, hn::LowerHalf(dh, v), rows);
  }
}
#endif  // HWY_TARGET != HWY_SCALAR

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::render
HWY_AFTER_NAMESPACE();

#endif  // MCPOSE_RENDER_BLOCKS_INL_H_ toggle
