#include "score/colour.h"

#include <cmath>

namespace mcpose::score {

ColourStats CountColour(const ColourSample& s, const ColourLookup& g) {
  ColourStats out;
  const float R0 = s.R_model_cam[0], R1 = s.R_model_cam[1], R2 = s.R_model_cam[2];
  const float R3 = s.R_model_cam[3], R4 = s.R_model_cam[4], R5 = s.R_model_cam[5];
  const float R6 = s.R_model_cam[6], R7 = s.R_model_cam[7], R8 = s.R_model_cam[8];
  const float nx = static_cast<float>(g.nx), ny = static_cast<float>(g.ny), nz = static_cast<float>(g.nz);
  for (int y = s.rect.y0; y < s.rect.y1; ++y) {
    const float v = (s.grid_y0 + static_cast<float>(y) - s.cy) * s.inv_fy;
    const float* zr = s.rendered + static_cast<size_t>(y) * s.stride;
    const float* zo = s.observed + static_cast<size_t>(y) * s.stride;
    const uint32_t* rgba = s.observed_rgba + static_cast<size_t>(y) * s.stride;
    for (int x = s.rect.x0; x < s.rect.x1; ++x) {
      // A depth inlier with an observed colour...
      const float z = zr[x];
      if (!(z != INFINITY && zo[x] > 0.f && std::fabs(z - zo[x]) < s.eps_m)) continue;
      const uint32_t obs = rgba[x];
      if ((obs >> 24) == 0) continue;
      // ... whose surface point, in the model frame, lies in a grid cell of known colour.
      const float u = (s.grid_x0 + static_cast<float>(x) - s.cx) * s.inv_fx;
      const float px = u * z, py = v * z;
      const float gx = (R0 * px + R1 * py + R2 * z + s.t_model_cam[0] - g.origin[0]) * g.inv_cell;
      const float gy = (R3 * px + R4 * py + R5 * z + s.t_model_cam[1] - g.origin[1]) * g.inv_cell;
      const float gz = (R6 * px + R7 * py + R8 * z + s.t_model_cam[2] - g.origin[2]) * g.inv_cell;
      if (!(gx >= 0.f && gx < nx && gy >= 0.f && gy < ny && gz >= 0.f && gz < nz)) continue;
      const uint32_t cell = g.cells[(static_cast<size_t>(gz) * g.ny + static_cast<size_t>(gy)) * g.nx + static_cast<size_t>(gx)];
      if ((cell >> 24) < kKnownAlpha) continue;
      ++out.n;
      for (int c = 0; c < 3; ++c) {
        const int64_t m = (cell >> (8 * c)) & 0xff, o = (obs >> (8 * c)) & 0xff;
        out.m[c] += m, out.o[c] += o, out.mm[c] += m * m, out.oo[c] += o * o, out.mo[c] += m * o;
      }
    }
  }
  return out;
}

double ColourAgreement(const ColourStats& s, int min_pixels) {
  if (s.n < std::max(min_pixels, 2)) return kNeutralAgreement;
  const double n = static_cast<double>(s.n);
  double sum = 0;
  int channels = 0;
  for (int c = 0; c < 3; ++c) {
    // n^2 times the variances and the covariance (exact in integers, then double).
    const double vm = static_cast<double>(s.n * s.mm[c] - s.m[c] * s.m[c]);
    const double vo = static_cast<double>(s.n * s.oo[c] - s.o[c] * s.o[c]);
    const double cov = static_cast<double>(s.n * s.mo[c] - s.m[c] * s.o[c]);
    // A channel that does not vary (a standard deviation under 2 of 255 levels) says nothing.
    if (vm < 4.0 * n * n || vo < 4.0 * n * n) continue;
    sum += cov / std::sqrt(vm * vo);
    ++channels;
  }
  if (channels == 0) return kNeutralAgreement;
  return 0.5 * (1.0 + sum / channels);
}

}  // namespace mcpose::score
