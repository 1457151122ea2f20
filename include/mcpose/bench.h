// `mcpose bench`: one Monte-Carlo iteration of the paper's workload, timed. Per object: its
// first real frame, the ground-truth visible-mask box (score 1), samples drawn as the
// estimator draws them. Measures
//   - the full iteration (render + inlier + weights + resample + diffuse) by running the
//     estimator's filter for `iterations` iterations with tau = infinity (no early stop),
//     depth only and, where the model has colour, again with the colour term;
//   - render + inlier alone on the initial hypotheses, for mcpose's raster cores and for each
//     baseline (src/baselines) on the same hypotheses, same boxes and same mesh, with the
//     inlier counts compared so that the times are of the same work; interleaved in rounds,
//     so that a slow stretch of a shared machine falls on both.
#pragma once

#include <functional>
#include <istream>
#include <string>
#include <vector>

#include "mcpose/dataset.h"
#include "mcpose/estimator.h"
#include "mcpose/options.h"
#include "mcpose/status.h"

namespace mcpose::bench {

struct BenchOptions {
  std::vector<int> obj_ids;           // empty: the paper's five objects (2, 4, 5, 9, 10)
  EstimatorOptions estimator;         // samples, threads, engine, LOD ...; tau is ignored
  int iterations = 50;                // full iterations timed per object
  // Rounds of render + inlier on the initial hypotheses: each times every baseline once and
  // mcpose about as long (1 to 32 runs), after one untimed run of each.
  int render_repeats = 5;
  std::vector<std::string> baselines;  // "embree", "osmesa"
};

struct BaselineResult {
  std::string name;
  double render_inlier_ms_median = 0;
  double speedup = 0;                  // baseline ms / mcpose ms, same hypotheses
  int64_t inliers_total = 0;           // sum of N over the samples
  double inliers_rel_diff = 0;         // |sum N - mcpose sum N| / mcpose sum N
  double inliers_mean_abs_diff = 0;    // mean over samples of |N - N_mcpose| / max(1, N_r mcpose)
};

struct BenchObject {
  int obj_id = 0;
  std::string name;
  FrameKey frame;
  Detection box;
  int samples = 0, threads = 0;
  int triangles_full = 0, triangles_lod = 0;
  // The chosen LOD level's measured deviation from the full mesh and meshoptimizer's own
  // figure for it, mm (0 for the full mesh).
  double lod_deviation_mm = 0, lod_meshopt_error_mm = 0;
  double triangles_after_cull = 0;     // rasterized triangles per sample render (mean)
  double fragments_per_iteration = 0;  // mean over iterations
  double render_inlier_ms_median = 0, render_inlier_ms_min = 0, render_inlier_ms_max = 0;
  double full_iteration_ms_median = 0, full_iteration_ms_min = 0, full_iteration_ms_max = 0;
  double hypotheses_per_s = 0;         // samples / median full iteration
  // With colour (the model has colour and --appearance on): the same filter on the same
  // hypotheses with the colour term, run right after the depth-only one; 0 without colour.
  bool colour = false;
  double colour_full_iteration_ms_median = 0, colour_render_inlier_ms_median = 0;
  double colour_ratio = 0;             // colour / depth-only median full iteration
  // Render + inlier (+ colour) of the depth-only run's last generation, with and without
  // colour (medians of alternating rounds), and the full iteration's ratio on those same
  // hypotheses (the rest of an iteration taken from the depth-only run).
  double depth_same_render_inlier_ms = 0, colour_same_render_inlier_ms = 0, colour_same_ratio = 0;
  int64_t mcpose_inliers_total = 0;    // on the initial hypotheses (baseline comparison)
  double mcpose_render_inlier_initial_ms = 0;  // median, initial hypotheses
  int mcpose_render_inlier_initial_runs = 0;   // timed runs behind that median
  std::vector<BaselineResult> baselines;
  EngineCounters counters;             // summed over the timed iterations
  std::vector<IterationSummary> per_iteration;
  // Resampling: CDF reads per draw of the paper's table, and of a linear search of the
  // unsorted CDF (bench/naive_cdf.h) for the same draws of every iteration.
  double cdf_reads_per_draw = 0, cdf_reads_per_draw_naive = 0;
  // Observed depth read from the frame, bytes: by the depth distributor (each box cut out once
  // per estimate), and by a per-sample copy of its box every iteration.
  int64_t depth_bytes_read = 0, depth_bytes_read_naive = 0;
};

using BenchProgressFn = std::function<void(const BenchObject&)>;

StatusOr<std::vector<BenchObject>> RunBench(const Dataset& dataset, const BenchOptions& options,
                                            const BenchProgressFn& progress);

// The hardware workload: for each object of `options` (the paper's five by default), the initial
// hypotheses of one `mcpose bench` iteration (its frame, box, LOD level and samples, with
// options.estimator's engine settings but the hw backend) in the raster core's formats, with the
// counts of the C++ model of the core (engine backend hw), written as text to `out` for the RTL
// testbench (hw/sim/, format in docs/hardware.md). Returns the samples written.
StatusOr<int64_t> WriteHardwareWorkload(const Dataset& dataset, const BenchOptions& options, std::ostream& out);

// "model name (family F model M), N logical CPUs" of this machine (from /proc/cpuinfo), for
// records; "unknown CPU, N logical CPUs" where /proc/cpuinfo says nothing.
std::string MachineDescription();
// The same from a /proc/cpuinfo-format stream; hardware_threads where it lists no processor.
std::string MachineDescriptionFrom(std::istream& cpuinfo, int hardware_threads);

}  // namespace mcpose::bench
