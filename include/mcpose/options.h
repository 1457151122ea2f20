// Options of the Monte-Carlo pose estimator. Every field has a documented default;
// EstimatorOptions::IsValid explains the first invalid field.
#pragma once

#include <cstdint>
#include <string>

namespace mcpose {

// How a rendered pixel is tested against the observed depth.
enum class InlierMode {
  k1D,  // |z_rendered - z_observed| < eps at the same pixel (the paper's raster-core test)
  k3D,  // the pixel's back-projected rendered point has an observed point of the box within
        // eps (nearest neighbour in 3-D; the SAND reference test, slow)
};

// Which rasterizer the raster cores run.
enum class RasterBackend {
  kScalar,      // the simple reference rasterizer (float edge functions), the test oracle
  kFixedPoint,  // integer sub-pixel (1/16 px) edge functions stepped incrementally; faster,
                // inlier counts within 0.5% of kScalar (render/raster_fixed.h)
  kSimd,        // kFixedPoint with its pixel rows walked N at a time by Highway (AVX-512,
                // AVX2, SSE4 or scalar, chosen at run time); bit-identical to kFixedPoint
  kFloatSimd,   // kScalar reorganised for Highway: triangles classified and pixels tested a
                // vector at a time with the same float operations; bit-identical to kScalar
};

// The names ParseRasterBackend accepts, for messages: "scalar, fixed, simd or float-simd".
inline constexpr const char* kRasterBackendChoices = "scalar, fixed, simd or float-simd";
// "scalar" / "fixed" / "simd" / "float-simd"; returns false for an unknown name.
bool ParseRasterBackend(const std::string& name, RasterBackend* backend);
const char* RasterBackendName(RasterBackend backend);

// Runtime SIMD dispatch (Highway) of every kernel: the targets compiled in and supported by this
// CPU, best first (e.g. "AVX3 AVX2 SSE4 SSSE3 SCALAR"), and the one the kernels use now.
std::string SimdTargets();
std::string ActiveSimdTarget();
// Caps the dispatch at `name` for the rest of the process, e.g. "AVX2" to measure the AVX2
// kernels on an AVX-512 machine. Results do not change (the kernels are bit-identical on every
// target). Returns false, changing nothing, for a name not in SimdTargets().
bool LimitSimdTarget(const std::string& name);

struct EstimatorOptions {
  // --- Sampling -------------------------------------------------------------------------
  int samples = 620;          // samples per object class per image, over all its boxes
  int max_iterations = 50;    // iteration limit
  double tau = 0.85;          // stop when the mean weight of the samples exceeds tau
  uint64_t seed = 0;          // RNG seed; same seed -> same result at any thread count

  // --- Initialization -------------------------------------------------------------------
  // Translation: the ray through the box centre at the `init_depth_quantile` of the valid
  // observed depths in the box plus half the object's depth extent, jittered by
  // init_sigma_t_m; rotation: uniform on SO(3).
  double init_depth_quantile = 0.5;
  double init_sigma_t_m = 0.01;

  // --- Scoring --------------------------------------------------------------------------
  InlierMode inlier_mode = InlierMode::k1D;
  double eps_m = 0.01;        // inlier threshold, metres
  bool backface_culling = true;
  // w = a * N / N_b + b * N / N_r + c * score, a + b + c = 1. The defaults lean on recall
  // (N / N_b) and the detector score: on the 108 real YCB-Video instances (README, accuracy)
  // the paper-like 0.45 / 0.45 / 0.10 let small well-fitting parts and distractor boxes win.
  double weight_a = 0.55;
  double weight_b = 0.15;
  double weight_c = 0.30;
  // Rendered pixels with an observed surface at least eps in front (occluded by something
  // else) are left out of N_r in the precision term: a partly hidden object is not punished
  // for the part that other objects hide. false = the paper's N_r (every rendered pixel).
  bool occlusion_aware = true;

