#include "hw/raster_core.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mcpose::hw {

namespace {

constexpr int32_t kOne = 1 << kSubpixelBits;
constexpr int64_t kInverseDepthOne = int64_t{1} << kInverseDepthBits;
constexpr uint32_t kMaxIz = std::numeric_limits<uint32_t>::max();

int32_t ClampToInt32(int64_t v) {
  return static_cast<int32_t>(std::clamp<int64_t>(v, std::numeric_limits<int32_t>::min(),
                                                  std::numeric_limits<int32_t>::max()));
}

}  // namespace

int64_t FloorDiv(int64_t n, int64_t d) {
  const int64_t q = n / d;
  return (n % d != 0 && n < 0) ? q - 1 : q;
}

int64_t RoundDiv(int64_t n, int64_t d) { return FloorDiv(2 * n + d, 2 * d); }

Pose QuantizePose(const Eigen::Matrix3f& R, const Eigen::Vector3f& t) {
  Pose p;
  constexpr double one = 1 << kRotationFracBits;
  for (int i = 0; i < 9; ++i)
    p.R[static_cast<size_t>(i)] =
        static_cast<int32_t>(std::clamp<long long>(std::llround(double{R(i / 3, i % 3)} * one), -(1 << kRotationFracBits),
                                                   1 << kRotationFracBits));
  for (int a = 0; a < 3; ++a) {
    const double q = std::round(double{t[a]} / kPositionUnitM);
    p.t[static_cast<size_t>(a)] = std::isfinite(q) ? ClampToInt32(static_cast<int64_t>(std::clamp(q, -4e18, 4e18))) : 0;
  }
  return p;
}

bool QuantizeModel(std::span<const Eigen::Vector3f> vertices_m, std::vector<ModelVertex>* out) {
  std::vector<ModelVertex> q(vertices_m.size());
  for (size_t i = 0; i < vertices_m.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      const double v = std::round(double{vertices_m[i][a]} / kPositionUnitM);
      if (!(std::fabs(v) <= kMaxModelCoordinate)) return false;
      q[i][static_cast<size_t>(a)] = static_cast<int16_t>(v);
    }
  *out = std::move(q);
  return true;
}

Camera QuantizeCamera(double fx, double fy, double cx, double cy, int x0, int y0, int width, int height,
                      double z_near_m) {
  Camera c;
  constexpr double focal_one = double{kOne} * (1 << kFocalFracBits);
  c.fx = std::llround(fx * focal_one), c.fy = std::llround(fy * focal_one);
  c.cx = static_cast<int32_t>(std::lround((cx - x0) * kOne));
  c.cy = static_cast<int32_t>(std::lround((cy - y0) * kOne));
  c.width = width, c.height = height;
  c.z_near = std::max<int32_t>(kMinNear, static_cast<int32_t>(std::lround(z_near_m / kPositionUnitM)));
  return c;
}

Vertex TransformVertex(const Pose& pose, const Camera& camera, const ModelVertex& v) {
  // X_cam = (R X + 2^15) >> 16 + t: each product in 32 bits (|R| <= 2^16, |X| < 2^15), the sum
  // in 34.
  int64_t cam[3];
  for (int r = 0; r < 3; ++r) {
    const int64_t acc = int64_t{pose.R[3 * r]} * v[0] + int64_t{pose.R[3 * r + 1]} * v[1] + int64_t{pose.R[3 * r + 2]} * v[2];
    cam[r] = ((acc + (1 << (kRotationFracBits - 1))) >> kRotationFracBits) + int64_t{pose.t[static_cast<size_t>(r)]};
  }
  Vertex out;
  out.Z = ClampToInt32(cam[2]);
  out.near = cam[2] < camera.z_near;
  if (out.near) return out;
  out.iz = static_cast<uint32_t>(kInverseDepthOne / cam[2]);
  // U = round(FX X / (Z 2^8)) + CX, box-relative 1/16 pixel.
  const int64_t denominator = cam[2] << kFocalFracBits;
  const int64_t U = RoundDiv(camera.fx * cam[0], denominator) + camera.cx;
  const int64_t V = RoundDiv(camera.fy * cam[1], denominator) + camera.cy;
  constexpr int64_t band = int64_t{kGuardBandPx} * kOne;
  out.in_band = U > -band && U < band && V > -band && V < band;
  if (out.in_band) out.U = static_cast<int32_t>(U), out.V = static_cast<int32_t>(V);
  return out;
}

