// Options of the Monte-Carlo pose estimator, grouped by the step of the filter they steer.
// Every field has a documented default and one line in the options table
// (mcpose/option_table.h), which gives its flag, JSON key and bounds;
// EstimatorOptions::IsValid names the first invalid field, or the fields of a combination that
// has no effect.
#pragma once

#include <cstdint>
#include <string>

namespace mcpose {

// Practical limits of the options, checked by IsValid (a value past one is a mistake, not a
// request: it would exhaust memory or run for days).
namespace limits {
inline constexpr int kMaxSamples = 1'000'000;       // samples (and tracker samples): ~0.2 GB of particles
inline constexpr int kMaxInitWide = 64;            // init.wide; samples * init.wide <= kMaxSamples too
inline constexpr int kMaxIterations = 10'000;       // filter, tracker, refinement and twin steps
inline constexpr int kMaxCdfTable = 1 << 20;        // resample.cdf_table_size entries
inline constexpr int kMaxThreads = 1024;            // engine.threads
inline constexpr double kMaxSigmaM = 10.0;          // translation sigmas, metres (a scene's scale)
inline constexpr double kMaxSigmaRad = 6.2831853;   // rotation sigmas, radians (a full turn)
// Detector boxes of one image, all classes together: at most this many (detectors keep 100-300;
// each box costs its scorer's buffers, so a million would take minutes and gigabytes); also the
// most instances of a class (max_instances).
inline constexpr int kMaxBoxesPerImage = 10'000;
}  // namespace limits

// How a rendered pixel is tested against the observed depth.
enum class InlierMode {
  k1D,  // |z_rendered - z_observed| < eps at the same pixel (the paper's raster-core test)
  k3D,  // the pixel's back-projected rendered point has an observed point of the box within
        // eps (nearest neighbour in 3-D; the SAND reference test, slow)
};

// Which raster core renders and counts a sample (src/backends/, one file each).
enum class RasterBackend {
  kScalar,      // the float reference: edge functions per pixel; the test oracle
  kFixedPoint,  // vertices snapped to 1/16 pixel, integer edge functions stepped per pixel
  kSimd,        // kFixedPoint with rows, vertices and counts a Highway vector at a time;
                // bit-identical to kFixedPoint
  kFloatSimd,   // kScalar a Highway vector at a time; bit-identical to kScalar
  kHardware,    // the paper's raster core in the hardware's integer numerics (docs/hardware.md):
                // 1-D inliers only, every triangle walked
  kRtl,         // that core's RTL simulated by Verilator: kHardware's counts, some 150 times
                // slower; only in a build where Verilator was found (RtlBackendAvailable)
};

// "scalar" / "fixed" / "simd" / "float-simd" / "hw" / "rtl" (RasterBackendNames() in mcpose/option_table.h);
// false for an unknown name.
bool ParseRasterBackend(const std::string& name, RasterBackend* backend);
const char* RasterBackendName(RasterBackend backend);
// kFixedPoint and kSimd: the backends that snap vertices and so can batch their setup and
// drop culling clusters.
bool IsFixedPoint(RasterBackend backend);
// kHardware and kRtl: the backends in the hardware's integer numerics (the depth distributor's
// bounds, the model in the core's formats).
bool IsHardwareNumerics(RasterBackend backend);
// Whether this build has kRtl (Verilator was found when it was configured).
bool RtlBackendAvailable();

// Step 1: N samples over the boxes in proportion to score. Rotation: uniform on SO(3).
// Translation: on the ray through the box centre, jittered by sigma_t_m, at one of two depths:
// - front: the sample's turned model has its nearest point at the `front_quantile` of the box's
//   valid observed depths (the object's front is among the nearest surfaces of its box);
// - centre: the model's origin at the `depth_quantile` of those depths plus half the object's
//   median side, the same for every turn.
// Neither is right for every object: where a thin object covers less of its box than the table
// behind it, the median depth is the table's and centre samples start behind the object; where
// something nearer shares the box (the objects in a bowl, a mug's handle turned to the camera),
// front samples start too near. `front_share` of each box's samples (every 1/front_share-th,
// no random draw) start at the front depth, the rest at the centre depth.
// `depth_quantile` also sets the depth at which the level of detail is chosen.
struct InitOptions {
  double front_share = 0.5;     // [0, 1]; 0: every sample at the centre depth
  double front_quantile = 0.1;  // [0, 1]
  double depth_quantile = 0.5;  // [0, 1]
  double sigma_t_m = 0.01;      // >= 0, metres
  // The share of each box's samples that start at rest on the plane that supports the box (the
  // largest plane in the depth around it): the model on one of its stable rest faces (drawn by
  // face area), turned at random about the plane's normal, its centre of mass above the plane
  // on the ray through the box centre. Objects lie on tables; a turn drawn over the whole sphere
  // seldom lands near a thin or flat object's. They are taken from the centre samples first
  // (the front samples find what leans on something else or lies on top of it), and past
  // 1 - front_share from the front ones as well. [0, 1]; 0: none. Without a plane the sample
  // starts as the others. 0.5 (with front_share 0.5: the front samples and the rest samples
  // half each) was chosen on the training videos 0000-0003 and the synthetic set of seed 0.
  double rest_share = 0.5;
  // The rest samples of a box stand on rays through random points of the box's central
  // rest_spread share (in width and height), not all on the ray through its centre: the box's
  // centre is seldom above the object's centre of mass (a jittered box, a part hidden, a long
  // object at an angle). [0, 1]; 0: the centre ray alone.
  double rest_spread = 0.5;
  // The first generation holds `wide` times `samples` samples, weighed once; the next
  // generation draws `samples` of them as any other does. A sample must land within about 10
  // degrees and 1 cm of a thin or flat object's pose before the weight prefers it
  // (docs/engine-notes.md); a wide first look lands more of them there for the cost of
  // wide - 1 more iterations. [1, limits::kMaxInitWide]; 1: the paper's first generation.
  int wide = 8;
};

// Step 3: w = a * N / N_b + b * N / N_r + c * score, a + b + c = 1, with N the depth inliers,
// N_b the valid observed pixels of the box and N_r the rendered pixels.
struct WeightOptions {
  InlierMode inlier = InlierMode::k1D;
  double eps_m = 0.01;  // inlier threshold, metres, > 0
  // Recall (a) and the detector score (c) carry most of the weight: with the paper's
  // 0.45 / 0.45 / 0.10, small well-fitting parts and distractor boxes win too often.
  double a = 0.55;
  double b = 0.15;
  double c = 0.30;
  // Leave rendered pixels behind an observed surface (occluded by something else) out of N_r,
  // so that a partly hidden object is not punished for what hides it. false: the paper's N_r.
  bool occlusion_aware = true;
  // Box fit (score/box_fit.h): a sample whose projected object (the bounding rectangle of the
  // model's extreme points) lies less than this share inside its box has its weight scaled by
  // share / box_fit. The detector boxes what it saw, so an object reaching far past its box is
  // unlikely; with boxes moved by up to 10 % a side the truth keeps a median 0.9 inside (under
  // 0.8 for a tenth of the real instances). [0, 1]; 0: off.
  double box_fit = 0.8;
};

// Step 4: sorted-index resampling with a coarse CDF table.
struct ResampleOptions {
  // Draw only from this best fraction of the samples, (0, 1]. With 1, weights of 0.4-0.9
  // hardly select; 0.2 concentrates the search on the best fifth.
  double keep_top_fraction = 0.2;
  int cdf_table_size = 64;  // entries of the coarse threshold table, >= 1
  // The best round(elite_share * samples) samples pass to the next generation as they are (not
  // drawn, not diffused); the others are drawn and diffused. A sample that has found the
  // narrow peak of a thin or flat object's pose then keeps it while the diffusion is still
  // wider than that peak. [0, keep_top_fraction]; 0: the paper's resampling.
  double elite_share = 0.15;
};

// Step 5: Gaussian 6-DoF diffusion, annealed: sigma_k = max(sigma_min, sigma_0 * anneal^k).
struct DiffusionOptions {
  double sigma_t_m = 0.015;       // translation noise at iteration 0, metres
  double sigma_r_rad = 0.25;      // rotation noise at iteration 0, radians (tangent space)
  double sigma_t_min_m = 0.002;
  double sigma_r_min_rad = 0.03;
  double anneal = 0.93;           // per-iteration factor, (0, 1]
  // Flip moves: a resampled sample turns, with this probability, 180 degrees about one of the
  // model's axes (chosen at random) through its bounding-box centre before its noise, so the
  // search can jump between two depth-alike twins. 0: no flips and no random draws for them.
  double flip_rate = 0.0;
};

// Step 2: the engine that renders each sample in its box and counts its inliers. Every speed
// feature is an option; the reference (Reference()) runs none of them.
// The SIMD target an estimator's kernels dispatch to: kBest (the best this CPU has), or a cap at
// the k-th name of SimdTargetNames() (mcpose/option_table.h), e.g. AVX2 on an AVX-512 machine.
// Every kernel is bit-identical on every target: only the speed changes.
enum class SimdTarget : int { kBest = 0 };

struct EngineOptions {
  RasterBackend backend = RasterBackend::kSimd;
  bool backface_culling = true;
  // Pixel stride s: each box is scored on every s-th pixel in x and y (the same rays, s^2
  // times fewer), [1, 16].
  int pixel_stride = 2;
  // A box with more grid pixels than this at pixel_stride is scored at the smallest coarser
  // stride that fits; 0 = no budget.
  int max_grid_pixels = 6000;
  // Level of detail: each box renders the coarsest meshoptimizer simplification whose measured
  // deviation from the full mesh, at the box's initial depth, is at most this many image
  // pixels. 0 = always the full mesh.
  double lod_error_px = 2.0;
  // LOD levels' vertices moved so that the full surface lies on each level on average (false:
  // meshoptimizer's, a subset of the full mesh's vertices, inside the surface where it
  // bulges). Needs lod_error_px > 0.
  bool lod_unbiased = true;
  // Drop whole meshoptimizer clusters of up to 16 triangles outside the box or facing away
  // before triangle setup. Needs lod_error_px > 0 (the clusters come with the LOD levels) and
  // a fixed-point backend.
  bool cluster_culling = true;
  // Snap each sample's vertices once, then decide and set up its triangles a SIMD vector at a
  // time: bit-identical to the per-triangle setup. Needs a fixed-point backend.
  bool batched_setup = true;
  int threads = 0;  // worker threads; 0 = one per hardware thread
  SimdTarget simd_target = SimdTarget::kBest;  // this estimator's threads only

