// The paper's raster core and depth distributor in integer arithmetic: a bit-accurate model of
// the hardware numerics (docs/hardware.md gives every signal's width and why it suffices).
//
//   pose          rotation Q1.16 (18 bits), translation in quarter depth units (int32)
//   vertex        model coordinates in quarter depth units (int16, |coordinate| < 0.8192 m)
//   transform     X_cam = (R X + 2^15) >> 16 + t, exact in 34 bits
//   projection    U = round(FX X_cam / (Z_cam 2^8)) + CX: one exact division per coordinate,
//                 U, V box-relative in 1/16 grid pixel; FX = round(16 fx 2^8)
//   inverse depth IZ = floor(2^36 / Z_cam) per vertex, interpolated as a plane in screen space
//                 (1/z is linear there), with 8 fraction bits, stepped by exact additions
//   edges         the integer edge functions of the 1/16-pixel grid with the top-left rule
//   z-buffer      the largest IZ of a pixel (0: nothing drawn), 32 bits
//   inlier test   the depth distributor turns each observed depth d (depth units, 0.1 mm) into
//                 the interval [lo, hi] of IZ with |2^36 / IZ - 4 d| < 4 eps, so the core tests
//                 lo <= IZ <= hi with two comparators and no division per pixel; IZ < lo is a
//                 pixel with something in front of the rendered surface (occluded)
//
// The depth unit is 0.1 mm (YCB-Video's, native and BOP); other sensors' units (1 mm) are
// whole multiples of it. Triangles the hardware does not draw are counted: a vertex nearer than
// the near plane, a vertex further than kGuardBandPx from the box corner, a triangle wider or
// taller than kMaxSpanPx grid pixels.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace mcpose::hw {

// Units and widths (docs/hardware.md).
inline constexpr double kDepthUnitM = 1e-4;  // the depth image's unit: 0.1 mm
inline constexpr int kPositionFracBits = 2;   // positions in 1/4 depth unit (25 um)
inline constexpr double kPositionUnitM = kDepthUnitM / (1 << kPositionFracBits);
inline constexpr int kRotationFracBits = 16;  // rotation entries Q1.16 in 18 bits (a DSP48E2 input)
inline constexpr int kFocalFracBits = 8;      // FX, FY: 1/16 pixel with 8 more fraction bits
inline constexpr int kSubpixelBits = 4;       // 1/16 pixel
inline constexpr int kInverseDepthBits = 36;  // IZ = floor(2^36 / Z)
inline constexpr int kPlaneFracBits = 8;      // the IZ plane's fraction bits
inline constexpr int32_t kMaxModelCoordinate = 32767;  // int16, quarter depth units
inline constexpr int32_t kMinNear = 2048;       // near plane at least 5.12 cm: IZ < 2^25
inline constexpr int32_t kGuardBandPx = 1023;  // |U|, |V| < 1023 grid pixels of the box corner
inline constexpr int32_t kMaxSpanPx = 255;     // a triangle's bounding box, grid pixels per side

// The sample's pose as the core receives it.
struct Pose {
  std::array<int32_t, 9> R{};  // row-major, Q1.16, each in [-2^16, 2^16]
  std::array<int32_t, 3> t{};  // quarter depth units
};
// Rounds R (a rotation) and t (metres) to the core's formats; t beyond +-2^31 quarter units is
// clamped (53 km: never a camera pose).
Pose QuantizePose(const Eigen::Matrix3f& R, const Eigen::Vector3f& t);

// Model vertices in quarter depth units. False (and *out untouched) when a coordinate does not
// fit in int16 (a model more than 0.8192 m from its origin).
using ModelVertex = std::array<int16_t, 3>;
bool QuantizeModel(std::span<const Eigen::Vector3f> vertices_m, std::vector<ModelVertex>* out);

// The grid camera relative to the box corner, and the box.
struct Camera {
  int64_t fx = 0, fy = 0;  // round(16 f 2^8)
  int32_t cx = 0, cy = 0;  // round(16 (c - box corner)), 1/16 pixel
  int32_t width = 0, height = 0;  // the box, grid pixels
  int32_t z_near = 0;      // quarter depth units
};
// fx, fy, cx, cy: the grid camera (pixels); x0, y0: the box corner, width x height its size
// (grid pixels); z_near_m: the near plane.
Camera QuantizeCamera(double fx, double fy, double cx, double cy, int x0, int y0, int width, int height,
                      double z_near_m);