Setup SetupTriangle(const Vertex& v0, const Vertex& v1, const Vertex& v2, const Camera& camera, bool cull_backfaces,
                    Triangle* out) {
  const Vertex* v[3] = {&v0, &v1, &v2};
  if (v0.near || v1.near || v2.near) return Setup::kNear;
  if (!v0.in_band || !v1.in_band || !v2.in_band) return Setup::kGuardBand;
  const int64_t X[3] = {v0.U, v1.U, v2.U}, Y[3] = {v0.V, v1.V, v2.V};
  // Orientation: front faces have negative area (y down).
  int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]);
  if (area == 0) return Setup::kDegenerate;
  int ia = 0, ib = 1, ic = 2;
  if (area > 0) {
    if (cull_backfaces) return Setup::kBackface;
    std::swap(ib, ic);
    area = -area;
  }
  const int64_t min_x = std::min({X[0], X[1], X[2]}), max_x = std::max({X[0], X[1], X[2]});
  const int64_t min_y = std::min({Y[0], Y[1], Y[2]}), max_y = std::max({Y[0], Y[1], Y[2]});
  if (max_x < 0 || min_x > int64_t{camera.width - 1} * kOne || max_y < 0 || min_y > int64_t{camera.height - 1} * kOne)
    return Setup::kOutsideBox;
  if (max_x - min_x > int64_t{kMaxSpanPx} * kOne || max_y - min_y > int64_t{kMaxSpanPx} * kOne) return Setup::kTooLarge;
  // ceil(min / 16) and floor(max / 16), clipped to the box.
  Triangle& t = *out;
  t.x_lo = static_cast<int32_t>(std::max<int64_t>(0, (min_x + kOne - 1) >> kSubpixelBits));
  t.x_hi = static_cast<int32_t>(std::min<int64_t>(camera.width - 1, max_x >> kSubpixelBits));
  t.y_lo = static_cast<int32_t>(std::max<int64_t>(0, (min_y + kOne - 1) >> kSubpixelBits));
  t.y_hi = static_cast<int32_t>(std::min<int64_t>(camera.height - 1, max_y >> kSubpixelBits));
  if (t.x_lo > t.x_hi || t.y_lo > t.y_hi) return Setup::kBetweenPixels;
  // Edge functions of the edges opposite a, b, c (positive inside), at the first pixel centre:
  // E(p) = (P1.x - P0.x)(p.y - P0.y) - (P1.y - P0.y)(p.x - P0.x) for the edge P0 -> P1.
  const int e0[3] = {ic, ia, ib}, e1[3] = {ib, ic, ia};
  const int opposite[3] = {ia, ib, ic};
  const int64_t px0 = int64_t{t.x_lo} * kOne, py0 = int64_t{t.y_lo} * kOne;
  // The IZ plane: the barycentric weight of the vertex opposite edge k is E_k / (-area), so
  // IZ(p) = sum_k E_k(p) IZ_k / (-area); with |E| < 2^25 (a span of at most 255 pixels) and
  // IZ < 2^26 the sums, with 8 fraction bits, fit in 62 bits.
  int64_t plane = 0, plane_x = 0, plane_y = 0;
  for (int k = 0; k < 3; ++k) {
    const int64_t dx = X[e1[k]] - X[e0[k]], dy = Y[e1[k]] - Y[e0[k]];
    const int64_t e = dx * (py0 - Y[e0[k]]) - dy * (px0 - X[e0[k]]);
    const bool top_left = (dy == 0 && dx < 0) || dy > 0;  // pixels on other edges are left out
    t.w[k] = e - (top_left ? 0 : 1);
    t.step_x[k] = -dy * kOne;
    t.step_y[k] = dx * kOne;
    const int64_t iz = v[opposite[k]]->iz;
    plane += e * iz, plane_x += t.step_x[k] * iz, plane_y += t.step_y[k] * iz;
  }
  const int64_t a = -area;
  t.iz = RoundDiv(plane << kPlaneFracBits, a);
  t.iz_step_x = RoundDiv(plane_x << kPlaneFracBits, a);
  t.iz_step_y = RoundDiv(plane_y << kPlaneFracBits, a);
  return Setup::kReady;
}

int64_t FillTriangle(const Triangle& t, uint32_t* zbuf, int stride) {
  int64_t covered = 0;
  int64_t w_row[3] = {t.w[0], t.w[1], t.w[2]};
  int64_t iz_row = t.iz;
  for (int32_t y = t.y_lo; y <= t.y_hi; ++y) {
    int64_t w0 = w_row[0], w1 = w_row[1], w2 = w_row[2], iz = iz_row;
    uint32_t* row = zbuf + static_cast<size_t>(y) * stride;
    for (int32_t x = t.x_lo; x <= t.x_hi; ++x) {
      if ((w0 | w1 | w2) >= 0) {
        ++covered;
        // The plane's integer part, held in [1, 2^32 - 1] (a drawn pixel is never 0).
        const auto value = static_cast<uint32_t>(std::clamp<int64_t>(iz >> kPlaneFracBits, 1, kMaxIz));
        if (value > row[x]) row[x] = value;
      }
      w0 += t.step_x[0], w1 += t.step_x[1], w2 += t.step_x[2], iz += t.iz_step_x;
    }
    w_row[0] += t.step_y[0], w_row[1] += t.step_y[1], w_row[2] += t.step_y[2], iz_row += t.iz_step_y;
  }
  return covered;
}

