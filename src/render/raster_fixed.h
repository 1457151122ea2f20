// The fixed-point raster core: the same contract as RasterizeDepthReference (raster.h), with
// vertices snapped to a 1/16-pixel grid (the paper's sub-pixel quantization) so that edge
// functions are exact integers, stepped incrementally across the triangle's bounding box.
//
// Differences from the reference: coverage is decided on the snapped triangle (a pixel centre
// within 1/32 pixel of an edge may flip), and depth comes from the 1/z plane through the
// snapped vertices. Triangles larger than the integer range (a side over 2048 pixels, or a
// vertex more than 16384 pixels off the box) go through the float reference path instead,
// so the result never depends on overflow.
#pragma once

#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "render/raster.h"

namespace mcpose::render {

inline constexpr int kSubpixelBits = 4;
inline constexpr int32_t kSubpixelOne = 1 << kSubpixelBits;  // one pixel in fixed point
inline constexpr float kGuardBandPx = 16384.f;  // |coordinate - box corner| beyond this: float path
inline constexpr int32_t kMaxSpanPx = 2048;     // triangles wider or taller than this: float path
// Triangles whose bounding box spans at most this many pixels per side have edge functions
// that fit in 32 bits (|E| < 2^30), so the SIMD row kernel can take them.
inline constexpr int32_t kMaxSimdSpanPx = 1024;

// One triangle after fixed-point setup, in box-relative pixels: the pixel range to walk,
// the edge functions (positive inside, top-left bias applied) at (x_lo, y_lo) and their steps
// per pixel, and the 1/z plane inv_z = A x + B y + C.
struct FixedTriangle {
  int32_t x_lo = 0, x_hi = -1, y_lo = 0, y_hi = -1;  // inclusive
  int64_t w_row[3] = {0, 0, 0}, step_x[3] = {0, 0, 0}, step_y[3] = {0, 0, 0};
  float A = 0, B = 0, C = 0;
  bool simd_fits = false;  // the span keeps the edge functions in 32 bits (kMaxSimdSpanPx)
};

// A set-up triangle whose span fits the SIMD rows (simd_fits): FixedTriangle's values in 32
// bits, which holds them exactly (|E| < 2^30), in 64 bytes. The batched setup writes these,
// and the SIMD row kernel reads them.
struct CompactTriangle {
  int32_t x_lo = 0, x_hi = -1, y_lo = 0, y_hi = -1;
  int32_t w_row[3] = {0, 0, 0}, step_x[3] = {0, 0, 0}, step_y[3] = {0, 0, 0};
  float A = 0, B = 0, C = 0;
};
static_assert(sizeof(CompactTriangle) == 64);
// The same triangle in the other form (Compact requires t.simd_fits).
CompactTriangle Compact(const FixedTriangle& t);
FixedTriangle Widen(const CompactTriangle& t);

// What triangle setup made of one triangle.
enum class TriangleSetup {
  kReady,                // *out is set up: walk it with a Fill kernel
  kCulledNear,           // a vertex closer than params.z_near_m
  kCulledDegenerate,     // zero area after snapping
  kCulledBackface,       // positive (back-facing) area and params.cull_backfaces
  kCulledOutsideBox,     // the snapped bounding box misses params.box
  kCulledBetweenPixels,  // the bounding box holds no pixel centre
  kFloatPath,            // outside the guard band or wider than 2048 px: use the float reference
};

// Triangle setup of the fixed-point core: near-plane test, snapping to 1/16 pixel, orientation,
// box and pixel-centre culls, then edge functions (exact integers) and the 1/z plane (float). The reasons are tested in
// this order (a triangle gets the first that applies).
TriangleSetup SetupFixedTriangle(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2,
                                 const RasterParams& params, FixedTriangle* out);
// The setup after the near-plane and guard-band tests and the snapping: X, Y box-relative in
// 1/16 pixel, z the vertices' depths. SetupFixedTriangle ends in it; the batched setup calls
// it with the vertices SnapVertices snapped (the same integers), so both give the same result.
TriangleSetup SetupSnappedTriangle(const int32_t X[3], const int32_t Y[3], const float z[3], const RasterParams& params,
                                   FixedTriangle* out);

// Walks the triangle's pixels, keeping the nearest depth 1 / (A x + (B y + C)) of covered
// pixels in zbuf (row stride `stride`). Returns the covered pixel count.
//   FillTriangleScalar: one pixel at a time, 64-bit edge functions (the reference).
//   FillTriangleSimd:   Highway, runtime-dispatched (AVX-512/AVX2/SSE4/scalar), 32-bit edge
//                       functions; requires a span of at most kMaxSimdSpanPx and
//                       kSimdPadFloats of readable, writable slack after the z-buffer (whole
//                       vectors are loaded and stored back; pixels past a row's end are
//                       written back unchanged). Triangles at most 4 (AVX2) or 8 (AVX-512)
//                       pixels wide take blocks of rows (AVX2: 4 x 2 pixels per vector;
//                       AVX-512: 4 x 4 or 8 x 2) where the box is at least the block's width;
//                       other triangles up to 4 vectors wide, a row at a time with its vectors
//                       unrolled; wider ones a row at a time in a loop over vectors.
//                       Bit-identical to FillTriangleScalar (same integer coverage, same float
//                       operations, no FMA contraction).
int64_t FillTriangleScalar(const FixedTriangle& t, float* zbuf, int stride);
int64_t FillTriangleSimd(const FixedTriangle& t, float* zbuf, int stride);
// FillTriangleSimd of Widen(t): the same kernel, without the conversion.
int64_t FillCompactSimd(const CompactTriangle& t, float* zbuf, int stride);
// FillCompactSimd of every t[j] with ready[j] != 0, in one dispatch; each counted in *stats as
// rasterized (with its fragments) or, covering no pixel centre, culled between pixels.
void FillCompactBatchSimd(const CompactTriangle* t, const uint8_t* ready, size_t n, float* zbuf, int stride,
                          RasterCounters* stats);
// Sets the pixels of `rect` (box-relative, row stride `stride`) to +infinity, whole vectors
// at a time (Highway, runtime-dispatched); touches nothing outside the rect.
void ClearDepthRectSimd(float* zbuf, int stride, const PixelRect& rect);

enum class RowKernel { kScalar, kSimd };

// Batched triangle setup (render/setup_simd.cc, Highway, runtime-dispatched once per call):
// the vertices of one sample snapped once, then the triangles classified a vector at a time.
// A snapped vertex is (X << 16) | (Y & 0xffff), X and Y in 1/16 pixel relative to the box
// corner as SetupFixedTriangle snaps them, for vertices at or beyond the near plane within
// kSnapBandPx of the corner; kSnappedDeferred for the others (their triangles are left to
// SetupFixedTriangle).
inline constexpr float kSnapBandPx = 2047.f;  // |X|, |Y| < 2^15 sub-pixels
inline constexpr int32_t kSnappedDeferred = INT32_MIN;
struct SnappedVertices {
  std::vector<int32_t> packed;
  std::vector<uint32_t> survivors;  // ClassifyTriangles' output buffer
  std::vector<CompactTriangle> setups;  // SetupSurvivors' output buffers
  std::vector<uint8_t> ready;
};
void SnapVertices(std::span<const ScreenVertex> vertices, const RasterParams& params, SnappedVertices* out);
// ProjectVerticesSimd, SnapVertices and CoverBoundSimd(out, params.box) in one pass over the
// vertices (render/project_simd.cc): the same vertices, packed values and rect (tested).
PixelRect ProjectSnapBoundSimd(std::span<const Eigen::Vector3f> vertices_m, const Eigen::Matrix3f& R,
                               const Eigen::Vector3f& t, const RasterParams& params, std::span<ScreenVertex> out,
                               SnappedVertices* snapped);
// One vertex, scalar: what SnapVertices stores for it (the reference and the vector tail).
inline int32_t SnapVertexScalar(const ScreenVertex& v, float ox, float oy, float z_near) {
  const float du = v.u - ox, dv = v.v - oy;
  if (!(std::fabs(du) < kSnapBandPx && std::fabs(dv) < kSnapBandPx && v.z >= z_near)) return kSnappedDeferred;
  const auto X = static_cast<uint32_t>(std::lrint(du * kSubpixelOne));
  const auto Y = static_cast<uint32_t>(std::lrint(dv * kSubpixelOne));
  return static_cast<int32_t>((X << 16) | (Y & 0xffffu));
}
// The sub-pixel coordinates of a packed vertex (not kSnappedDeferred).
inline int32_t SnappedX(int32_t packed) { return packed >> 16; }
inline int32_t SnappedY(int32_t packed) { return static_cast<int16_t>(packed & 0xffff); }
// Decides every triangle whose fate the snapped integers make certain: back-facing, outside
// the box, between pixel centres. Each gets the reason SetupFixedTriangle gives it (tested),
// counted in *stats (not `triangles`). Writes the indices into `triangles` of the rest
// (front-facing ones that reach a pixel centre; degenerate, nearly degenerate, near-plane and
// deferred ones) to (*survivors)[0, returned count), in increasing order.
size_t ClassifyTriangles(const SnappedVertices& snapped, std::span<const std::array<uint32_t, 3>> triangles,
                         const RasterParams& params, RasterCounters* stats, std::vector<uint32_t>* survivors);

// The per-triangle stage of the batched setup, for ClassifyTriangles' survivors: unpacks the
// snapped vertices into SetupSnappedTriangle, or (a deferred vertex) runs SetupFixedTriangle.
TriangleSetup SetupBatchedTriangle(std::span<const ScreenVertex> vertices, const int32_t* packed,
                                   const std::array<uint32_t, 3>& tri, const RasterParams& params, FixedTriangle* out);

// SetupBatchedTriangle for many survivors at once, a SIMD vector of int32 and float lanes at a
// time (setup_simd.cc; 8 triangles per vector with AVX2, 16 with AVX-512): for each j, ready[j] = 1 and out[j] = Compact of what SetupSnappedTriangle
// sets up (bit-identical) when that would return kReady with simd_fits; ready[j] = 0 otherwise
// (a deferred vertex, any cull, the float path, or a span too wide for the SIMD rows: the
// caller runs SetupBatchedTriangle for it).
void SetupSurvivors(const SnappedVertices& snapped, std::span<const ScreenVertex> vertices,
                    std::span<const std::array<uint32_t, 3>> triangles, const RasterParams& params,
                    std::span<const uint32_t> survivors, CompactTriangle* out, uint8_t* ready);

// Renders the triangles. With `snapped` (SnapVertices of these vertices and params), setup is
// batched: ClassifyTriangles first, then SetupSurvivors, and SetupBatchedTriangle for the
// survivors it leaves; the z-buffer and every statistic are identical to the per-triangle
// setup (triangle order does not change a z-buffer of minima or the counts).
void RasterizeDepthFixedPoint(std::span<const ScreenVertex> vertices,
                              std::span<const std::array<uint32_t, 3>> triangles,
                              const RasterParams& params, float* zbuf, RasterCounters* stats,
                              RowKernel rows = RowKernel::kScalar, SnappedVertices* snapped = nullptr);
// With RowKernel::kSimd, zbuf must have kSimdPadFloats of slack after the box.

}  // namespace mcpose::render
