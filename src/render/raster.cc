#include "render/raster.h"

#include <algorithm>
#include <cmath>

namespace mcpose::render {

void ProjectVertices(std::span<const Eigen::Vector3f> vertices_m, const Eigen::Matrix3f& R,
                     const Eigen::Vector3f& t, const RasterParams& params,
                     std::span<ScreenVertex> out) {
  for (size_t i = 0; i < vertices_m.size(); ++i) {
    const Eigen::Vector3f p = R * vertices_m[i] + t;
    const float inv_z = 1.0f / p.z();
    out[i].u = params.fx * p.x() * inv_z + params.cx;
    out[i].v = params.fy * p.y() * inv_z + params.cy;
    out[i].z = p.z();
  }
}

PixelRect CoverBound(std::span<const ScreenVertex> vertices, const PixelRect& box) {
  const float none[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
  return CoverBoundFrom(vertices, box, none);
}

PixelRect CoverBoundFrom(std::span<const ScreenVertex> vertices, const PixelRect& box, const float bounds[4]) {
  float min_u = bounds[0], max_u = bounds[1], min_v = bounds[2], max_v = bounds[3];
  bool finite = true;
  for (const ScreenVertex& p : vertices) {
    finite = finite && std::isfinite(p.u) && std::isfinite(p.v);
    min_u = std::min(min_u, p.u), max_u = std::max(max_u, p.u);
    min_v = std::min(min_v, p.v), max_v = std::max(max_v, p.v);
  }
  if (!finite) return box;
  if (!(min_u <= max_u) || max_u < box.x0 || min_u > box.x1 - 1 || max_v < box.y0 || min_v > box.y1 - 1)
    return PixelRect{};
  // Clamped to the box and a little beyond before the conversion to int: a vertex near the
  // camera plane projects far past the range of int. (The rect below is the same.)
  min_u = std::max(min_u, box.x0 - 2.f), max_u = std::min(max_u, box.x1 + 2.f);
  min_v = std::max(min_v, box.y0 - 2.f), max_v = std::min(max_v, box.y1 + 2.f);
  PixelRect r;
  // Rounded outwards by one pixel: vertices snapped to a sub-pixel grid stay inside.
  r.x0 = std::max(box.x0, static_cast<int>(std::floor(min_u)) - 1);
  r.x1 = std::min(box.x1 - 1, static_cast<int>(std::ceil(max_u)) + 1) + 1;
  r.y0 = std::max(box.y0, static_cast<int>(std::floor(min_v)) - 1);
  r.y1 = std::min(box.y1 - 1, static_cast<int>(std::ceil(max_v)) + 1) + 1;
  if (r.empty()) return PixelRect{};
  return r;
}

namespace {

// Edge function of the directed edge a -> b at point p: positive on the left in a y-down image
// for the orientation used below.
inline float Edge(float ax, float ay, float bx, float by, float px, float py) {
  return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

// Top-left rule for a triangle whose edge functions are positive inside: an edge owns the
// pixels exactly on it if it is a "top" edge (horizontal, interior below) or a "left" edge.
inline bool IsTopLeft(float ax, float ay, float bx, float by) {
  const float dx = bx - ax, dy = by - ay;
  return (dy == 0.f && dx < 0.f) || dy > 0.f;
}

}  // namespace

void RasterizeDepthReference(std::span<const ScreenVertex> vertices,
                             std::span<const std::array<uint32_t, 3>> triangles,
                             const RasterParams& params, float* zbuf, RasterCounters* stats) {
  const PixelRect& box = params.box;
  const int stride = box.width();
  RasterCounters s;
  s.triangles_in = static_cast<int64_t>(triangles.size());
  for (const auto& tri : triangles) {
    ScreenVertex a = vertices[tri[0]], b = vertices[tri[1]], c = vertices[tri[2]];

    // Near plane: no clipping, the whole triangle goes.
    if (a.z < params.z_near_m || b.z < params.z_near_m || c.z < params.z_near_m) {
      ++s.culled_near;
      continue;
    }

    // Orientation: front faces have negative signed area (y points down in the image).
    float area = Edge(a.u, a.v, b.u, b.v, c.u, c.v);
    if (area == 0.f || !std::isfinite(area)) {
      ++s.culled_degenerate;
      continue;
    }
    if (area > 0.f) {
      if (params.cull_backfaces) {
        ++s.culled_backface;
        continue;
      }
      std::swap(b, c);  // draw the back face with the same (positive-inside) edge functions
      area = -area;
    }
    // From here the triangle a, b, c has negative area; edge functions of the reversed edges
    // (b -> a etc.) are positive inside.

    // Bounding box of pixel centres, clipped to the box.
    const float min_u = std::min({a.u, b.u, c.u}), max_u = std::max({a.u, b.u, c.u});
    const float min_v = std::min({a.v, b.v, c.v}), max_v = std::max({a.v, b.v, c.v});
    if (max_u < box.x0 || min_u > box.x1 - 1 || max_v < box.y0 || min_v > box.y1 - 1) {
      ++s.culled_outside_box;
      continue;
    }
    // (Clamped to the box before the conversion to int, as in CoverBoundFrom.)
    const int x_lo = std::max(box.x0, static_cast<int>(std::ceil(std::max(min_u, box.x0 - 1.f))));
    const int x_hi = std::min(box.x1 - 1, static_cast<int>(std::floor(std::min(max_u, float(box.x1)))));
    const int y_lo = std::max(box.y0, static_cast<int>(std::ceil(std::max(min_v, box.y0 - 1.f))));
    const int y_hi = std::min(box.y1 - 1, static_cast<int>(std::floor(std::min(max_v, float(box.y1)))));

    // Per-vertex 1/z for perspective-correct depth.
    const float inv_area = 1.0f / -area;
    const float iza = 1.0f / a.z, izb = 1.0f / b.z, izc = 1.0f / c.z;
    const bool tl_bc = IsTopLeft(c.u, c.v, b.u, b.v);
    const bool tl_ca = IsTopLeft(a.u, a.v, c.u, c.v);
    const bool tl_ab = IsTopLeft(b.u, b.v, a.u, a.v);

    int64_t covered = 0;
    for (int y = y_lo; y <= y_hi; ++y) {
      const float py = static_cast<float>(y);
      for (int x = x_lo; x <= x_hi; ++x) {
        const float px = static_cast<float>(x);
        // Barycentric weights (unnormalised) of a, b, c: edges opposite each vertex.
        const float wa = Edge(c.u, c.v, b.u, b.v, px, py);
        const float wb = Edge(a.u, a.v, c.u, c.v, px, py);
        const float wc = Edge(b.u, b.v, a.u, a.v, px, py);
        const bool inside = (wa > 0.f || (wa == 0.f && tl_bc)) &&
                            (wb > 0.f || (wb == 0.f && tl_ca)) &&
                            (wc > 0.f || (wc == 0.f && tl_ab));
        if (!inside) continue;
        ++covered;
        // Depth: interpolate 1/z with the normalised weights.
        const float inv_z = (wa * iza + wb * izb + wc * izc) * inv_area;
        const float z = 1.0f / inv_z;
        float& dst = zbuf[(y - box.y0) * stride + (x - box.x0)];
        if (z < dst) dst = z;
      }
    }
    if (covered == 0) {
      ++s.culled_between_pixels;
    } else {
      ++s.triangles_rasterized;
      s.fragments += covered;
    }
  }
  if (stats) *stats += s;
}

}  // namespace mcpose::render
