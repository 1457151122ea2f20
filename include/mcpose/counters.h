// The engine's counters, each named once: a counter is one line of these lists, which declare
// the fields, sum them and write them to JSON (`estimate --out-json`, `bench --json`) under
// their names. The raster cores count the first list per sample render (RasterCounters); an
// estimate sums them with the filter's own (EngineCounters, mcpose/estimator.h). Every triangle
// submitted has exactly one fate: the culled_* counts plus triangles_rasterized sum to
// triangles_in.
#pragma once

#include <cstdint>

// X(name, doc) for each counter of the raster cores.
#define MCPOSE_RASTER_COUNTERS(X)                                                              \
  X(triangles_in, "triangles submitted (after the LOD choice)")                                \
  X(culled_backface, "triangles facing away")                                                  \
  X(culled_degenerate, "triangles of no area")                                                 \
  X(culled_outside_box, "triangles that miss the sample's box")                                \
  X(culled_near, "triangles with a vertex behind the near plane")                              \
  X(culled_between_pixels, "triangles that cover no pixel centre")                             \
  X(culled_hw_range, "triangles outside the hardware core's range (engine hw): a vertex "       \
                     "beyond its guard band or a side over 255 pixels")                        \
  X(triangles_rasterized, "triangles that covered at least one pixel centre")                  \
  X(fragments, "pixel centres covered, before the depth test")                                 \
  X(clusters, "culling clusters tested (cluster_culling)")                                     \
  X(clusters_culled_backface, "clusters dropped whole, facing away (their triangles counted "  \
                              "in culled_backface)")                                           \
  X(clusters_culled_outside_box, "clusters dropped whole, outside the box (their triangles "   \
                                 "counted in culled_outside_box)")

// X(name, doc) for each counter of an estimate: the raster cores' and the filter's.
#define MCPOSE_ENGINE_COUNTERS(X)                                                 \
  X(triangles_full, "triangles the full mesh would have submitted")               \
  MCPOSE_RASTER_COUNTERS(X)                                                       \
  X(cdf_draws, "resampling draws")                                                \
  X(cdf_reads, "CDF and table entries those draws read")

namespace mcpose {

#define MCPOSE_COUNTER_FIELD(name, doc) int64_t name = 0;
#define MCPOSE_COUNTER_ADD(name, doc) name += o.name;

// What the raster cores count while rendering samples.
struct RasterCounters {
  MCPOSE_RASTER_COUNTERS(MCPOSE_COUNTER_FIELD)

  RasterCounters& operator+=(const RasterCounters& o) {
    MCPOSE_RASTER_COUNTERS(MCPOSE_COUNTER_ADD)
    return *this;
  }
  bool operator==(const RasterCounters&) const = default;
};

// What an estimate counts: the raster cores' counters summed over its renders, the triangles
// the full mesh would have submitted, and the resampling's draws and reads.
struct EngineCounters {
  MCPOSE_ENGINE_COUNTERS(MCPOSE_COUNTER_FIELD)

  EngineCounters& operator+=(const EngineCounters& o) {
    MCPOSE_ENGINE_COUNTERS(MCPOSE_COUNTER_ADD)
    return *this;
  }
  EngineCounters& operator+=(const RasterCounters& o) {
    MCPOSE_RASTER_COUNTERS(MCPOSE_COUNTER_ADD)
    return *this;
  }
  bool operator==(const EngineCounters&) const = default;
};

#undef MCPOSE_COUNTER_FIELD
#undef MCPOSE_COUNTER_ADD

}  // namespace mcpose
