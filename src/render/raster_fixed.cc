#include "render/raster_fixed.h"

#include <algorithm>
#include <cmath>

namespace mcpose::render {

namespace {

constexpr int32_t kOne = kSubpixelOne;

}  // namespace

CompactTriangle Compact(const FixedTriangle& t) {
  CompactTriangle c;
  c.x_lo = t.x_lo, c.x_hi = t.x_hi, c.y_lo = t.y_lo, c.y_hi = t.y_hi;
  for (int k = 0; k < 3; ++k) {
    c.w_row[k] = static_cast<int32_t>(t.w_row[k]);
    c.step_x[k] = static_cast<int32_t>(t.step_x[k]), c.step_y[k] = static_cast<int32_t>(t.step_y[k]);
  }
  c.A = t.A, c.B = t.B, c.C = t.C;
  return c;
}

FixedTriangle Widen(const CompactTriangle& c) {
  FixedTriangle t;
  t.x_lo = c.x_lo, t.x_hi = c.x_hi, t.y_lo = c.y_lo, t.y_hi = c.y_hi;
  for (int k = 0; k < 3; ++k) t.w_row[k] = c.w_row[k], t.step_x[k] = c.step_x[k], t.step_y[k] = c.step_y[k];
  t.A = c.A, t.B = c.B, t.C = c.C;
  t.simd_fits = true;
  return t;
}

int64_t FillTriangleScalar(const FixedTriangle& t, float* zbuf, int stride) {
  int64_t covered = 0;
  int64_t w_row[3] = {t.w_row[0], t.w_row[1], t.w_row[2]};
  for (int32_t y = t.y_lo; y <= t.y_hi; ++y) {
    int64_t w0 = w_row[0], w1 = w_row[1], w2 = w_row[2];
    float* row = zbuf + static_cast<size_t>(y) * stride;
    const float row_c = t.B * static_cast<float>(y) + t.C;
    for (int32_t x = t.x_lo; x <= t.x_hi; ++x) {
      if ((w0 | w1 | w2) >= 0) {
        ++covered;
        const float z = 1.0f / (t.A * static_cast<float>(x) + row_c);
        if (z < row[x]) row[x] = z;
      }
      w0 += t.step_x[0], w1 += t.step_x[1], w2 += t.step_x[2];
    }
    w_row[0] += t.step_y[0], w_row[1] += t.step_y[1], w_row[2] += t.step_y[2];
  }
  return covered;
}

TriangleSetup SetupFixedTriangle(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2,
                                 const RasterParams& params, FixedTriangle* out) {
  const PixelRect& box = params.box;
  const ScreenVertex* v[3] = {&v0, &v1, &v2};
  // Fixed-point coordinates are taken relative to the box origin to keep them small.
  const float ox = static_cast<float>(box.x0), oy = static_cast<float>(box.y0);

  // Near plane, as in the reference.
  if (v[0]->z < params.z_near_m || v[1]->z < params.z_near_m || v[2]->z < params.z_near_m) {
    return TriangleSetup::kCulledNear;
  }

  // Outside the guard band (or not finite): leave it to the float reference.
  bool in_band = true;
  for (const ScreenVertex* p : v) {
    in_band = in_band && std::fabs(p->u - ox) < kGuardBandPx && std::fabs(p->v - oy) < kGuardBandPx;
  }
  if (!in_band) return TriangleSetup::kFloatPath;

  // Snap to the sub-pixel grid.
  int32_t X[3], Y[3];
  for (int k = 0; k < 3; ++k) {
    X[k] = static_cast<int32_t>(std::lrint((v[k]->u - ox) * kOne));
    Y[k] = static_cast<int32_t>(std::lrint((v[k]->v - oy) * kOne));
  }
  const float z[3] = {v0.z, v1.z, v2.z};
  return SetupSnappedTriangle(X, Y, z, params, out);
}

TriangleSetup SetupSnappedTriangle(const int32_t X[3], const int32_t Y[3], const float z[3], const RasterParams& params,
                                   FixedTriangle* out) {
  const PixelRect& box = params.box;

  // Orientation on the snapped triangle: front faces have negative area (y down).
  int64_t area = int64_t{X[1] - X[0]} * (Y[2] - Y[0]) - int64_t{Y[1] - Y[0]} * (X[2] - X[0]);
  if (area == 0) return TriangleSetup::kCulledDegenerate;
  int ia = 0, ib = 1, ic = 2;
  if (area > 0) {
    if (params.cull_backfaces) return TriangleSetup::kCulledBackface;
    std::swap(ib, ic);
    area = -area;
  }

  // Bounding box in whole pixels (box-relative), clipped to the box.
  const int32_t min_x = std::min({X[0], X[1], X[2]}), max_x = std::max({X[0], X[1], X[2]});
  const int32_t min_y = std::min({Y[0], Y[1], Y[2]}), max_y = std::max({Y[0], Y[1], Y[2]});
  const int32_t bw = box.width(), bh = box.height();
  if (max_x < 0 || min_x > (bw - 1) * kOne || max_y < 0 || min_y > (bh - 1) * kOne) {
    return TriangleSetup::kCulledOutsideBox;
  }
  if (max_x - min_x > kMaxSpanPx * kOne || max_y - min_y > kMaxSpanPx * kOne) return TriangleSetup::kFloatPath;
  // ceil(min / kOne) and floor(max / kOne) for possibly negative values.
  const int32_t x_lo = std::max(0, (min_x + kOne - 1) >> kSubpixelBits);
  const int32_t x_hi = std::min(bw - 1, max_x >> kSubpixelBits);
  const int32_t y_lo = std::max(0, (min_y + kOne - 1) >> kSubpixelBits);
  const int32_t y_hi = std::min(bh - 1, max_y >> kSubpixelBits);
  if (x_lo > x_hi || y_lo > y_hi) return TriangleSetup::kCulledBetweenPixels;

  // Edge functions of the reversed edges (positive inside), opposite vertices a, b, c:
  // E(p) = (P1.x - P0.x) * (p.y - P0.y) - (P1.y - P0.y) * (p.x - P0.x) for edge P0 -> P1.
  // Stepping one pixel in x adds -(P1.y - P0.y) * kOne, in y adds (P1.x - P0.x) * kOne.
  FixedTriangle& ft = *out;
  ft.x_lo = x_lo, ft.x_hi = x_hi, ft.y_lo = y_lo, ft.y_hi = y_hi;
  const int e0[3] = {ic, ia, ib};  // edge start: c->b (opp. a), a->c (opp. b), b->a (opp. c)
  const int e1[3] = {ib, ic, ia};
  const int64_t px0 = int64_t{x_lo} * kOne, py0 = int64_t{y_lo} * kOne;
  // 1/z as a plane over pixel coordinates: inv_z = A x + B y + C (box-relative pixels), in
  // float, each operation in this order (the batched setup repeats it lane by lane). The
  // integer terms are exact before their one conversion to float. The barycentric weight of
  // vertex k is E_k(p) / (-area); E_k is linear in p with gradient (step_x, step_y) per pixel,
  // and E_k(0, 0) = dy_k X_0 - dx_k Y_0.
  const float inv_area = 1.0f / static_cast<float>(-area);
  const float iz[3] = {1.0f / z[ia], 1.0f / z[ib], 1.0f / z[ic]};
  float A = 0, B = 0, C = 0;
  for (int k = 0; k < 3; ++k) {
    const int64_t dx = X[e1[k]] - X[e0[k]], dy = Y[e1[k]] - Y[e0[k]];
    // Top-left rule (same predicate as the reference): pixels exactly on a non-owning
    // edge are excluded by a bias of -1.
    const bool top_left = (dy == 0 && dx < 0) || dy > 0;
    ft.w_row[k] = dx * (py0 - Y[e0[k]]) - dy * (px0 - X[e0[k]]) - (top_left ? 0 : 1);
    ft.step_x[k] = -dy * kOne;
    ft.step_y[k] = dx * kOne;
    const float wk = iz[k] * inv_area;
    A += static_cast<float>(ft.step_x[k]) * wk;
    B += static_cast<float>(ft.step_y[k]) * wk;
    C += static_cast<float>(dy * X[e0[k]] - dx * Y[e0[k]]) * wk;
  }
  ft.A = A, ft.B = B, ft.C = C;
  // Edge functions fit in 32 bits for the SIMD rows when the span is small enough.
  ft.simd_fits = max_x - min_x <= kMaxSimdSpanPx * kOne && max_y - min_y <= kMaxSimdSpanPx * kOne;
  return TriangleSetup::kReady;
}

TriangleSetup SetupBatchedTriangle(std::span<const ScreenVertex> vertices, const int32_t* packed,
                                   const std::array<uint32_t, 3>& tri, const RasterParams& params, FixedTriangle* out) {
  int32_t X[3], Y[3];
  float z[3];
  for (int k = 0; k < 3; ++k) {
    const int32_t p = packed[tri[k]];
    if (p == kSnappedDeferred) return SetupFixedTriangle(vertices[tri[0]], vertices[tri[1]], vertices[tri[2]], params, out);
    X[k] = SnappedX(p), Y[k] = SnappedY(p), z[k] = vertices[tri[k]].z;
  }
  return SetupSnappedTriangle(X, Y, z, params, out);
}

namespace {

// A triangle's covered pixel count, counted in *s.
inline void CountFill(int64_t covered, RasterCounters* s) {
  if (covered == 0) {
    ++s->culled_between_pixels;
  } else {
    ++s->triangles_rasterized;
    s->fragments += covered;
  }
}

// The rows of one set-up triangle, counted in *s.
inline void FillOne(const FixedTriangle& ft, float* zbuf, int stride, RowKernel rows, RasterCounters* s) {
  // Walk the bounding box a vector of pixels at a time where the edge functions fit in 32 bits
  // (render/raster_simd.cc); both kernels give bit-identical results.
  const bool simd = rows == RowKernel::kSimd && ft.simd_fits;
  CountFill(simd ? FillTriangleSimd(ft, zbuf, stride) : FillTriangleScalar(ft, zbuf, stride), s);
}

// Setup and rows of one triangle (triangles[t]), counted in *s.
// With `packed` (SnapVertices), the batched setup's per-triangle stage.
inline void RasterizeOne(std::span<const ScreenVertex> vertices, std::span<const std::array<uint32_t, 3>> triangles,
                         size_t t, const RasterParams& params, float* zbuf, int stride, RowKernel rows,
                         RasterCounters* s, const int32_t* packed = nullptr) {
  const auto& tri = triangles[t];
  FixedTriangle ft;
  const TriangleSetup setup =
      packed ? SetupBatchedTriangle(vertices, packed, tri, params, &ft)
             : SetupFixedTriangle(vertices[tri[0]], vertices[tri[1]], vertices[tri[2]], params, &ft);
  switch (setup) {
    case TriangleSetup::kCulledNear: ++s->culled_near; return;
    case TriangleSetup::kCulledDegenerate: ++s->culled_degenerate; return;
    case TriangleSetup::kCulledBackface: ++s->culled_backface; return;
    case TriangleSetup::kCulledOutsideBox: ++s->culled_outside_box; return;
    case TriangleSetup::kCulledBetweenPixels: ++s->culled_between_pixels; return;
    case TriangleSetup::kFloatPath:
      RasterizeDepthReference(vertices, triangles.subspan(t, 1), params, zbuf, s);
      --s->triangles_in;  // counted once by the caller
      return;
    case TriangleSetup::kReady: break;
  }
  FillOne(ft, zbuf, stride, rows, s);
}

}  // namespace

void RasterizeDepthFixedPoint(std::span<const ScreenVertex> vertices,
                              std::span<const std::array<uint32_t, 3>> triangles, const RasterParams& params,
                              float* zbuf, RasterCounters* stats, RowKernel rows, SnappedVertices* snapped) {
  const int stride = params.box.width();
  RasterCounters s;
  s.triangles_in = static_cast<int64_t>(triangles.size());
  if (snapped) {
    const size_t kept = ClassifyTriangles(*snapped, triangles, params, &s, &snapped->survivors);
    snapped->setups.resize(std::max(snapped->setups.size(), kept));
    snapped->ready.resize(std::max(snapped->ready.size(), kept));
    SetupSurvivors(*snapped, vertices, triangles, params, std::span(snapped->survivors.data(), kept),
                   snapped->setups.data(), snapped->ready.data());
    // The ready triangles' rows, then the rest (culled, float path or a deferred vertex) in the
    // per-triangle stage: the z-buffer keeps the nearest depth, so the order does not matter.
    if (rows == RowKernel::kSimd) {
      FillCompactBatchSimd(snapped->setups.data(), snapped->ready.data(), kept, zbuf, stride, &s);
    }
    for (size_t j = 0; j < kept; ++j) {
      if (snapped->ready[j]) {
        if (rows != RowKernel::kSimd) CountFill(FillTriangleScalar(Widen(snapped->setups[j]), zbuf, stride), &s);
      } else {
        RasterizeOne(vertices, triangles, snapped->survivors[j], params, zbuf, stride, rows, &s,
                     snapped->packed.data());
      }
    }
  } else {
    for (size_t t = 0; t < triangles.size(); ++t) RasterizeOne(vertices, triangles, t, params, zbuf, stride, rows, &s);
  }
  if (stats) *stats += s;
}

}  // namespace mcpose::render