  // --- Resampling -----------------------------------------------------------------------
  // Resample only from the best fraction of samples, (0, 1]. 1 = the whole population (weights
  // of 0.4-0.9 then hardly select); 0.2 concentrates the search on the best fifth.
  double keep_top_fraction = 0.2;
  int cdf_table_size = 64;         // coarse threshold table entries, >= 1

  // --- Diffusion (annealed: sigma_k = max(sigma_min, sigma_0 * anneal^k)) ----------------
  double sigma_t_m = 0.015;        // translation noise at iteration 0, metres
  double sigma_r_rad = 0.25;       // rotation noise at iteration 0, radians (tangent space)
  double sigma_t_min_m = 0.002;
  double sigma_r_min_rad = 0.03;
  double anneal = 0.93;            // per-iteration factor, (0, 1]
  // Flip moves: each resampled sample is, with this probability, turned 180 degrees about one
  // of the model's axes (chosen at random) through its bounding-box centre before the noise,
  // so the search can jump to the other of two depth-alike twins. 0 = none (and no random
  // draws for them: the same samples as without the option).
  double flip_rate = 0.0;

  // --- Engine ---------------------------------------------------------------------------
  // The default is the fast engine; kScalar with lod_error_px = 0, pixel_stride = 1 and
  // max_grid_pixels = 0 is the reference on every pixel (the test oracle). On the 108 real
  // instances both give the same accuracy within the seed-to-seed spread (README, accuracy).
  RasterBackend backend = RasterBackend::kSimd;
  // Level of detail: each box renders the coarsest meshoptimizer simplification whose
  // measured deviation from the full mesh, projected at the box's initial depth, is at most
  // lod_error_px image pixels, at any pixel stride (render/lod.h, engine/initialize.h).
  // 0 = always the full mesh.
  double lod_error_px = 2.0;
  // Where the LOD levels' vertices lie (render/lod.h): true moves them so that the full surface
  // lies on each level on average (LodVertices::kUnbiased); false keeps meshoptimizer's, a
  // subset of the full mesh's vertices, whose levels lie inside the full surface wherever it
  // bulges (0.19 mm on average for the cracker box's 310-triangle level). Either way a box
  // draws the same level (chosen by the deviation of meshoptimizer's level). No effect with
  // lod_error_px = 0.
  bool lod_unbiased = true;
  // Cluster culling (fixed and simd engines, with LOD): drop whole meshoptimizer clusters of up
  // to 16 triangles that lie outside the box or face away (when back faces are culled), before
  // triangle setup; the same inlier counts as culling triangle by triangle in the tests
  // (render/clusters.h).
  bool cluster_culling = true;
  // Batched triangle setup (fixed and simd engines): snap each sample's vertices once, decide
  // back-facing, outside-box and between-pixel triangles a SIMD vector at a time, and set up the
  // rest a SIMD vector at a time too (render/setup_simd.cc). Bit-identical z-buffers and
  // counters to the per-triangle setup.
  bool batched_setup = true;
  // Pixel stride: score each box on every pixel_stride-th pixel in x and y (the same rays,
  // pixel_stride^2 times fewer; engine/raster_cores.h); the LOD budget is in these raster
  // pixels. 1 (with max_grid_pixels = 0) = every pixel, as the paper. 2 halves the iteration
  // time with the same accuracy on the 108 real instances within the seed-to-seed spread
  // (README, accuracy).
  int pixel_stride = 2;
  // Grid budget: a box with more than this many grid pixels at pixel_stride is sampled more
  // coarsely, at the smallest stride that fits (a resolution level of detail); 0 = no budget.
  // 6000 puts the large boxes of YCB-Video (the cracker box, the bowl: 30 000-45 000 pixels) at
  // stride 3, with the same accuracy on the 108 real instances within the seed spread.
  int max_grid_pixels = 6000;
  int threads = 0;                 // raster cores (worker threads); 0 = hardware threads

  bool IsValid(std::string* error) const;
};

}  // namespace mcpose
