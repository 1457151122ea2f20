#include "score/colour_grid.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace mcpose::appearance {

namespace {

uint8_t ToByte(double v) { return static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L)); }

// Alpha-weighted blend of up to four colours with weights w (summing to 1).
Rgba8 Blend(const Rgba8* c, const double* w, int n) {
  double sum[3] = {0, 0, 0}, alpha = 0;
  for (int i = 0; i < n; ++i) {
    const double a = w[i] * c[i].a;
    sum[0] += a * c[i].r, sum[1] += a * c[i].g, sum[2] += a * c[i].b;
    alpha += a;
  }
  if (!(alpha > 0)) return Rgba8{};
  return {ToByte(sum[0] / alpha), ToByte(sum[1] / alpha), ToByte(sum[2] / alpha), ToByte(alpha)};
}

}  // namespace

Rgba8 SampleTexture(const ColourImage& texture, const Eigen::Vector2f& uv) {
  if (!uv.allFinite() || texture.width <= 0 || texture.height <= 0) return Rgba8{};
  const double px = static_cast<double>(uv.x()) * texture.width - 0.5;
  const double py = (1.0 - static_cast<double>(uv.y())) * texture.height - 0.5;
  const double fx0 = std::floor(px), fy0 = std::floor(py);
  const double fx = px - fx0, fy = py - fy0;
  auto clampi = [](double v, int n) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(n - 1))); };
  const int x0 = clampi(fx0, texture.width), x1 = clampi(fx0 + 1, texture.width);
  const int y0 = clampi(fy0, texture.height), y1 = clampi(fy0 + 1, texture.height);
  Rgba8 c[4];
  const int xs[4] = {x0, x1, x0, x1}, ys[4] = {y0, y0, y1, y1};
  for (int i = 0; i < 4; ++i) {
    const uint8_t* p = texture.at(xs[i], ys[i]);
    c[i] = {p[0], p[1], p[2], p[3]};
  }
  const double w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
  return Blend(c, w, 4);
}

Rgba8 SurfaceColour(const Mesh& mesh, size_t t, const Eigen::Vector3f& b) {
  const MeshAppearance& a = mesh.appearance;
  if (a.has_texture()) {
    const auto& uv = a.triangle_uv[t];
    return SampleTexture(*a.texture, b[0] * uv[0] + b[1] * uv[1] + b[2] * uv[2]);
  }
  if (a.has_vertex_colours()) {
    const auto& tri = mesh.triangles[t];
    const Rgba8 c[3] = {a.vertex_colours[tri[0]], a.vertex_colours[tri[1]], a.vertex_colours[tri[2]]};
    const double w[3] = {b[0], b[1], b[2]};
    return Blend(c, w, 3);
  }
  return Rgba8{};
}

