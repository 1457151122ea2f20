#include "io/options_json.h"

namespace mcpose::io {

nlohmann::json OptionsToJson(const EstimatorOptions& o) {
  const auto& w = o.weight;
  const auto& d = o.diffusion;
  const auto& e = o.engine;
  return {
      {"samples", o.samples},
      {"max_iterations", o.max_iterations},
      {"tau", o.tau},
      {"seed", o.seed},
      {"max_instances", o.max_instances},
      {"init",
       {{"front_share", o.init.front_share},
        {"front_quantile", o.init.front_quantile},
        {"depth_quantile", o.init.depth_quantile},
        {"rest_share", o.init.rest_share},
        {"sigma_t_m", o.init.sigma_t_m}}},
      {"weight",
       {{"inlier", w.inlier == InlierMode::k1D ? "1d" : "3d"},
        {"eps_m", w.eps_m},
        {"a", w.a},
        {"b", w.b},
        {"c", w.c},
        {"occlusion_aware", w.occlusion_aware},
        {"box_fit", w.box_fit}}},
      {"resample",
       {{"keep_top_fraction", o.resample.keep_top_fraction}, {"cdf_table_size", o.resample.cdf_table_size}}},
      {"diffusion",
       {{"sigma_t_m", d.sigma_t_m},
        {"sigma_r_rad", d.sigma_r_rad},
        {"sigma_t_min_m", d.sigma_t_min_m},
        {"sigma_r_min_rad", d.sigma_r_min_rad},
        {"anneal", d.anneal},
        {"flip_rate", d.flip_rate}}},
      {"appearance",
       {{"enabled", o.appearance.enabled}, {"weight", o.appearance.weight}, {"min_pixels", o.appearance.min_pixels},
        {"pixel_step", o.appearance.pixel_step},
        {"smooth_radius", o.appearance.smooth_radius},
        {"drop_clipped", o.appearance.drop_clipped},
        {"trust_pixels", o.appearance.trust_pixels},
        {"ramp_iterations", o.appearance.ramp_iterations},
        {"space", AppearanceOptions::SpaceName(o.appearance.space)},
        {"resolve_twins", o.appearance.resolve_twins},
        {"twin_step_deg", o.appearance.twin_step_deg},
        {"twin_refine_iterations", o.appearance.twin_refine_iterations},
        {"twin_depth_margin", o.appearance.twin_depth_margin}}},
      {"refine",
       {{"enabled", o.refine.enabled},
        {"max_iterations", o.refine.max_iterations},
        {"twin_iterations", o.refine.twin_iterations},
        {"tukey_m", o.refine.tukey_m},
        {"max_distance_m", o.refine.max_distance_m},
        {"accept_eps_m", o.refine.accept_eps_m}}},
      {"engine",
       {{"backend", RasterBackendName(e.backend)},
        {"backface_culling", e.backface_culling},
        {"pixel_stride", e.pixel_stride},
        {"max_grid_pixels", e.max_grid_pixels},
        {"lod_error_px", e.lod_error_px},
        {"lod_unbiased", e.lod_unbiased},
        {"cluster_culling", e.cluster_culling},
        {"batched_setup", e.batched_setup},
        {"threads", e.threads}}},
  };
}

nlohmann::json CountersToJson(const EngineCounters& c) {
  return {{"triangles_full", c.triangles_full},
          {"triangles_in", c.triangles_in},
          {"culled_backface", c.culled_backface},
          {"culled_degenerate", c.culled_degenerate},
          {"culled_outside_box", c.culled_outside_box},
          {"culled_near", c.culled_near},
          {"culled_between_pixels", c.culled_between_pixels},
          {"triangles_rasterized", c.triangles_rasterized},
          {"fragments", c.fragments},
          {"clusters", c.clusters},
          {"clusters_culled_backface", c.clusters_culled_backface},
          {"clusters_culled_outside_box", c.clusters_culled_outside_box},
          {"cdf_draws", c.cdf_draws},
          {"cdf_reads", c.cdf_reads}};
}

nlohmann::json TrackerOptionsToJson(const TrackerOptions& t) {
  return {{"samples", t.samples},
          {"iterations", t.iterations},
          {"stop_weight", t.stop_weight},
          {"motion_sigma_t_m", t.motion_sigma_t_m},
          {"motion_sigma_r_rad", t.motion_sigma_r_rad},
          {"box_margin", t.box_margin},
          {"refine_iterations", t.refine_iterations},
          {"lost_fit", t.lost_fit},
          {"lost_visible", t.lost_visible},
          {"estimator", OptionsToJson(t.estimator)}};
}

}  // namespace mcpose::io
