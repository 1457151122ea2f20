// Every field of the estimator's options, as the run fingerprint sees it (its JSON), can be set
// from the command line (and so from Python, which passes its keyword options as these flags),
// and setting it changes the fingerprint that guards `--resume`.
#include <cmath>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/common.h"
#include "mcpose/options_json.h"
#include "mcpose/results_journal.h"
#include "mcpose/option_table.h"
#include "mcpose/simd.h"

namespace mcpose {
namespace {

// The JSON pointers of every leaf of `j`.
void Leaves(const nlohmann::json& j, const std::string& at, std::set<std::string>* out) {
  if (!j.is_object()) {
    out->insert(at);
    return;
  }
  for (const auto& [key, value] : j.items()) Leaves(value, at + "/" + key, out);
}

// The last SIMD target this CPU offers (EMU128 where it is compiled): a --simd-target that is
// not the default.
std::string LeastSimdTarget() {
  const std::string all = render::SimdTargetsAvailable();
  return all.substr(all.rfind(' ') + 1);
}

struct FlagCase {
  std::vector<std::string> args;     // flags that move fields off their defaults
  std::set<std::string> changed;     // the JSON pointers of exactly those fields
};

const std::vector<FlagCase>& Cases() {
  static const std::vector<FlagCase> cases = {
      {{"--samples", "300"}, {"/samples"}},
      {{"--iterations", "20"}, {"/max_iterations"}},
      {{"--tau", "0.9"}, {"/tau"}},
      {{"--seed", "7"}, {"/seed"}},
      {{"--max-instances", "2"}, {"/max_instances"}},
      {{"--init-front-share", "0.25"}, {"/init/front_share"}},
      {{"--init-front-quantile", "0.2"}, {"/init/front_quantile"}},
      {{"--init-depth-quantile", "0.4"}, {"/init/depth_quantile"}},
      {{"--init-rest-share", "0.25"}, {"/init/rest_share"}},
      {{"--init-sigma-t", "0.02"}, {"/init/sigma_t_m"}},
      {{"--inlier", "3d"}, {"/weight/inlier"}},
      {{"--eps", "0.02"}, {"/weight/eps_m"}},
      {{"--weights", "0.5", "0.2", "0.3"}, {"/weight/a", "/weight/b"}},
      {{"--weights", "0.5", "0.15", "0.35"}, {"/weight/a", "/weight/c"}},
      {{"--no-occlusion-aware"}, {"/weight/occlusion_aware"}},
      {{"--box-fit", "0.5"}, {"/weight/box_fit"}},
      {{"--keep-top", "0.5"}, {"/resample/keep_top_fraction"}},
      {{"--elite", "0.1"}, {"/resample/elite_share"}},
      {{"--init-rest-spread", "0.25"}, {"/init/rest_spread"}},
      {{"--init-wide", "2"}, {"/init/wide"}},
      {{"--cdf-table", "32"}, {"/resample/cdf_table_size"}},
      {{"--sigma-t", "0.02"}, {"/diffusion/sigma_t_m"}},
      {{"--sigma-r", "0.3"}, {"/diffusion/sigma_r_rad"}},
      {{"--sigma-t-min", "0.003"}, {"/diffusion/sigma_t_min_m"}},
      {{"--sigma-r-min", "0.04"}, {"/diffusion/sigma_r_min_rad"}},
      {{"--anneal", "0.9"}, {"/diffusion/anneal"}},
      {{"--flip-rate", "0.1"}, {"/diffusion/flip_rate"}},
      {{"--appearance", "off"}, {"/appearance/enabled"}},
      {{"--colour-weight", "0.4"}, {"/appearance/weight"}},
      {{"--colour-min-pixels", "30"}, {"/appearance/min_pixels"}},
      {{"--colour-step", "2"}, {"/appearance/pixel_step"}},
      {{"--colour-smooth", "2"}, {"/appearance/smooth_radius"}},
      {{"--no-colour-drop-clipped"}, {"/appearance/drop_clipped"}},
      {{"--colour-trust-pixels", "30"}, {"/appearance/trust_pixels"}},
      {{"--colour-hue-first", "4"}, {"/appearance/hue_first_levels"}},
      {{"--colour-ramp", "5"}, {"/appearance/ramp_iterations"}},
      {{"--colour-space", "chroma"}, {"/appearance/space"}},
      {{"--no-resolve-twins"}, {"/appearance/resolve_twins"}},
      {{"--twin-step", "45"}, {"/appearance/twin_step_deg"}},
      {{"--twin-refine", "5"}, {"/appearance/twin_refine_iterations"}},
      {{"--twin-depth-margin", "0.05"}, {"/appearance/twin_depth_margin"}},
      {{"--refine", "off"}, {"/refine/enabled"}},
      {{"--refine-iterations", "10"}, {"/refine/max_iterations"}},
      {{"--refine-twin-iterations", "4"}, {"/refine/twin_iterations"}},
      {{"--refine-tukey", "0.008"}, {"/refine/tukey_m"}},
      {{"--refine-max-distance", "0.03"}, {"/refine/max_distance_m"}},
      {{"--refine-accept-eps", "0.005"}, {"/refine/accept_eps_m"}},
      {{"--engine", "fixed"}, {"/engine/backend"}},
      {{"--no-backface-culling"}, {"/engine/backface_culling"}},
      {{"--pixel-stride", "3"}, {"/engine/pixel_stride"}},
      {{"--max-grid-pixels", "4000"}, {"/engine/max_grid_pixels"}},
      {{"--lod-px", "1"}, {"/engine/lod_error_px"}},
      {{"--no-lod-unbiased"}, {"/engine/lod_unbiased"}},
      {{"--no-cluster-culling"}, {"/engine/cluster_culling"}},
      {{"--no-batched-setup"}, {"/engine/batched_setup"}},
      {{"--threads", "3"}, {"/engine/threads"}},
      {{"--simd-target", LeastSimdTarget()}, {"/engine/simd_target"}},
  };
  return cases;
}

TEST(OptionFlags, EveryFieldHasAFlagThatSetsItAloneAndChangesTheFingerprint) {
  const EstimatorOptions defaults;
  const nlohmann::json base = io::OptionsToJson(defaults);
  std::set<std::string> leaves;
  Leaves(base, "", &leaves);
  const std::vector<Detection> boxes = {Detection{49, 1, 6, 0.9, 10, 20, 30, 40}};
  const io::RunSource source{"/data/ycbv", "test", "/data/ycbv/models", ""};
  const std::string base_print = io::RunFingerprint(defaults, boxes, source);

  std::set<std::string> covered;
  for (const FlagCase& c : Cases()) {
    std::string joined;
    for (const std::string& a : c.args) joined += a + " ";
    StatusOr<EstimatorOptions> o = ParseEstimatorOptions(c.args);
    ASSERT_TRUE(o.ok()) << joined << ": " << o.status().ToString();
    const nlohmann::json j = io::OptionsToJson(*o);
    std::set<std::string> changed;
    for (const std::string& leaf : leaves) {
      const nlohmann::json::json_pointer p(leaf);
      ASSERT_TRUE(j.contains(p)) << leaf;
      if (j.at(p) != base.at(p)) changed.insert(leaf);
    }
    EXPECT_EQ(changed, c.changed) << joined;
    // JSON -> options gives the same options again.
    StatusOr<EstimatorOptions> back = io::OptionsFromJson(j);
    ASSERT_TRUE(back.ok()) << joined << ": " << back.status().ToString();
    EXPECT_EQ(io::OptionsToJson(*back), j) << joined;
    covered.insert(changed.begin(), changed.end());
    // The thread count and the SIMD target change no result: they are left out of the fingerprint.
    const bool result_field = c.changed != std::set<std::string>{"/engine/threads"} &&
                              c.changed != std::set<std::string>{"/engine/simd_target"};
    EXPECT_EQ(io::RunFingerprint(*o, boxes, source) != base_print, result_field) << joined;
  }
  // No field without a flag: one added to the options' JSON needs a case here, and a flag.
  EXPECT_EQ(covered, leaves);
}

TEST(OptionFlags, JsonOptionsAreCheckedAsTheCommandLineChecksThem) {
  const auto message = [](const char* text) {
    StatusOr<EstimatorOptions> o = io::OptionsFromJson(nlohmann::json::parse(text));
    return o.ok() ? std::string("ok") : o.status().message();
  };
  EXPECT_EQ(message(R"({"samples": 300, "refine": {"tukey_m": 0.008}})"), "ok");
  EXPECT_NE(message(R"({"samples": 0})").find("samples must lie in [1, 1000000], got 0"), std::string::npos);
  EXPECT_NE(message(R"({"samples": 1.5})").find("samples must be a whole number"), std::string::npos);
  EXPECT_NE(message(R"({"refine": {"tukey": 0.008}})").find("unknown key 'refine.tukey'"), std::string::npos);
  EXPECT_NE(message(R"({"engine": {"backend": "gpu"}})").find("scalar, fixed, simd, float-simd, hw or rtl"), std::string::npos);
  EXPECT_NE(message(R"({"weight": {"eps_m": -1}})").find("weight.eps_m must be finite and > 0 m"), std::string::npos);
  EXPECT_NE(message(R"({"appearance": {"enabled": "yes"}})").find("true or false"), std::string::npos);
  EXPECT_NE(message(R"({"seed": -1})").find("seed must be a whole number >= 0"), std::string::npos);
  EXPECT_NE(message("[1]").find("expected a JSON object"), std::string::npos);
}

// docs/options.md holds the table as OptionTableMarkdown() prints it.
TEST(OptionFlags, EveryTrackerFieldHasAFlagThatSetsItAloneAndItsJsonKey) {
  const TrackerOptions defaults;
  const nlohmann::json base = io::TrackerOptionsToJson(defaults);
  for (const TrackerOptionField& f : TrackerOptionFields()) {
    SCOPED_TRACE(f.key);
    ASSERT_NE(f.flag, nullptr);
    EXPECT_TRUE(f.CheckBounds(defaults).empty());
    nlohmann::json want = base;
    std::string text;
    if (f.type == OptionType::kInt) {
      const int v = f.Get<int>(defaults) + 1 <= f.max ? f.Get<int>(defaults) + 1 : f.Get<int>(defaults) - 1;
      text = std::to_string(v), want[f.key] = v;
    } else {
      ASSERT_EQ(f.type, OptionType::kDouble);
      const double d = f.Get<double>(defaults);
      const double v = d + 0.01 <= f.max ? d + 0.01 : d - 0.01;
      text = nlohmann::json(v).dump(), want[f.key] = v;
    }
    StatusOr<TrackerOptions> got = ParseTrackerOptions({f.flag, text});
    ASSERT_TRUE(got.ok()) << got.status().ToString();
    EXPECT_EQ(io::TrackerOptionsToJson(*got), want);
    // Out of bounds: refused, naming the field.
    if (std::isfinite(f.min)) {
      const std::string below = f.type == OptionType::kInt ? std::to_string(static_cast<long long>(f.min) - 1)
                                                           : nlohmann::json(f.min - 1).dump();
      StatusOr<TrackerOptions> bad = ParseTrackerOptions({f.flag, below});
      ASSERT_FALSE(bad.ok());
      EXPECT_NE(bad.status().message().find(f.key), std::string::npos) << bad.status().message();
    }
  }
}

TEST(OptionFlags, TheDocsTableIsTheTable) {
  const std::string path = std::string(MCPOSE_SOURCE_DIR) + "/docs/options.md";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string table = OptionTableMarkdown();
  EXPECT_NE(doc.find(table), std::string::npos) << path << " must hold the options table as it is now:\n" << table;
  const std::string tracker = TrackerOptionTableMarkdown();
  EXPECT_NE(doc.find(tracker), std::string::npos) << path << " must hold the tracker's table as it is now:\n"
                                                  << tracker;
}

}  // namespace
}  // namespace mcpose