std::shared_ptr<const ColourGrid> ColourGrid::Build(const Mesh& mesh) {
  if (mesh.appearance.empty()) return nullptr;
  auto grid = std::make_shared<ColourGrid>();
  ColourGrid& g = *grid;
  // ---- The grid: the mesh's bounds and one cell of margin ---------------------------------
  const Eigen::Vector3f lo = mesh.BoundsMin(), hi = mesh.BoundsMax();
  g.cell_m_ = (hi - lo).maxCoeff() / kCellsLongestSide;
  g.origin_ = lo - Eigen::Vector3f::Constant(g.cell_m_);
  int n[3];
  for (int a = 0; a < 3; ++a) n[a] = static_cast<int>(std::ceil((hi[a] - lo[a]) / g.cell_m_)) + 2;
  g.nx_ = n[0], g.ny_ = n[1], g.nz_ = n[2];
  const size_t cells = static_cast<size_t>(g.nx_) * g.ny_ * g.nz_;
  auto index = [&](const Eigen::Vector3f& p) -> int64_t {
    const Eigen::Vector3f c = (p - g.origin_) / g.cell_m_;
    const int i = static_cast<int>(c.x()), j = static_cast<int>(c.y()), k = static_cast<int>(c.z());
    if (i < 0 || j < 0 || k < 0 || i >= g.nx_ || j >= g.ny_ || k >= g.nz_) return -1;
    return (static_cast<int64_t>(k) * g.ny_ + j) * g.nx_ + i;
  };

  // ---- Sample the surface at half a cell or finer; sum each cell's samples ----------------
  std::vector<double> sum(4 * cells, 0.0);  // alpha-weighted r, g, b, and alpha
  std::vector<uint32_t> count(cells, 0);
  const float step = 0.5f * g.cell_m_;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3f& A = mesh.vertices_m[tri[0]];
    const Eigen::Vector3f& B = mesh.vertices_m[tri[1]];
    const Eigen::Vector3f& C = mesh.vertices_m[tri[2]];
    const float edge = std::max({(B - A).norm(), (C - B).norm(), (A - C).norm()});
    const int k = std::clamp(static_cast<int>(std::ceil(edge / step)), 1, 256);
    for (int i = 0; i <= k; ++i) {
      for (int j = 0; i + j <= k; ++j) {
        const Eigen::Vector3f b(static_cast<float>(k - i - j) / k, static_cast<float>(i) / k, static_cast<float>(j) / k);
        const int64_t c = index(b[0] * A + b[1] * B + b[2] * C);
        if (c < 0) continue;
        const Rgba8 col = SurfaceColour(mesh, t, b);
        double* s = &sum[4 * static_cast<size_t>(c)];
        const double a = col.a;
        s[0] += a * col.r, s[1] += a * col.g, s[2] += a * col.b, s[3] += a;
        ++count[static_cast<size_t>(c)];
      }
    }
  }

  // ---- Cells: the mean colour where the mean alpha says known ------------------------------
  g.cells_.assign(cells, 0u);
  size_t surface = 0, known = 0;
  for (size_t c = 0; c < cells; ++c) {
    if (count[c] == 0) continue;
    ++surface;
    const double* s = &sum[4 * c];
    if (s[3] / count[c] < score::kKnownAlpha) continue;
    g.cells_[c] = Pack({ToByte(s[0] / s[3]), ToByte(s[1] / s[3]), ToByte(s[2] / s[3]), 255});
    ++known;
  }
  g.known_fraction_ = surface ? static_cast<double>(known) / surface : 0.0;

  // ---- One cell of dilation: empty cells take the mean of their known neighbours ----------
  const std::vector<uint32_t> baked = g.cells_;
  for (int k = 0; k < g.nz_; ++k) {
    for (int j = 0; j < g.ny_; ++j) {
      for (int i = 0; i < g.nx_; ++i) {
        const size_t c = (static_cast<size_t>(k) * g.ny_ + j) * g.nx_ + i;
        if (count[c] != 0) continue;
        double s[3] = {0, 0, 0};
        int m = 0;
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const int ii = i + di, jj = j + dj, kk = k + dk;
              if (ii < 0 || jj < 0 || kk < 0 || ii >= g.nx_ || jj >= g.ny_ || kk >= g.nz_) continue;
              const Rgba8 v = Unpack(baked[(static_cast<size_t>(kk) * g.ny_ + jj) * g.nx_ + ii]);
              if (v.a < score::kKnownAlpha) continue;
              s[0] += v.r, s[1] += v.g, s[2] += v.b;
              ++m;
            }
        if (m > 0) g.cells_[c] = Pack({ToByte(s[0] / m), ToByte(s[1] / m), ToByte(s[2] / m), 255});
      }
    }
  }
  g.chroma_cells_.resize(cells);
  g.intensity_hue_cells_.resize(cells);
  for (size_t c = 0; c < cells; ++c) {
    g.chroma_cells_[c] = score::ChromaOf(g.cells_[c]);
    g.intensity_hue_cells_[c] = score::IntensityHueOf(g.cells_[c]);
  }
  return grid;
}

score::ColourLookup ColourGrid::lookup(AppearanceOptions::Space space) const {
  score::ColourLookup l;
  l.cells = space == AppearanceOptions::Space::kChroma          ? chroma_cells_.data()
            : space == AppearanceOptions::Space::kIntensityHue ? intensity_hue_cells_.data()
                                                                : cells_.data();
  l.nx = nx_, l.ny = ny_, l.nz = nz_;
  for (int a = 0; a < 3; ++a) l.origin[a] = origin_[a];
  l.inv_cell = 1.0f / cell_m_;
  return l;
}

Rgba8 ColourGrid::At(const Eigen::Vector3f& p) const {
  const score::ColourLookup l = lookup();
  float g[3];
  for (int a = 0; a < 3; ++a) g[a] = (p[a] - l.origin[a]) * l.inv_cell;
  if (!(g[0] >= 0 && g[0] < nx_ && g[1] >= 0 && g[1] < ny_ && g[2] >= 0 && g[2] < nz_)) return Rgba8{};
  const Rgba8 v = Unpack(cells_[(static_cast<size_t>(g[2]) * ny_ + static_cast<size_t>(g[1])) * nx_ + static_cast<size_t>(g[0])]);
  return v.a >= score::kKnownAlpha ? v : Rgba8{};
}

uint64_t AppearanceFingerprint(const MeshAppearance& a) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const void* data, size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  if (!a.vertex_colours.empty()) mix(a.vertex_colours.data(), a.vertex_colours.size() * sizeof(Rgba8));
  if (!a.triangle_uv.empty()) mix(a.triangle_uv.data(), a.triangle_uv.size() * sizeof(a.triangle_uv[0]));
  if (a.texture) {
    mix(&a.texture->width, sizeof(int));
    mix(&a.texture->height, sizeof(int));
    mix(a.texture->rgba.data(), a.texture->rgba.size());
  }
  return h;
}

}  // namespace mcpose::appearance