// One vertex after the transform and the projection.
struct Vertex {
  int32_t U = 0, V = 0;  // box-relative, 1/16 pixel (valid when in_band)
  int32_t Z = 0;         // camera depth, quarter depth units
  uint32_t iz = 0;       // floor(2^36 / Z) (valid when !near)
  bool near = false;     // Z < camera.z_near
  bool in_band = false;  // |U|, |V| < kGuardBandPx pixels
};
Vertex TransformVertex(const Pose& pose, const Camera& camera, const ModelVertex& v);

// Integer helpers of the model (exact; the RTL's dividers compute the same).
// floor(n / d) for d > 0.
int64_t FloorDiv(int64_t n, int64_t d);
// n / d rounded to nearest, halves up, for d > 0.
int64_t RoundDiv(int64_t n, int64_t d);

// One triangle after setup: the pixel range to walk, the edge functions at (x_lo, y_lo) (top-left
// bias applied; a pixel is covered when all three are >= 0) and their steps per pixel, and the
// IZ plane at (x_lo, y_lo) and its steps, with kPlaneFracBits fraction bits.
struct Triangle {
  int32_t x_lo = 0, x_hi = -1, y_lo = 0, y_hi = -1;
  int64_t w[3] = {0, 0, 0}, step_x[3] = {0, 0, 0}, step_y[3] = {0, 0, 0};
  int64_t iz = 0, iz_step_x = 0, iz_step_y = 0;
};

enum class Setup {
  kReady,
  kNear,            // a vertex nearer than the near plane
  kGuardBand,       // a vertex outside the guard band
  kDegenerate,      // zero area on the 1/16-pixel grid
  kBackface,        // facing away, with culling on
  kOutsideBox,      // the bounding box misses the box
  kTooLarge,        // wider or taller than kMaxSpanPx
  kBetweenPixels,   // the bounding box holds no pixel centre
};
Setup SetupTriangle(const Vertex& v0, const Vertex& v1, const Vertex& v2, const Camera& camera, bool cull_backfaces,
                    Triangle* out);

// Walks the triangle, keeping the largest IZ of each covered pixel in zbuf (box-sized, row-major,
// 0 = nothing drawn). Returns the covered pixels.
int64_t FillTriangle(const Triangle& t, uint32_t* zbuf, int stride);

// The depth distributor's word for one observed pixel: the core's pixel is an inlier when
// lo <= IZ <= hi, occluded when 0 < IZ < lo; an invalid pixel (no depth) has lo = hi = 0.
struct DepthBounds {
  uint32_t lo = 0, hi = 0;
};
// d: the observed depth in depth units (0: none), eps: the inlier threshold in depth units (> 0).
DepthBounds InlierBounds(int32_t d, int32_t eps);
// The observed depth of a box in depth units (round(z / 0.1 mm), 0 where z is not > 0), and
// eps_m in depth units (at least 1).
std::vector<int32_t> ObservedDepthUnits(std::span<const float> observed_m);
int32_t EpsUnits(float eps_m);

struct Counts {
  int32_t inliers = 0, rendered = 0, occluded = 0;
  bool operator==(const Counts&) const = default;
};
Counts CountBox(std::span<const uint32_t> zbuf, std::span<const DepthBounds> bounds);

// What the core did with a sample's triangles.
struct CoreStats {
  int64_t triangles = 0, drawn = 0, fragments = 0;
  int64_t near = 0, guard_band = 0, degenerate = 0, backface = 0, outside_box = 0, too_large = 0,
          between_pixels = 0;
};

// One sample through the core: clears zbuf (box-sized), transforms every vertex, sets up and
// fills every triangle. `vertices` is scratch (resized).
void RenderSample(std::span<const ModelVertex> model, std::span<const std::array<uint32_t, 3>> triangles,
                  const Pose& pose, const Camera& camera, bool cull_backfaces, std::vector<Vertex>* vertices,
                  std::span<uint32_t> zbuf, CoreStats* stats);

// Metres of an IZ (0: +infinity), for the colour test that runs beside the core on a CPU.
float DepthMetres(uint32_t iz);

}  // namespace mcpose::hw
