#include "score/colour.h"

#include <algorithm>
#include <cmath>

namespace mcpose::score {

ColourStats CountColour(const ColourSample& s, const ColourLookup& g) {
  ColourStats out;
  const float nx = static_cast<float>(g.nx), ny = static_cast<float>(g.ny), nz = static_cast<float>(g.nz);
  // Model point p = R (u z, v z, z) + t of the pixel looking along (u, v, 1), in cell units:
  // g_a = ((R_a0 u + (R_a1 v + R_a2)) inv_cell) z + (t_a - origin_a) inv_cell.
  float c[3];
  for (int a = 0; a < 3; ++a) c[a] = (s.t_model_cam[a] - g.origin[a]) * g.inv_cell;
  const int step = s.step;
  auto first = [step](int v) { return (v + step - 1) / step * step; };  // v >= 0
  for (int y = first(s.rect.y0); y < s.rect.y1; y += step) {
    const float v = (s.grid_y0 + static_cast<float>(y) - s.cy) * s.inv_fy;
    float rv[3];
    for (int a = 0; a < 3; ++a) rv[a] = s.R_model_cam[3 * a + 1] * v + s.R_model_cam[3 * a + 2];
    const float* zr = s.rendered + static_cast<size_t>(y) * s.stride;
    const float* zo = s.observed + static_cast<size_t>(y) * s.stride;
    const uint32_t* rgba = s.observed_rgba + static_cast<size_t>(y) * s.stride;
    for (int x = first(s.rect.x0); x < s.rect.x1; x += step) {
      // A depth inlier with an observed colour...
      const float z = zr[x];
      if (!(z != INFINITY && zo[x] > 0.f && std::fabs(z - zo[x]) < s.eps_m)) continue;
      const uint32_t obs = rgba[x];
      if ((obs >> 24) == 0) continue;
      // ... whose surface point, in the model frame, lies in a grid cell of known colour.
      const float u = (s.grid_x0 + static_cast<float>(x) - s.cx) * s.inv_fx;
      float gc[3];
      for (int a = 0; a < 3; ++a) gc[a] = (s.R_model_cam[3 * a] * u + rv[a]) * g.inv_cell * z + c[a];
      if (!(gc[0] >= 0.f && gc[0] < nx && gc[1] >= 0.f && gc[1] < ny && gc[2] >= 0.f && gc[2] < nz)) continue;
      const uint32_t cell =
          g.cells[(static_cast<size_t>(gc[2]) * g.ny + static_cast<size_t>(gc[1])) * g.nx + static_cast<size_t>(gc[0])];
      if ((cell >> 24) < kKnownAlpha) continue;
      ++out.n;
      for (int ch = 0; ch < 3; ++ch) {
        const int64_t m = (cell >> (8 * ch)) & 0xff, o = (obs >> (8 * ch)) & 0xff;
        out.m[ch] += m, out.o[ch] += o, out.mm[ch] += m * m, out.oo[ch] += o * o, out.mo[ch] += m * o;
      }
    }
  }
  return out;
}

double ColourAgreement(const ColourStats& s, int min_pixels, double hue_first_levels) {
  if (s.n < std::max(min_pixels, 2)) return kNeutralAgreement;
  const double n = static_cast<double>(s.n);
  double r[3] = {0, 0, 0};
  bool varies[3] = {false, false, false};
  bool hue_decides = false;
  for (int c = 0; c < 3; ++c) {
    // n^2 times the variances and the covariance (exact in integers, then double).
    const double vm = static_cast<double>(s.n * s.mm[c] - s.m[c] * s.m[c]);
    const double vo = static_cast<double>(s.n * s.oo[c] - s.o[c] * s.o[c]);
    const double cov = static_cast<double>(s.n * s.mo[c] - s.m[c] * s.o[c]);
    // A channel that does not vary (a standard deviation under 2 of 255 levels) says nothing.
    if (vm < 4.0 * n * n || vo < 4.0 * n * n) continue;
    r[c] = cov / std::sqrt(vm * vo);
    varies[c] = true;
    if (c > 0 && hue_first_levels > 0 && vm >= hue_first_levels * hue_first_levels * n * n) hue_decides = true;
  }
  // Hue first: the hue channels where the model's hue varies enough to carry a pattern, the
  // intensity alone where it does not (an achromatic surface, whose hue is noise).
  double sum = 0;
  int channels = 0;
  for (int c = 0; c < 3; ++c)
    if (varies[c] && (hue_first_levels <= 0 || (c > 0) == hue_decides)) sum += r[c], ++channels;
  if (channels == 0) return kNeutralAgreement;
  return 0.5 * (1.0 + sum / channels);
}

}  // namespace mcpose::score