  // The float reference on every pixel of the full mesh, with no speed feature: the oracle
  // every fast engine is tested against.
  static EngineOptions Reference();
  // Turns off the features this backend and LOD setting cannot use (lod_unbiased and
  // cluster_culling without LOD, cluster_culling and batched_setup on a float backend), so
  // that choosing a backend needs no other change.
  void DropUnusableFeatures();
};

// Colour: a term of the weight that tells apart poses depth alone cannot (a box turned 180
// degrees, a can about its axis). Used for an object class wherever its model has colour
// (a texture or vertex colours) and the frame has a colour image.
struct AppearanceOptions {
  // false: depth only, the poses of an estimator without colour exactly.
  bool enabled = true;
  // d in w = (1 - d) (a N/N_b + b N/N_r + c score) + d A, with A in [0, 1] the colour
  // agreement of the depth inliers (score/colour.h), [0, 1).
  double weight = 0.3;
  // A sample with fewer depth inliers of known colour than this gets the neutral A = 0.5.
  int min_pixels = 20;
  // Trust in the colour evidence: the agreement is drawn towards neutral by n / (n + trust_pixels),
  // n the depth inliers of known colour tested (score/weight.h), so that colour seen on a few
  // pixels cannot overrule the depth and the box. >= 0; 0: no such pull (the default: with 30,
  // the captured-colour run on the training videos fell from 78.5 to 75.3 % ADD(-S) < 4 cm).
  double trust_pixels = 0;
  // The colour test reads every pixel_step-th pixel of each box's grid in x and y (1 to 4):
  // a few hundred pixels tell the agreement as well as all of them, at a fraction of the cost.
  int pixel_step = 3;
  // The colour term's weight grows over the filter's first ramp_iterations, d (k + 1) / ramp at
  // iteration k: colour narrows the basin of the right pose, so depth leads the search while it
  // is wide. The answer is the best sample weighed with the full d. 0: d from the start.
  int ramp_iterations = 15;
  // What is compared: kRgb the colour as it is; kChroma the normalised colour c / (r + g + b),
  // which shading does not change (pixels darker than r + g + b = 30 count as unknown);
  // kIntensityHue the intensity and two channels of the normalised colour.
  enum class Space { kRgb, kChroma, kIntensityHue };
  Space space = Space::kIntensityHue;
  // "rgb", "chroma", "intensity-hue"; Parse: false for another name.
  static const char* SpaceName(Space space);
  static bool ParseSpace(const std::string& name, Space* space);
  // Hue first (intensity-hue only; IsValid refuses it with another space): where the model's
  // hue varies over the tested pixels with a standard deviation of at least this many levels (of
  // 255), the colour term compares the hue alone, which shading does not change; elsewhere the
  // intensity alone (an achromatic surface). 0 (the default): the mean of intensity and hue everywhere. On the training videos 0000-0003,
  // 8 gains with the objects' real textures and loses with colour captured from frames
  // (docs/engine-notes.md, "Colour in other light"), so it is for textured models.
  double hue_first_levels = 0;
  // The observed colour of each tested pixel is the mean of the (2 r + 1)^2 pixels around it,
  // r = smooth_radius (0 to 3; 0: the pixel alone): sensor noise and compression artefacts
  // average out, as they do in the model's colour grid, whose cells span a few millimetres.
  int smooth_radius = 1;
  // Leave out observed pixels with a clipped channel (at 255, or at a level many of the box's
  // pixels share: a saturated sensor or tone curve), whose hue is wrong.
  bool drop_clipped = true;
  // Twin resolution, after the filter, for objects scored with colour: the best pose and its
  // depth twins (180-degree turns about the model axes through its bounding-box centre, each
  // also turned about the model's most distinct axis in steps of twin_step_deg) scored on every
  // pixel of the full mesh; the best one is refined by twin_refine_iterations of the filter at
  // the smallest diffusion.
  bool resolve_twins = true;
  double twin_step_deg = 30;     // divides 360; 180 = the flips alone
  int twin_refine_iterations = 10;
  // Among the candidates whose depth weight (the weight without its colour term) lies within
  // this of the best candidate's, the one whose colour agrees best wins: depth cannot tell
  // those apart, so colour decides alone. 0: the candidate of the highest whole weight.
  double twin_depth_margin = 0.0;
};

// Refinement: after the filter (and twin resolution), the pose is aligned to the observed depth
// in its box by projective point-to-plane steps with a robust loss (refine/align.h), and kept
// only if that does not lower its full-resolution weight, the weight's inliers counted within
// accept_eps_m. Twin resolution aligns each of its candidates the same way before comparing them.
struct RefineOptions {
  bool enabled = true;           // false: the filter's answer as it is
  int max_iterations = 20;       // Gauss-Newton steps
  int twin_iterations = 8;       // steps for each twin candidate
  double tukey_m = 0.006;        // robust loss scale, metres
  double max_distance_m = 0.02;  // model and observed points farther apart are not paired
  // The inlier threshold of the weight that judges the aligned pose against the filter's, metres;
  // 0: the filter's own (weight.eps_m). Within the filter's centimetre two poses a few millimetres
  // apart differ only by the pixels at the object's outline, where the sensor's depth is least
  // sure; at a few millimetres every pixel of the surface tells them apart.
  double accept_eps_m = 0.004;
};

struct EstimatorOptions {
  int samples = 620;         // per object class per image, over all its boxes, >= 1
  int max_iterations = 50;   // >= 1
  double tau = 0.85;         // Step 6: stop when the mean weight of the samples exceeds tau
  uint64_t seed = 0;         // same seed, same result at any thread count
  // Instances of one class an image may hold (0 to limits::kMaxBoxesPerImage; 0: as many as
  // its boxes show). The first is the filter's over all the class's boxes; each further cluster
  // of boxes (engine/instances.h) gets a filter of its own, and its pose is another instance
  // unless it explains the depth pixels of one kept before it. 1: one pose per class.
  int max_instances = 0;

  InitOptions init;
  WeightOptions weight;
  ResampleOptions resample;
  DiffusionOptions diffusion;
  EngineOptions engine;
  AppearanceOptions appearance;
  RefineOptions refine;

  // True if every field is in range and every feature asked for has an effect; otherwise
  // false with a message naming the field(s).
  bool IsValid(std::string* error) const;
};

}  // namespace mcpose