DepthBounds InlierBounds(int32_t d, int32_t eps) {
  if (d <= 0) return {};
  // |2^36 / IZ - 4 d| < 4 eps  <=>  2^36 / (4 (d + eps)) < IZ < 2^36 / (4 (d - eps)).
  const int64_t far = (int64_t{d} + eps) << kPositionFracBits;
  const int64_t lo = kInverseDepthOne / far + 1;
  int64_t hi = kMaxIz;
  if (d > eps) {
    const int64_t near = (int64_t{d} - eps) << kPositionFracBits;
    hi = (kInverseDepthOne + near - 1) / near - 1;  // ceil(2^36 / near) - 1
  }
  return {static_cast<uint32_t>(std::min<int64_t>(lo, kMaxIz)), static_cast<uint32_t>(std::min<int64_t>(hi, kMaxIz))};
}

std::vector<int32_t> ObservedDepthUnits(std::span<const float> observed_m) {
  std::vector<int32_t> d(observed_m.size(), 0);
  for (size_t i = 0; i < d.size(); ++i)
    if (observed_m[i] > 0.f)
      d[i] = static_cast<int32_t>(std::min<double>(std::lround(double{observed_m[i]} / kDepthUnitM), 1 << 30));
  return d;
}

int32_t EpsUnits(float eps_m) {
  return static_cast<int32_t>(std::clamp<double>(std::lround(double{eps_m} / kDepthUnitM), 1, 1 << 30));
}

Counts CountBox(std::span<const uint32_t> zbuf, std::span<const DepthBounds> bounds) {
  Counts c;
  for (size_t i = 0; i < zbuf.size(); ++i) {
    const uint32_t iz = zbuf[i];
    if (iz == 0) continue;
    ++c.rendered;
    c.inliers += bounds[i].lo <= iz && iz <= bounds[i].hi;
    c.occluded += iz < bounds[i].lo;
  }
  return c;
}

void RenderSample(std::span<const ModelVertex> model, std::span<const std::array<uint32_t, 3>> triangles,
                  const Pose& pose, const Camera& camera, bool cull_backfaces, std::vector<Vertex>* vertices,
                  std::span<uint32_t> zbuf, CoreStats* stats) {
  std::fill(zbuf.begin(), zbuf.end(), 0u);
  vertices->resize(model.size());
  for (size_t i = 0; i < model.size(); ++i) (*vertices)[i] = TransformVertex(pose, camera, model[i]);
  CoreStats s;
  s.triangles = static_cast<int64_t>(triangles.size());
  for (const auto& tri : triangles) {
    Triangle t;
    switch (SetupTriangle((*vertices)[tri[0]], (*vertices)[tri[1]], (*vertices)[tri[2]], camera, cull_backfaces, &t)) {
      case Setup::kReady: {
        const int64_t covered = FillTriangle(t, zbuf.data(), camera.width);
        if (covered == 0) {
          ++s.between_pixels;
        } else {
          ++s.drawn;
          s.fragments += covered;
        }
        break;
      }
      case Setup::kNear: ++s.near; break;
      case Setup::kGuardBand: ++s.guard_band; break;
      case Setup::kDegenerate: ++s.degenerate; break;
      case Setup::kBackface: ++s.backface; break;
      case Setup::kOutsideBox: ++s.outside_box; break;
      case Setup::kTooLarge: ++s.too_large; break;
      case Setup::kBetweenPixels: ++s.between_pixels; break;
    }
  }
  if (stats) {
    stats->triangles += s.triangles, stats->drawn += s.drawn, stats->fragments += s.fragments;
    stats->near += s.near, stats->guard_band += s.guard_band, stats->degenerate += s.degenerate;
    stats->backface += s.backface, stats->outside_box += s.outside_box, stats->too_large += s.too_large;
    stats->between_pixels += s.between_pixels;
  }
}

float DepthMetres(uint32_t iz) {
  if (iz == 0) return INFINITY;
  return static_cast<float>(static_cast<double>(kInverseDepthOne) / iz * kPositionUnitM);
}

}  // namespace mcpose::hw
