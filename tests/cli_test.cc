// The mcpose command line on real data: bad input gets one clear error and no output file;
// the same seed gives the same CSV at any thread count; BOP and native layouts agree.

#include <algorithm>
#include <cmath>
#include <functional>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/ply_io.h"
#include "mcpose/png_io.h"
#include "mcpose/dataset.h"
#include "mcpose/results.h"
#include "mcpose/options.h"
#include "mcpose/simd.h"
#include "cli_run.h"
#include "dataset_copy.h"
#include "test_data.h"

namespace mcpose {
namespace {

namespace fs = std::filesystem;

using testing::CliResult;
using testing::MakeBopCopy;
using testing::Replace;
using testing::WriteText;
using testing::ReadText;
using testing::RunCli;
using testing::RunTools;

// Detections of scene 49 image 1 (both layouts hold it) with tight boxes from box.txt-like
// values; enough to run the estimator.
nlohmann::json Scene49Detections() {
  return nlohmann::json::parse(R"([
    {"scene_id": 49, "image_id": 1, "category_id": 3, "score": 0.9, "bbox": [233, 132, 197, 208]},
    {"scene_id": 49, "image_id": 1, "category_id": 6, "score": 0.8, "bbox": [434, 89, 97, 84]},
    {"scene_id": 49, "image_id": 1, "category_id": 9, "score": 0.7, "bbox": [170, 98, 129, 131]},
    {"scene_id": 49, "image_id": 1, "category_id": 9, "score": 0.3, "bbox": [400, 300, 129, 131]}
  ])");
}

struct BadCase {
  std::string name;
  // Breaks something in the dataset copy or the detections; returns the text the error must
  // contain (a file name or a phrase).
  std::function<std::string(const fs::path& bop, nlohmann::json& dets)> breaker;
  std::string extra_args;
};

class CliBadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(CliBadInput, OneClearErrorNonZeroExitNoResultsFile) {
  const BadCase& c = GetParam();
  const fs::path bop = MakeBopCopy("bad_" + c.name);
  const fs::path dir = bop.parent_path();
  nlohmann::json dets = Scene49Detections();
  const std::string must_contain = c.breaker(bop, dets);
  const fs::path dets_path = dir / "dets.json";
  if (!fs::exists(dets_path)) WriteText(dets_path, dets.dump());
  const fs::path results = dir / "results.csv";
  const CliResult r = RunCli("estimate --dataset " + bop.string() + " --detections " + dets_path.string() +
                                 " --out " + results.string() + " --iterations 2 " +
                                 (c.extra_args.empty() ? "--samples 16" : c.extra_args),
                             dir);
  EXPECT_NE(r.exit_code, 0) << c.name;
  EXPECT_NE(r.err.find("mcpose: error:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(must_contain), std::string::npos) << "expected '" << must_contain << "' in: " << r.err;
  // One message: a single line on stderr.
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(results)) << c.name;
  EXPECT_TRUE(testing::LeftBeside(results).empty()) << c.name;
}

// Outputs never overwrite an input, never each other, and never write through a link planted at
// their name or beside it.
TEST(Cli, OutputsNeitherOverwriteInputsNorFollowLinks) {
  const fs::path bop = MakeBopCopy("outputs_links");
  const fs::path dir = bop.parent_path();
  const fs::path dets = dir / "dets.json";
  WriteText(dets, Scene49Detections().dump());
  const std::string dets_text = ReadText(dets);
  WriteText(dir / "victim.txt", "keep");
  fs::create_symlink(dets, dir / "alias.json");
  const std::string run = "estimate --dataset " + bop.string() + " --detections " + dets.string() +
                          " --iterations 2 --samples 16 --quiet --out ";
  const std::pair<std::string, std::string> refused[] = {
      {dets.string(), "--out names the same file as --detections"},
      {(dir / "alias.json").string(), "--out names the same file as --detections"},
      {(dir / "r.csv").string() + " --out-json " + (dir / "r.csv").string(), "--out-json and --out name the same file"},
  };
  for (const auto& [args, message] : refused) {
    const CliResult r = RunCli(run + args, dir);
    EXPECT_EQ(r.exit_code, 1) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(ReadText(dets), dets_text);
  }
  CliResult r = RunCli("eval --dataset " + bop.string() + " --results " + (dir / "victim.txt").string() + " --json " +
                           (dir / "victim.txt").string(),
                       dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--json names the same file as --results"), std::string::npos) << r.err;

  // A link planted at the journal's name is refused; one at the output's name is replaced.
  fs::create_symlink(dir / "victim.txt", dir / "r.csv.partial");
  r = RunCli(run + (dir / "r.csv").string(), dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("r.csv.partial: is a link"), std::string::npos) << r.err;
  fs::remove(dir / "r.csv.partial");
  fs::create_symlink(dir / "victim.txt", dir / "r.csv");
  r = RunCli(run + (dir / "r.csv").string(), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::is_symlink(dir / "r.csv"));
  EXPECT_NE(ReadText(dir / "r.csv").find("scene_id,im_id,obj_id"), std::string::npos);
  EXPECT_EQ(ReadText(dir / "victim.txt"), "keep");
  EXPECT_TRUE(testing::LeftBeside(dir / "r.csv").empty());
}

// No command writes over what the dataset holds (any of it may be an input), nor into a folder
// that holds the dataset; the file is unchanged. A new file inside the dataset folder is fine.
TEST(Cli, OutputsNeverOverwriteTheDataset) {
  const fs::path ycbv = testing::MakeYcbvCopy("outputs_dataset");
  const fs::path dir = ycbv.parent_path();
  const fs::path dets = dir / "dets.json", results = dir / "r.csv";
  WriteText(dets, Scene49Detections().dump());
  WriteText(results, "scene_id,im_id,obj_id,score,R,t,time\n");
  const fs::path meta = ycbv / "data/0049/000001-meta.mat", classes = ycbv / "classes.txt";
  const fs::path points = testing::OwnModel(ycbv, "004_sugar_box") / "points.xyz";
  const std::string meta_bytes = ReadText(meta), classes_text = ReadText(classes), points_text = ReadText(points);
  const std::string ds = " --dataset " + ycbv.string();
  const std::string cases[] = {
      "estimate" + ds + " --detections " + dets.string() + " --samples 16 --iterations 2 --out " + meta.string(),
      "estimate" + ds + " --detections " + dets.string() + " --samples 16 --iterations 2 --out " + results.string() +
          " --out-json " + points.string(),
      "track" + ds + " --video 49 --frames 1 --out " + classes.string(),
      "eval" + ds + " --results " + results.string() + " --json " + points.string(),
      "detections-from-gt" + ds + " --out " + meta.string(),
      "report" + ds + " --results " + results.string() + " --out " + (ycbv / "data").string(),
      "report" + ds + " --results " + results.string() + " --out " + dir.string(),
      "bench" + ds + " --iterations 1 --json " + classes.string(),
      "capture-appearance" + ds + " --frames " + dets.string() + " --out " + ycbv.string(),
  };
  for (const std::string& args : cases) {
    const CliResult r = RunCli(args, dir);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.err;
    EXPECT_TRUE(r.err.find("which this run may read; it would be overwritten") != std::string::npos ||
                r.err.find("names a folder holding the dataset") != std::string::npos)
        << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_EQ(ReadText(meta), meta_bytes);
  EXPECT_EQ(ReadText(classes), classes_text);
  EXPECT_EQ(ReadText(points), points_text);
  const CliResult fresh = RunCli("detections-from-gt" + ds + " --out " + (ycbv / "new_dets.json").string(), dir);
  EXPECT_EQ(fresh.exit_code, 0) << fresh.err;
}

// An allocation that fails ends as one line and exit status 1, not std::terminate: a million
// samples (about 425 MB) under a 350 MB address-space limit, under which 100 samples run.
TEST(Cli, OutOfMemoryIsOneClearError) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "the sanitizers reserve more address space than the limit";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
  GTEST_SKIP() << "the sanitizers reserve more address space than the limit";
#endif
#endif
  const fs::path bop = MakeBopCopy("out_of_memory");
  const fs::path dir = bop.parent_path();
  WriteText(dir / "dets.json", Scene49Detections().dump());
  const auto run = [&](const std::string& out, int samples) {
    return testing::RunProgram(std::string("ulimit -v 350000; ") + MCPOSE_CLI_PATH,
                               "estimate --dataset " + bop.string() + " --detections " + (dir / "dets.json").string() +
                                   " --out " + (dir / out).string() + " --samples " + std::to_string(samples) +
                                   " --iterations 2 --threads 1 --quiet",
                               dir);
  };
  const CliResult small = run("small.csv", 100);
  ASSERT_EQ(small.exit_code, 0) << small.err;
  const CliResult r = run("r.csv", 1000000);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("mcpose: error:", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "r.csv"));
  EXPECT_TRUE(testing::LeftBeside(dir / "r.csv").empty());
}

// A real detector's raw boxes (FCOS, key frame 0049/000001): the four objects of the frame
// within 2 cm ADD-S, one row each; each of the three classes not in the frame (boxes of detector
// score 0.18-0.26) gets a pose too, one per cluster of its boxes whose pose explains pixels no
// other of its poses explains, each scored below every true object's. --min-score 0.3 leaves
// their boxes out, and only the four true objects get a row.
TEST(Cli, RealDetectorBoxesWithoutAThreshold) {
  const fs::path dir = testing::TempDir("fcos");
  const std::string fcos = testing::DataDir() + "/real_detections/fcos_ycbv_0049_000001.json";
  const std::set<int> in_frame = {3, 6, 9, 13}, not_in_frame = {2, 10, 15};
  const auto run = [&](const std::string& extra, const std::string& out) {
    const CliResult r = RunCli("estimate -q --seed 0 --dataset " + testing::YcbvDir() + " --detections " + fcos +
                                   " --out " + (dir / out).string() + extra,
                               dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    auto rows = ReadResultsCsv((dir / out).string());
    EXPECT_TRUE(rows.ok()) << rows.status().ToString();
    return rows.ok() ? *rows : std::vector<PoseResult>{};
  };
  const std::vector<PoseResult> all = run("", "all.csv");
  std::set<int> classes;
  std::map<int, int> rows_of_class;
  double lowest_true = 1, highest_false = 0;
  for (const PoseResult& row : all) {
    classes.insert(row.obj_id);
    ++rows_of_class[row.obj_id];
    if (in_frame.contains(row.obj_id))
      lowest_true = std::min(lowest_true, row.score);
    else
      highest_false = std::max(highest_false, row.score);
  }
  std::set<int> expected = in_frame;
  expected.insert(not_in_frame.begin(), not_in_frame.end());
  EXPECT_EQ(classes, expected);
  EXPECT_LT(highest_false, lowest_true);
  const fs::path ej = dir / "eval.json";
  const CliResult e = RunCli("eval --dataset " + testing::YcbvDir() + " --results " + (dir / "all.csv").string() +
                                 " --detections " + fcos + " --json " + ej.string(),
                             dir);
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const nlohmann::json ev = nlohmann::json::parse(ReadText(ej));
  ASSERT_EQ(ev["instances"].size(), 4u);
  for (const nlohmann::json& i : ev["instances"]) EXPECT_LT(i["adds_m"].get<double>(), 0.02) << i.dump();
  int false_rows = 0;
  for (const auto& [obj_id, n] : rows_of_class) {
    if (in_frame.contains(obj_id)) {
      EXPECT_EQ(n, 1) << "class " << obj_id;
    }
    if (not_in_frame.contains(obj_id)) false_rows += n;
  }
  EXPECT_EQ(ev["unmatched_rows"].get<int>(), false_rows);

  std::set<int> kept;
  for (const PoseResult& row : run(" --min-score 0.3", "kept.csv")) kept.insert(row.obj_id);
  EXPECT_EQ(kept, in_frame);
  const CliResult none = RunCli("estimate -q --dataset " + testing::YcbvDir() + " --detections " + fcos +
                                    " --min-score 0.99 --out " + (dir / "none.csv").string(),
                                dir);
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_NE(none.err.find(fcos + ": no detection scores at least --min-score 0.99"), std::string::npos) << none.err;
}

// The ground truth as results scores 100 % on every BOP19 metric: on the BOP copy with its own
// models_info.json and targets, and on the YCB-Video layout with the BOP file given.
TEST(Cli, Bop19MetricsOfTheTruthAreAHundredPercent) {
  const fs::path dir = testing::TempDir("bop19");
  for (const std::string& root : {testing::BopDir(), testing::YcbvDir()}) {
    auto dataset = Dataset::Open(root, "test", "");
    ASSERT_TRUE(dataset.ok()) << dataset.status().ToString();
    std::vector<PoseResult> rows;
    for (const FrameKey& key : (*dataset)->Frames()) {
      auto frame = (*dataset)->LoadFrame(key);
      ASSERT_TRUE(frame.ok()) << frame.status().ToString();
      for (const GtInstance& gt : frame->gt) rows.push_back({key.scene_id, key.image_id, gt.obj_id, 1.0, gt.T_cam_obj, 1});
    }
    ASSERT_TRUE(WriteResultsCsv((dir / "gt.csv").string(), rows).ok());
    const std::string info = root == testing::YcbvDir() ? " --models-info " + testing::BopDir() + "/models/models_info.json" : "";
    const CliResult r = RunCli("eval --metrics bop19 --dataset " + root + " --results " + (dir / "gt.csv").string() +
                                   info + " --json " + (dir / "e.json").string(),
                               dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json doc = nlohmann::json::parse(ReadText(dir / "e.json"));
    EXPECT_FALSE(doc.contains("overall")) << "ycbv metrics were not asked for";
    const nlohmann::json& all = doc["bop19"]["overall"];
    EXPECT_GT(all["targets"].get<int>(), 0);
    for (const char* ar : {"ar_vsd", "ar_mssd", "ar_mspd", "ar"}) EXPECT_NEAR(all[ar].get<double>(), 1.0, 1e-12) << root << " " << ar;
    EXPECT_NE(r.out.find("BOP19 average recall"), std::string::npos) << r.out;
  }
  // The YCB-Video layout has no models_info.json of its own.
  const CliResult r = RunCli("eval --metrics ycbv,bop19 --dataset " + testing::YcbvDir() + " --results " +
                                 (dir / "gt.csv").string(),
                             dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--metrics bop19 needs the objects' diameters and symmetries: --models-info FILE"),
            std::string::npos) << r.err;
}

// A seed outside 0..2^64-1 is refused, not wrapped around to another seed.
TEST(Cli, SeedsOutsideTheirRangeAreRefused) {
  const fs::path dir = testing::TempDir("seed_range");
  for (const char* seed : {"-1", "18446744073709551616", "1e3", "seven"}) {
    const CliResult r = RunCli("detections-from-gt --dataset " + testing::YcbvDir() + " --out " +
                                   (dir / "d.json").string() + " --seed " + seed,
                               dir);
    EXPECT_NE(r.exit_code, 0) << seed;
    EXPECT_NE(r.err.find("a seed is a whole number from 0 to 18446744073709551615"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "d.json")) << seed;
  }
  const CliResult ok = RunCli("detections-from-gt --dataset " + testing::YcbvDir() + " --out " +
                                  (dir / "d.json").string() + " --seed 18446744073709551615",
                              dir);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

std::string PatchSceneCamera(const fs::path& bop, double fx) {
  const fs::path p = bop / "test/000049/scene_camera.json";
  std::string text = ReadText(p);
  const std::string key = "\"cam_K\": [1066.778";
  const size_t at = text.find(key);
  std::ostringstream v;
  if (std::isnan(fx)) v << "NaN"; else v << fx;
  text.replace(at, key.size(), "\"cam_K\": [" + v.str());
  Replace(p, text);
  return p.string();
}

// Colour for the sugar box (obj 3) of the BOP copy, so that its colour frames are read: a
// vertex-coloured model and the frames' rgb/ folder (linked).
void AddColour(const fs::path& bop) {
  const fs::path model = bop / "models/obj_000003.ply";
  auto mesh = io::ReadPlyMesh(model.string(), 1000.0);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  for (size_t i = 0; i < mesh->vertices_m.size(); ++i) mesh->appearance.vertex_colours.push_back({200, 180, 40, 255});
  fs::remove(model);
  ASSERT_TRUE(io::WritePlyMesh(model.string(), *mesh, 1000.0).ok());
  fs::create_directories(bop / "test/000049/rgb");
  for (const auto& e : fs::directory_iterator(fs::path(testing::BopDir()) / "test/000049/rgb"))
    fs::create_symlink(e.path(), bop / "test/000049/rgb" / e.path().filename());
}

const BadCase kBadCases[] = {
    {"missing_dataset", [](const fs::path& bop, nlohmann::json&) { fs::remove_all(bop); return bop.string(); }, ""},
    {"missing_detections", [](const fs::path& bop, nlohmann::json&) {
       fs::create_directory(bop.parent_path() / "dets.json");  // a folder, not a file
       return (bop.parent_path() / "dets.json").string(); }, ""},
    {"malformed_json", [](const fs::path& bop, nlohmann::json&) {
       WriteText(bop.parent_path() / "dets.json", "[{\"scene_id\": 49, \"image_id\": ");
       return (bop.parent_path() / "dets.json").string(); }, ""},
    {"unknown_class", [](const fs::path&, nlohmann::json& d) { d[0]["category_id"] = 99; return std::string("unknown class"); }, ""},
    {"box_outside_image", [](const fs::path&, nlohmann::json& d) {
       d[1]["bbox"] = {900, 100, 50, 50}; return std::string("outside"); }, ""},
    {"box_far_outside_image", [](const fs::path&, nlohmann::json& d) {  // past the range of int
       d[1]["bbox"] = {1e300, 100, 50, 50}; return std::string("outside"); }, ""},
    {"box_far_left_of_image", [](const fs::path&, nlohmann::json& d) {
       d[1]["bbox"] = {-1e300, 100, 50, 50}; return std::string("outside"); }, ""},
    {"zero_size_box", [](const fs::path& bop, nlohmann::json& d) {
       d[1]["bbox"] = {100, 100, 0, 50}; return (bop.parent_path() / "dets.json").string(); }, ""},
    {"no_such_image", [](const fs::path&, nlohmann::json& d) { d[0]["scene_id"] = 77; return std::string("no such image"); }, ""},
    {"truncated_depth_png", [](const fs::path& bop, nlohmann::json&) {
       const fs::path p = bop / "test/000049/depth/000001.png";
       const std::string bytes = ReadText(fs::read_symlink(p));
       Replace(p, bytes.substr(0, bytes.size() / 3));
       return p.string(); }, ""},
    {"eight_bit_depth_png", [](const fs::path& bop, nlohmann::json&) {
       const fs::path p = bop / "test/000049/depth/000001.png";
       fs::remove(p);
       MaskImage m;
       m.width = 640, m.height = 480;
       m.values.assign(640 * 480, 7);
       EXPECT_TRUE(io::WriteMaskPng(p.string(), m).ok());
       return p.string(); }, ""},
    {"nan_intrinsics", [](const fs::path& bop, nlohmann::json&) { return PatchSceneCamera(bop, NAN); }, ""},
    {"zero_intrinsics", [](const fs::path& bop, nlohmann::json&) { return PatchSceneCamera(bop, 0.0); }, ""},
    {"empty_mesh", [](const fs::path& bop, nlohmann::json&) {
       const fs::path p = bop / "models/obj_000003.ply";
       Replace(p, "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 0\nproperty list uchar int vertex_indices\nend_header\n");
       return p.string(); }, ""},
    {"degenerate_mesh", [](const fs::path& bop, nlohmann::json&) {
       const fs::path p = bop / "models/obj_000003.ply";
       Replace(p, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 1 1\n2 2 2\n3 0 1 2\n");
       return p.string(); }, ""},
    {"invalid_option", [](const fs::path&, nlohmann::json&) { return std::string("samples"); }, "--samples 0"},
    {"invalid_flip_rate", [](const fs::path&, nlohmann::json&) { return std::string("flip_rate"); }, "--flip-rate 1.5"},
    {"threads_past_the_limit", [](const fs::path&, nlohmann::json&) { return std::string("engine.threads must lie in"); },
     "--threads 10000"},
    {"samples_past_the_limit", [](const fs::path&, nlohmann::json&) { return std::string("samples must lie in"); },
     "--samples 1000000000"},
    {"colour_frame_of_another_size", [](const fs::path& bop, nlohmann::json&) {
       AddColour(bop);
       const fs::path p = bop / "test/000049/rgb/000001.png";
       fs::remove(p);
       ColourImage small;
       small.width = 320, small.height = 240;
       small.rgba.assign(4 * 320 * 240, 90);
       EXPECT_TRUE(io::WriteColourPng(p.string(), small).ok());
       return p.string(); }, ""},
    {"truncated_colour_frame", [](const fs::path& bop, nlohmann::json&) {
       AddColour(bop);
       const fs::path p = bop / "test/000049/rgb/000001.png";
       const std::string bytes = ReadText(fs::read_symlink(p));
       Replace(p, bytes.substr(0, bytes.size() / 2));
       return p.string(); }, ""},
    {"missing_colour_frame", [](const fs::path& bop, nlohmann::json&) {
       AddColour(bop);
       const fs::path p = bop / "test/000049/rgb/000001.png";
       fs::remove(p);
       return p.string(); }, ""},
    {"invalid_appearance", [](const fs::path&, nlohmann::json&) { return std::string("--appearance"); }, "--appearance maybe"},
};

INSTANTIATE_TEST_SUITE_P(Cases, CliBadInput, ::testing::ValuesIn(kBadCases),
                         [](const auto& info) { return info.param.name; });

// Rows without the time column.
std::vector<std::string> RowsWithoutTime(const fs::path& csv) {
  std::vector<std::string> rows;
  std::istringstream in(ReadText(csv));
  for (std::string line; std::getline(in, line);) rows.push_back(line.substr(0, line.rfind(',')));
  return rows;
}

class CliThreads : public ::testing::TestWithParam<std::string> {};

TEST_P(CliThreads, SameSeedSameCsvAtAnyThreadCount) {
  const fs::path dir = testing::TempDir("threads");
  WriteText(dir / "dets.json", Scene49Detections().dump());
  std::vector<std::vector<std::string>> runs;
  for (int threads : {1, 2, 3}) {
    const fs::path out = dir / ("r" + std::to_string(threads) + ".csv");
    const CliResult r = RunCli("estimate --dataset " + testing::YcbvDir() + " --detections " + (dir / "dets.json").string() +
                                   " --out " + out.string() + " --iterations 6 --init-wide 2 --seed 5 -q " +
                                   GetParam() + " --threads " + std::to_string(threads),
                               dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    runs.push_back(RowsWithoutTime(out));
  }
  ASSERT_EQ(runs[0].size(), 5u);  // header + a row per instance: classes 3, 6 and two of 9
  EXPECT_EQ(runs[0], runs[1]);
  EXPECT_EQ(runs[0], runs[2]);
}

// --engine rtl scores every sample through the Verilated RTL of the raster core: on a real frame
// its rows equal --engine hw's, byte for byte but for the time column (a small budget: the
// simulation takes milliseconds a sample).
TEST(Cli, RtlEngineGivesTheHwEnginesCsv) {
  if (!RtlBackendAvailable()) GTEST_SKIP() << "built without Verilator: no --engine rtl";
  const fs::path dir = testing::TempDir("rtl");
  WriteText(dir / "dets.json", Scene49Detections().dump());
  std::vector<std::vector<std::string>> runs;
  for (const std::string engine : {"hw", "rtl"}) {
    const fs::path out = dir / (engine + ".csv");
    const CliResult r = RunCli("estimate --dataset " + testing::YcbvDir() + " --detections " + (dir / "dets.json").string() +
                                   " --out " + out.string() + " --samples 24 --iterations 2 --no-resolve-twins" +
                                   " --refine-iterations 2 --seed 3 -q --threads 2 --engine " + engine,
                               dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    runs.push_back(RowsWithoutTime(out));
  }
  ASSERT_EQ(runs[0].size(), 5u);  // header + a row per instance: classes 3, 6 and two of 9
  EXPECT_EQ(runs[1], runs[0]);
}

// Each (image, class) draws from random streams of its own, so a subset of the boxes gives the
// whole run's rows for its classes (scripts/accuracy_seeds.sh DETECTIONS= relies on this).
TEST(Cli, EachClassAloneGivesTheWholeRunsRow) {
  const fs::path dir = testing::TempDir("subsets");
  const nlohmann::json all = Scene49Detections();
  auto run = [&](const nlohmann::json& dets, const std::string& name) {
    WriteText(dir / (name + ".json"), dets.dump());
    const fs::path out = dir / (name + ".csv");
    const CliResult r = RunCli("estimate --dataset " + testing::YcbvDir() + " --detections " +
                                   (dir / (name + ".json")).string() + " --out " + out.string() +
                                   " --iterations 6 --seed 7 -q",
                               dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return RowsWithoutTime(out);
  };
  const std::vector<std::string> whole = run(all, "all");
  ASSERT_EQ(whole.size(), 5u);  // header + classes 3, 6 and two instances of 9 (a box apart)
  std::vector<std::string> pieced = {whole[0]};
  for (int category : {3, 6, 9}) {
    nlohmann::json one = nlohmann::json::array();
    for (const auto& d : all)
      if (d["category_id"] == category) one.push_back(d);
    const std::vector<std::string> rows = run(one, "class" + std::to_string(category));
    ASSERT_EQ(rows.size(), category == 9 ? 3u : 2u) << "class " << category;
    pieced.insert(pieced.end(), rows.begin() + 1, rows.end());
  }
  std::vector<std::string> sorted_whole = whole;
  std::sort(sorted_whole.begin() + 1, sorted_whole.end());
  std::sort(pieced.begin() + 1, pieced.end());
  EXPECT_EQ(pieced, sorted_whole);
}

std::string EngineTestName(const ::testing::TestParamInfo<std::string>& info) {
  static const char* const kNames[] = {"scalar", "fixed", "simd_lod", "float_simd", "simd_flips"};
  return kNames[info.index];
}

INSTANTIATE_TEST_SUITE_P(Engines, CliThreads,
                         ::testing::Values("--engine scalar", "--engine fixed", "--engine simd --lod-px 1",
                                           "--engine float-simd", "--engine simd --flip-rate 0.2"),
                         EngineTestName);

// Boxes a detector gives for far, thin or mostly hidden objects: strips 2 to 7 pixels wide,
// a 3-pixel-tall band, a 2 x 2 box and one half outside the image.
const char* const kThinBoxes = R"([
    {"scene_id": 49, "image_id": 1, "category_id": 3, "score": 0.9, "bbox": [330, 132, 5, 150]},
    {"scene_id": 49, "image_id": 1, "category_id": 3, "score": 0.5, "bbox": [300, 200, 2, 2]},
    {"scene_id": 49, "image_id": 1, "category_id": 6, "score": 0.8, "bbox": [434, 130, 97, 3]},
    {"scene_id": 49, "image_id": 1, "category_id": 9, "score": 0.7, "bbox": [230, 98, 7, 131]},
    {"scene_id": 49, "image_id": 1, "category_id": 9, "score": 0.6, "bbox": [-45, 300, 90, 131]},
    {"scene_id": 49, "image_id": 1, "category_id": 5, "score": 0.6, "bbox": [500, 20, 3, 90]}
  ])";

// The CSV rows of `mcpose estimate` on kThinBoxes with each of two engine settings, at pixel
// strides 2 and 1: each pair must be equal.
void ExpectThinBoxRowsEqual(const std::string& name, const std::string& engine_a, const std::string& engine_b,
                            const std::string& extra) {
  const fs::path dir = testing::TempDir(name);
  WriteText(dir / "dets.json", kThinBoxes);
  for (const std::string stride : {"2", "1"}) {
    std::vector<std::vector<std::string>> runs;
    for (const std::string& engine : {engine_a, engine_b}) {
      const fs::path out = dir / "r.csv";
      const CliResult r = RunCli("estimate --dataset " + testing::YcbvDir() + " --detections " +
                                     (dir / "dets.json").string() + " --out " + out.string() +
                                     " --iterations 6 --init-wide 2 --seed 3 -q --pixel-stride " + stride +
                                     " --engine " + engine +
                                     extra,
                                 dir);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      runs.push_back(RowsWithoutTime(out));
    }
    // Header + a row per class, and one per further box of classes 3 and 9 (theirs lie apart)
    // whose pose explains pixels of its own.
    ASSERT_GE(runs[0].size(), 5u);
    ASSERT_LE(runs[0].size(), 7u);
    EXPECT_EQ(runs[1], runs[0]) << engine_a << " vs " << engine_b << ", pixel stride " << stride;
  }
}

// The simd engine gives the fixed-point engine's rows (grids narrower than a block of rows once
// lost depth writes).
TEST(Cli, ThinAndTinyBoxesGiveTheFixedPointEnginesCsv) {
  ExpectThinBoxRowsEqual("thin_boxes", "fixed --threads 1", "simd --threads 2", "");
}

// The float-simd engine gives the scalar reference's rows, full mesh and LOD (its row blocks
// are used only where a box is at least a block wide).
TEST(Cli, ThinAndTinyBoxesGiveTheScalarEnginesCsvOnFloatSimd) {
  ExpectThinBoxRowsEqual("thin_boxes_float", "scalar --threads 1", "float-simd --threads 2",
                         " --samples 200 --lod-px 0");
  ExpectThinBoxRowsEqual("thin_boxes_float_lod", "scalar --threads 1", "float-simd --threads 2", " --lod-px 1");
}

// --simd-target: the default (best) target and the last, least capable one give the same rows;
// an unknown target is one clear error and no CSV.
TEST(Cli, SimdTargetCapGivesTheSameCsv) {
  const fs::path dir = testing::TempDir("simd_target");
  WriteText(dir / "dets.json", Scene49Detections().dump());
  const std::string targets = render::SimdTargetsAvailable();
  const std::string worst = targets.substr(targets.rfind(' ') + 1);
  std::vector<std::vector<std::string>> runs;
  for (const std::string& cap : {std::string(), worst}) {
    const fs::path out = dir / ("r" + cap + ".csv"), json = dir / ("r" + cap + ".json");
    const CliResult r = RunCli("estimate --dataset " + testing::YcbvDir() + " --detections " +
                                   (dir / "dets.json").string() + " --out " + out.string() + " --out-json " +
                                   json.string() + " --iterations 6 --init-wide 2 --seed 5 -q" +
                                   (cap.empty() ? "" : " --simd-target " + cap),
                               dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    runs.push_back(RowsWithoutTime(out));
    const std::string used = nlohmann::json::parse(ReadText(json))["options"]["engine"]["simd_target"];
    EXPECT_EQ(used, cap.empty() ? targets.substr(0, targets.find(' ')) : cap);
  }
  ASSERT_EQ(runs[0].size(), 5u);  // header + a row per instance: classes 3, 6 and two of 9
  EXPECT_EQ(runs[0], runs[1]) << "default vs --simd-target " << worst << " (of " << targets << ")";
  const fs::path bad = dir / "bad.csv";
  const CliResult e = RunCli("estimate --dataset " + testing::YcbvDir() + " --detections " +
                                 (dir / "dets.json").string() + " --out " + bad.string() + " --simd-target AVX9",
                             dir);
  EXPECT_EQ(e.exit_code, 1);
  EXPECT_NE(e.err.find("--simd-target must be best, "), std::string::npos) << e.err;
  EXPECT_FALSE(fs::exists(bad));
}

// --no-lod-unbiased (meshoptimizer's vertices for the LOD levels) against the default unbiased
// levels: both run, and --out-json records which.
TEST(Cli, LodVertexPlacementIsRecordedInTheJson) {
  const fs::path dir = testing::TempDir("lod_unbiased");
  WriteText(dir / "dets.json", Scene49Detections().dump());
  for (const std::string flag : {"", " --no-lod-unbiased"}) {
    const fs::path out = dir / "r.csv", json = dir / "r.json";
    const CliResult r = RunCli("estimate --dataset " + testing::YcbvDir() + " --detections " +
                                   (dir / "dets.json").string() + " --out " + out.string() + " --out-json " +
                                   json.string() + " --iterations 4 --seed 5 -q" + flag,
                               dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json doc = nlohmann::json::parse(ReadText(json));
    EXPECT_EQ(doc["options"]["engine"]["lod_unbiased"].get<bool>(), flag.empty()) << flag;
    ASSERT_EQ(doc["objects"].size(), 4u);  // classes 3, 6 and two instances of 9
    for (const auto& o : doc["objects"])
      for (const auto& n : o["box_triangles"]) EXPECT_GT(n.get<int>(), 0) << flag;
  }
}

// `mcpose bench` on one object with both baselines: every documented JSON field is there, the
// baselines count the same inliers as mcpose (the comparison is of the same work).
TEST(Cli, BenchWritesEveryFieldAndBaselinesAgree) {
  const fs::path dir = testing::TempDir("bench");
  const fs::path json = dir / "bench.json";
  const CliResult r = RunCli("bench --dataset " + testing::YcbvDir() + " --objects 10 --samples 120 --iterations 4 "
                             "--repeats 1 --engine simd --lod-px 1 --baselines embree,osmesa --json " + json.string(),
                             dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("011_banana"), std::string::npos) << r.out;
  const nlohmann::json doc = nlohmann::json::parse(ReadText(json));
  ASSERT_TRUE(doc.contains("machine"));
  ASSERT_EQ(doc["objects"].size(), 1u);
  const auto& o = doc["objects"][0];
  for (const char* f : {"obj_id", "name", "samples", "threads", "triangles_full", "triangles_lod", "lod_deviation_mm", "lod_meshopt_error_mm",
                        "triangles_after_cull", "fragments_per_iteration", "render_inlier_ms_median",
                        "full_iteration_ms_median", "full_iteration_ms_min", "full_iteration_ms_max",
                        "hypotheses_per_s", "embree_ms_median", "osmesa_ms_median", "speedup_embree",
                        "speedup_osmesa", "cdf_reads_per_draw", "cdf_reads_per_draw_naive", "depth_bytes_read",
                        "depth_bytes_read_naive", "initial_render_inlier_runs"})
    EXPECT_TRUE(o.contains(f)) << f;
  // One round (--repeats 1): mcpose timed 1 to 32 times, about as long as the faster baseline.
  EXPECT_GE(o["initial_render_inlier_runs"].get<int>(), 1);
  EXPECT_LE(o["initial_render_inlier_runs"].get<int>(), 32);
  EXPECT_EQ(o["obj_id"], 10);
  EXPECT_EQ(o["samples"], 120);
  EXPECT_EQ(o["per_iteration"]["full_ms"].size(), 4u);
  EXPECT_LT(o["triangles_lod"].get<int>(), o["triangles_full"].get<int>());
  // A simplified level: measured deviation above zero, at least meshoptimizer's figure, and
  // within the 1-pixel budget of this run at the banana's depth (about 1 mm).
  EXPECT_GT(o["lod_deviation_mm"].get<double>(), 0.0);
  EXPECT_GE(o["lod_deviation_mm"].get<double>(), o["lod_meshopt_error_mm"].get<double>());
  EXPECT_LT(o["lod_deviation_mm"].get<double>(), 2.0);
  EXPECT_LT(o["cdf_reads_per_draw"].get<double>(), o["cdf_reads_per_draw_naive"].get<double>());
  ASSERT_EQ(o["baselines"].size(), 2u);
  for (const auto& b : o["baselines"]) EXPECT_LT(b["inliers_rel_diff"].get<double>(), 0.01) << b.dump();

  // Bad input: one clear error, no JSON, nothing on stdout.
  fs::remove(json);
  for (const std::string& bad : {std::string("--objects 99"), std::string("--objects 10,10"),
                                 std::string("--baselines vulkan"), std::string("--iterations 0"), std::string("--engine gpu"),
                                 std::string("--simd-target AVX9")}) {
    const CliResult e = RunCli("bench --dataset " + testing::YcbvDir() + " " + bad + " --json " + json.string(), dir);
    EXPECT_EQ(e.exit_code, 1) << bad;
    EXPECT_NE(e.err.find("error"), std::string::npos) << bad << ": " << e.err;
    EXPECT_FALSE(fs::exists(json)) << bad;
    EXPECT_EQ(e.out, "") << bad;
  }
}

// `mcpose bench --no-backface-culling`: no triangle or cluster is culled as facing away, more
// triangles reach the rows, and both baselines, which then keep back faces too, still count the
// same inliers.
TEST(Cli, BenchWithoutBackfaceCullingKeepsBackFacesInEveryRenderer) {
  const fs::path dir = testing::TempDir("bench_no_culling");
  std::map<bool, nlohmann::json> runs;
  for (const bool culling : {true, false}) {
    const fs::path json = dir / (culling ? "on.json" : "off.json");
    const CliResult r = RunCli("bench --dataset " + testing::YcbvDir() + " --objects 5 --samples 120 --iterations 2 "
                               "--repeats 1 --baselines embree,osmesa --json " + json.string() +
                               (culling ? "" : " --no-backface-culling"),
                               dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    runs[culling] = nlohmann::json::parse(ReadText(json));
    EXPECT_EQ(runs[culling]["options"]["engine"]["backface_culling"].get<bool>(), culling);
  }
  const auto& on = runs[true]["objects"][0];
  const auto& off = runs[false]["objects"][0];
  EXPECT_GT(on["counters"]["culled_backface"].get<int64_t>(), 0);
  EXPECT_GT(on["counters"]["clusters_culled_backface"].get<int64_t>(), 0);
  EXPECT_EQ(off["counters"]["culled_backface"].get<int64_t>(), 0);
  EXPECT_EQ(off["counters"]["clusters_culled_backface"].get<int64_t>(), 0);
  EXPECT_GT(off["triangles_after_cull"].get<double>(), on["triangles_after_cull"].get<double>());
  ASSERT_EQ(off["baselines"].size(), 2u);
  for (const auto& b : off["baselines"]) EXPECT_LT(b["inliers_rel_diff"].get<double>(), 0.01) << b.dump();
}

TEST(Cli, BopAndNativeLayoutsGiveTheSamePoses) {
  const fs::path dir = testing::TempDir("bop_vs_native");
  nlohmann::json dets = Scene49Detections();
  for (auto d : Scene49Detections()) {  // and image 3 too
    d["image_id"] = 3;
    dets.push_back(d);
  }
  WriteText(dir / "dets.json", dets.dump());
  // The BOP layout reads its own test_targets_bop19.json (one instance of each class in these
  // images); the native layout is given the same file.
  const std::string targets = testing::BopDir() + "/test_targets_bop19.json";
  std::vector<std::vector<PoseResult>> results;
  for (const std::string& root : {testing::YcbvDir(), testing::BopDir()}) {
    const bool native = results.empty();
    const fs::path out = dir / (native ? "native.csv" : "bop.csv");
    const CliResult r = RunCli("estimate --dataset " + root + " --detections " + (dir / "dets.json").string() +
                                   " --out " + out.string() + " --iterations 8 -q" +
                                   (native ? " --targets " + targets : std::string()),
                               dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto rows = ReadResultsCsv(out.string());
    ASSERT_TRUE(rows.ok()) << rows.status().ToString();
    results.push_back(*rows);
  }
  ASSERT_EQ(results[0].size(), 6u);  // per image: classes 3, 6 and 9, one instance each
  ASSERT_EQ(results[0].size(), results[1].size());
  for (size_t i = 0; i < results[0].size(); ++i) {
    const PoseResult &a = results[0][i], &b = results[1][i];
    EXPECT_EQ(a.obj_id, b.obj_id);
    EXPECT_NEAR(a.score, b.score, 1e-6);
    EXPECT_LT((a.T_cam_obj.R - b.T_cam_obj.R).cwiseAbs().maxCoeff(), 1e-6) << i;
    EXPECT_LT((a.T_cam_obj.t - b.T_cam_obj.t).cwiseAbs().maxCoeff(), 1e-6) << i;  // metres
  }
}

TEST(Cli, EvalScoresGroundTruthDetectionsRunOnBothLayouts) {
  const fs::path dir = testing::TempDir("eval_cli");
  for (const std::string& root : {testing::YcbvDir(), testing::BopDir()}) {
    const CliResult d = RunCli("detections-from-gt --dataset " + root + " --out " + (dir / "d.json").string(), dir);
    ASSERT_EQ(d.exit_code, 0) << d.err;
    // An empty results file: every target is a failure, nothing crashes.
    WriteText(dir / "empty.csv", "scene_id,im_id,obj_id,score,R,t,time\n");
    const CliResult e = RunCli("eval --dataset " + root + " --results " + (dir / "empty.csv").string(), dir);
    ASSERT_EQ(e.exit_code, 0) << e.err;
    EXPECT_NE(e.out.find("ALL"), std::string::npos) << e.out;
  }
}

// The tuna can of 49/1 turned about its axis: the full mesh at every pixel jitters less from one
// turn to the next than the defaults' level of detail at pixel stride 2 (docs/engine-notes.md, turn profiles).
TEST(Cli, TurnProfileOfTheTunaCan) {
  const fs::path dir = testing::TempDir("turn_profile");
  WriteText(dir / "d.json", Scene49Detections().dump());
  const std::string base = "turn-profile --dataset " + testing::YcbvDir() + " --detections " + (dir / "d.json").string();
  std::map<std::string, nlohmann::json> runs;
  for (const std::string opts : {"", " --engine float-simd --lod-px 0 --pixel-stride 1 --max-grid-pixels 0"}) {
    const fs::path json = dir / (opts.empty() ? "defaults.json" : "reference.json");
    const CliResult r = RunTools(base + " --obj 6 --threads 2 --json " + json.string() + opts, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("007_tuna_fish_can about model axis z"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\n49/1 "), std::string::npos) << r.out;
    runs[opts.empty() ? "defaults" : "reference"] = nlohmann::json::parse(ReadText(json));
  }
  const nlohmann::json& d = runs["defaults"]["instances"];
  const nlohmann::json& ref = runs["reference"]["instances"];
  ASSERT_EQ(d.size(), 1u);
  ASSERT_EQ(ref.size(), 1u);
  EXPECT_EQ(d[0]["weight"].size(), 72u);
  EXPECT_EQ(d[0]["stride"], 2);
  EXPECT_EQ(ref[0]["stride"], 1);
  EXPECT_LT(d[0]["triangles"].get<int>(), ref[0]["triangles"].get<int>());
  EXPECT_GT(d[0]["jitter"].get<double>(), 1.5 * ref[0]["jitter"].get<double>());

  // Bad input: one error, a non-zero exit, no JSON.
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {" --obj 99", "99"}, {" --obj 5", "no box of obj_id 5"}, {" --obj 6 --step-deg 7", "divide 360"},
           {" --obj 6 --engine warp", "--engine must be"}}) {
    const fs::path json = dir / "bad.json";
    const CliResult r = RunTools(base + args + " --json " + json.string(), dir);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(json)) << args;
  }
}

// The refinement floor on the BOP frames: every instance aligned from its truth, the summary and
// the per-instance JSON; bad options give one error and no JSON.
TEST(Cli, RefineFloorOnTheBopFrames) {
  const fs::path dir = testing::TempDir("refine_floor");
  const fs::path json = dir / "floor.json";
  const std::string base = "refine-floor --dataset " + testing::BopDir();
  const CliResult r = RunTools(base + " --start-mm 10 --start-deg 5 --json " + json.string(), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\nALL "), std::string::npos) << r.out;
  const nlohmann::json doc = nlohmann::json::parse(ReadText(json));
  const int n = doc["overall"]["instances"].get<int>();
  EXPECT_GT(n, 0);
  ASSERT_EQ(doc["instances"].size(), static_cast<size_t>(n));
  EXPECT_EQ(doc["options"]["start_mm"], 10.0);
  EXPECT_EQ(doc["options"]["iterations"], 20);
  for (const auto& i : doc["instances"]) {
    EXPECT_NEAR(i["adds_start_mm"].get<double>(), 0, 10.001);
    EXPECT_LT(i["adds_aligned_mm"].get<double>(), 10.0) << i.dump();
  }
  EXPECT_LT(doc["overall"]["mean_aligned_adds_mm"].get<double>(), doc["overall"]["mean_start_adds_mm"].get<double>());

  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {" --start-deg 200", "start_deg must be in [0, 180]"},
           {" --tukey 0", "the alignment's Tukey scale must be > 0"},
           {" --iterations -1", "iterations must be >= 0"},
           {" --box-margin -1", "box_margin must be >= 0"}}) {
    const fs::path bad = dir / "bad.json";
    const CliResult b = RunTools(base + args + " --json " + bad.string(), dir);
    EXPECT_NE(b.exit_code, 0) << args;
    EXPECT_NE(b.err.find(message), std::string::npos) << args << ": " << b.err;
    EXPECT_FALSE(fs::exists(bad)) << args;
  }
  const CliResult missing = RunTools("refine-floor --dataset " + (dir / "nowhere").string(), dir);
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("nowhere"), std::string::npos) << missing.err;
}

// Misses on a BOP frame: every object at its truth but one moved 5 cm; that one is the only
// answer listed, and the truth outweighs it (a search failure). Bad input: one error, no JSON.
TEST(Cli, MissesTellsSearchFromWeightFailures) {
  const fs::path dir = testing::TempDir("misses");
  auto ds = Dataset::Open(testing::BopDir());
  ASSERT_TRUE(ds.ok()) << ds.status().ToString();
  const FrameKey key = (*ds)->Frames().front();
  auto frame = (*ds)->LoadFrame(key);
  ASSERT_TRUE(frame.ok()) << frame.status().ToString();
  ASSERT_FALSE(frame->gt.empty());
  std::vector<PoseResult> rows;
  for (const GtInstance& g : frame->gt) {
    PoseResult r;
    r.scene_id = key.scene_id, r.im_id = key.image_id, r.obj_id = g.obj_id, r.score = 1;
    r.T_cam_obj = g.T_cam_obj;
    if (rows.empty()) r.T_cam_obj.t.x() += 0.05;
    rows.push_back(r);
  }
  ASSERT_TRUE(WriteResultsCsv((dir / "r.csv").string(), rows).ok());
  const CliResult d = RunCli("detections-from-gt --dataset " + testing::BopDir() + " --jitter 0 --distractors 0 --out " +
                             (dir / "d.json").string(), dir);
  ASSERT_EQ(d.exit_code, 0) << d.err;
  const std::string base = "misses --dataset " + testing::BopDir() + " --detections " + (dir / "d.json").string() +
                           " --scene " + std::to_string(key.scene_id) + " --appearance off";
  const fs::path json = dir / "m.json";
  const CliResult r = RunTools(base + " --results " + (dir / "r.csv").string() + " --json " + json.string(), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json doc = nlohmann::json::parse(ReadText(json));
  ASSERT_EQ(doc["misses"].size(), 1u) << r.out;
  const nlohmann::json& m = doc["misses"][0];
  EXPECT_EQ(m["obj_id"], rows[0].obj_id);
  EXPECT_EQ(m["im_id"], key.image_id);
  EXPECT_GT(m["adds_mm"].get<double>(), 10.0);
  EXPECT_EQ(m["failure"], "search") << m.dump();
  EXPECT_GT(m["truth_weight"].get<double>(), m["estimate_weight"].get<double>());
  EXPECT_LT(m["truth_aligned_adds_mm"].get<double>(), 10.0);
  EXPECT_NE(r.out.find("1 answers: 1 search failures, 0 weight failures"), std::string::npos) << r.out;
  // A search failure's basin: a step of 2.5-20 (deg, mm), or null where no probe reaches the estimate.
  for (const char* key : {"basin_turn_deg", "basin_shift_mm"}) {
    ASSERT_TRUE(m.contains(key)) << m.dump();
    EXPECT_TRUE(m[key].is_null() || (m[key].get<double>() >= 2.5 && m[key].get<double>() <= 20)) << m.dump();
  }
  EXPECT_NE(r.out.find("search failures' basin, median:"), std::string::npos) << r.out;
  // As the filter weighs (its level of detail and pixel stride): the same verdict.
  const CliResult f = RunTools(base + " --as-filter --results " + (dir / "r.csv").string() + " --json " + json.string(), dir);
  ASSERT_EQ(f.exit_code, 0) << f.err;
  const nlohmann::json as_filter = nlohmann::json::parse(ReadText(json));
  EXPECT_EQ(as_filter["as_filter"], true);
  ASSERT_EQ(as_filter["misses"].size(), 1u);
  EXPECT_EQ(as_filter["misses"][0]["failure"], "search");
  EXPECT_NE(as_filter["misses"][0]["estimate_weight"], m["estimate_weight"]) << "weighed at another resolution";

  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {" --results " + (dir / "none.csv").string(), "none.csv"},
           {" --results " + (dir / "r.csv").string() + " --min-adds-mm -1", "--min-adds-mm must be >= 0"}}) {
    const fs::path bad = dir / "bad.json";
    const CliResult b = RunTools(base + args + " --json " + bad.string(), dir);
    EXPECT_NE(b.exit_code, 0) << args;
    EXPECT_NE(b.err.find(message), std::string::npos) << args << ": " << b.err;
    EXPECT_FALSE(fs::exists(bad)) << args;
  }
}

// Relight: a YCB-Video dataset whose colour images are transformed and whose other files are
// links to the original; written whole or not at all; the result loads and estimates.
TEST(Cli, RelightWritesATransformedDatasetOrNothing) {
  const fs::path dir = testing::TempDir("relight");
  const fs::path src = testing::MakeYcbvCopy("relight_src");
  const fs::path out = dir / "relit";
  const CliResult r = RunTools("relight --dataset " + src.string() + " --out " + out.string() +
                                   " --transform white-balance:1.3,1,0.7",
                               dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(out / "classes.txt"));
  EXPECT_TRUE(fs::is_symlink(out / "data/0049/000001-depth.png"));
  ASSERT_TRUE(fs::is_regular_file(out / "data/0049/000001-color.png"));
  EXPECT_FALSE(fs::is_symlink(out / "data/0049/000001-color.png"));
  auto before = io::ReadColourPng((src / "data/0049/000001-color.png").string());
  auto after = io::ReadColourPng((out / "data/0049/000001-color.png").string());
  ASSERT_TRUE(before.ok() && after.ok());
  ASSERT_EQ(before->rgba.size(), after->rgba.size());
  int64_t red = 0, blue = 0;
  for (size_t i = 0; i < before->rgba.size(); i += 4)
    red += after->rgba[i] - before->rgba[i], blue += after->rgba[i + 2] - before->rgba[i + 2];
  EXPECT_GT(red, 0);
  EXPECT_LT(blue, 0);
  auto ds = Dataset::Open(out.string());
  ASSERT_TRUE(ds.ok()) << ds.status().ToString();
  EXPECT_EQ((*ds)->Frames().size(), 1u);

  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {" --out " + out.string() + " --transform gamma:2", "already exists"},
           {" --out " + (dir / "b").string() + " --transform gamma:0", "'gamma:0'"},
           {" --out " + (dir / "c").string() + " --transform sepia", "unknown transform 'sepia'"},
           {" --out " + (dir / "no/d").string() + " --transform gamma:2", "does not exist"}}) {
    const CliResult b = RunTools("relight --dataset " + src.string() + args, dir);
    EXPECT_NE(b.exit_code, 0) << args;
    EXPECT_NE(b.err.find(message), std::string::npos) << args << ": " << b.err;
  }
  EXPECT_FALSE(fs::exists(dir / "b"));
  EXPECT_FALSE(fs::exists(dir / "c"));
  const CliResult bop = RunTools("relight --dataset " + testing::BopDir() + " --out " + (dir / "e").string() +
                                     " --transform gamma:2",
                                 dir);
  EXPECT_NE(bop.exit_code, 0);
  EXPECT_NE(bop.err.find("not a YCB-Video dataset"), std::string::npos) << bop.err;
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << "left behind: " << e.path();
}

// Twin margins on the key frame: a table per object, JSON per instance; the truth's weight
// margins are finite; an answer far from the truth is listed with its candidates' reach.
TEST(Cli, TwinMarginOnTheKeyFrame) {
  const fs::path dir = testing::TempDir("twin_margin");
  const fs::path src = testing::MakeYcbvCopy("twin_margin_src");
  const fs::path json = dir / "m.json";
  const CliResult r = RunTools("twin-margin --dataset " + src.string() + " --json " + json.string(), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\nALL "), std::string::npos) << r.out;
  const nlohmann::json doc = nlohmann::json::parse(ReadText(json));
  ASSERT_EQ(doc["instances"].size(), 4u);
  for (const auto& i : doc["instances"]) EXPECT_TRUE(std::isfinite(i["margin"].get<double>())) << i.dump();
  const CliResult bad = RunTools("twin-margin --dataset " + src.string() + " --right-mm 50 --wrong-mm 10", dir);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("right_m <= wrong_m"), std::string::npos) << bad.err;
}

// mcpose synth: the same dataset for a seed; it loads, estimates and evaluates like any BOP
// dataset, with the textured models through --models; bad options leave nothing behind.
TEST(Cli, SynthRoundTripsThroughEstimateAndEval) {
  const fs::path dir = testing::TempDir("synth");
  const std::string models = testing::DataDir() + "/ycbv_textured/models";
  if (!fs::exists(models)) GTEST_SKIP() << "no " << models;
  const std::string seed = "synth -q --models " + models + " --seed 5";
  const std::string base = seed + " --frames 2";
  const CliResult a = RunCli(base + " --out " + (dir / "a").string(), dir);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const CliResult b = RunCli(base + " --out " + (dir / "b").string(), dir);
  ASSERT_EQ(b.exit_code, 0) << b.err;
  for (const char* f : {"test/000000/scene_gt.json", "test/000000/scene_gt_info.json", "test/000000/scene_camera.json",
                        "test/000000/depth/000002.png", "test/000000/rgb/000002.png", "detections.json", "camera.json",
                        "models/models_info.json"})
    EXPECT_EQ(ReadText(dir / "a" / f), ReadText(dir / "b" / f)) << f;
  const nlohmann::json info = nlohmann::json::parse(ReadText(dir / "a/test/000000/scene_gt_info.json"));
  ASSERT_EQ(info.size(), 2u);
  for (const auto& [im, rows] : info.items()) {
    EXPECT_GE(rows.size(), 3u);
    EXPECT_LE(rows.size(), 7u);
    for (const auto& r : rows) EXPECT_GE(r["visib_fract"].get<double>(), 0.1);
  }
  const std::string ds = (dir / "a").string();
  const CliResult e = RunCli("estimate -q --dataset " + ds + " --models " + models + " --detections " + ds +
                                 "/detections.json --out " + (dir / "r.csv").string(),
                             dir);
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const CliResult v = RunCli("eval --dataset " + ds + " --results " + (dir / "r.csv").string() + " --json " +
                                 (dir / "e.json").string(),
                             dir);
  ASSERT_EQ(v.exit_code, 0) << v.err;
  const nlohmann::json eval = nlohmann::json::parse(ReadText(dir / "e.json"));
  EXPECT_EQ(eval["overall"]["with_result"], eval["overall"]["instances"]);
  EXPECT_GT(eval["overall"]["adds_lt_4cm"].get<double>(), 0.5) << eval["overall"].dump();

  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {" --out " + ds, "already exists"},
           {" --out " + (dir / "c").string() + " --objects 5 2", "min_objects"},
           {" --out " + (dir / "d").string() + " --frames 0", "frames must lie in"},
           {" --out " + (dir / "e").string() + " --distance 0.1 1", "min_distance_m"},
           {" --out " + (dir / "f").string() + " --jpeg 101", "jpeg_quality"}}) {
    const CliResult bad = RunCli((args.find("--frames") != std::string::npos ? seed : base) + args, dir);
    EXPECT_NE(bad.exit_code, 0) << args;
    EXPECT_NE(bad.err.find(message), std::string::npos) << args << ": " << bad.err;
  }
  const CliResult nomodels = RunCli("synth --models " + (dir / "none").string() + " --out " + (dir / "g").string(), dir);
  EXPECT_NE(nomodels.exit_code, 0);
  EXPECT_NE(nomodels.err.find("does not exist"), std::string::npos) << nomodels.err;
  for (const char* f : {"c", "d", "e", "f", "g"}) EXPECT_FALSE(fs::exists(dir / f)) << f;
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << "left behind: " << entry.path();
}

TEST(Cli, HelpOnEveryCommand) {
  const fs::path dir = testing::TempDir("help");
  for (const char* cmd : {"", "estimate ", "detections-from-gt ", "eval ", "bench ", "synth "}) {
    const CliResult r = RunCli(std::string(cmd) + "--help", dir);
    EXPECT_EQ(r.exit_code, 0) << cmd;
    EXPECT_NE(r.out.find("--"), std::string::npos) << cmd;
  }
  for (const char* cmd : {"", "ambiguity ", "turn-profile ", "refine-floor ", "misses ", "relight ", "twin-margin "}) {
    const CliResult r = RunTools(std::string(cmd) + "--help", dir);
    EXPECT_EQ(r.exit_code, 0) << cmd;
    EXPECT_NE(r.out.find("--"), std::string::npos) << cmd;
  }
}

// An engine feature the chosen engine cannot use is off by default there, and an error when
// asked for: `--engine scalar` runs as is, `--engine scalar --cluster-culling` does not.
TEST(Cli, EngineFeaturesFollowTheEngineAndAreRejectedWhereMeaningless) {
  const fs::path dir = testing::TempDir("engine_features");
  WriteText(dir / "dets.json", Scene49Detections().dump());
  const std::string base = "estimate --dataset " + testing::YcbvDir() + " --detections " + (dir / "dets.json").string() +
                           " --iterations 2 --samples 32 -q --out " + (dir / "r.csv").string() + " --out-json " +
                           (dir / "r.json").string();
  const CliResult ok = RunCli(base + " --engine scalar --lod-px 0", dir);
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const nlohmann::json engine = nlohmann::json::parse(ReadText(dir / "r.json"))["options"]["engine"];
  EXPECT_EQ(engine["backend"], "scalar");
  EXPECT_FALSE(engine["cluster_culling"].get<bool>());
  EXPECT_FALSE(engine["batched_setup"].get<bool>());
  EXPECT_FALSE(engine["lod_unbiased"].get<bool>());
  fs::remove(dir / "r.csv");
  for (const auto& [args, field] : std::vector<std::pair<std::string, std::string>>{
           {" --engine scalar --cluster-culling", "engine.cluster_culling"},
           {" --engine float-simd --batched-setup", "engine.batched_setup"},
           {" --lod-px 0 --lod-unbiased", "engine.lod_unbiased"}}) {
    const CliResult r = RunCli(base + args, dir);
    EXPECT_EQ(r.exit_code, 1) << args;
    EXPECT_NE(r.err.find(field), std::string::npos) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(dir / "r.csv")) << args;
  }
}

// Several instances of one class: synth --copies 3 makes frames with three potted meat cans and
// three tomato soup cans (seed 5); estimate gives each instance its row, every one within 2 cm
// ADD-S; --max-instances 1 gives the first row of each class alone, the same pose; BOP's
// inst_count caps a class where the targets give it.
TEST(Cli, SeveralInstancesOfAClassGetARowEach) {
  const fs::path dir = testing::TempDir("instances");
  const std::string models = testing::DataDir() + "/ycbv_textured/models";
  if (!fs::exists(models)) GTEST_SKIP() << "no " << models;
  const std::string ds = (dir / "set").string();
  const CliResult made = RunCli("synth -q --models " + models + " --seed 5 --frames 2 --copies 3 --objects 3 3 "
                                "--distractors 0 --out " + ds, dir);
  ASSERT_EQ(made.exit_code, 0) << made.err;
  const std::string run = "estimate -q --appearance off --dataset " + ds + " --detections " + ds + "/detections.json";
  const auto rows = [&](const std::string& csv) {
    std::map<std::string, std::vector<std::string>> by_class;  // "im,obj" -> rows, columns 1-6
    std::istringstream in(ReadText(dir / csv));
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      std::vector<std::string> cols;
      std::stringstream ls(line);
      for (std::string c; std::getline(ls, c, ',');) cols.push_back(c);
      by_class[cols[1] + "," + cols[2]].push_back(cols[0] + cols[1] + cols[2] + cols[3] + cols[4] + cols[5]);
    }
    return by_class;
  };
  ASSERT_EQ(RunCli(run + " --out " + (dir / "all.csv").string(), dir).exit_code, 0);
  const auto all = rows("all.csv");
  ASSERT_EQ(all.size(), 2u);
  for (const auto& [key, r] : all) EXPECT_EQ(r.size(), 3u) << key;
  const CliResult v = RunCli("eval --dataset " + ds + " --results " + (dir / "all.csv").string() + " --json " +
                                 (dir / "e.json").string(), dir);
  ASSERT_EQ(v.exit_code, 0) << v.err;
  const nlohmann::json eval = nlohmann::json::parse(ReadText(dir / "e.json"));
  ASSERT_EQ(eval["instances"].size(), 6u);
  for (const auto& i : eval["instances"]) EXPECT_LT(i["adds_m"].get<double>(), 0.02) << i.dump();

  ASSERT_EQ(RunCli(run + " --max-instances 1 --out " + (dir / "one.csv").string(), dir).exit_code, 0);
  const auto one = rows("one.csv");
  ASSERT_EQ(one.size(), 2u);
  for (const auto& [key, r] : one) {
    ASSERT_EQ(r.size(), 1u) << key;
    EXPECT_EQ(r[0], all.at(key)[0]) << key;
  }
  std::ofstream(dir / "targets.json") << R"([{"scene_id": 0, "im_id": 1, "obj_id": 9, "inst_count": 2}])";
  ASSERT_EQ(RunCli(run + " --targets " + (dir / "targets.json").string() + " --out " + (dir / "t.csv").string(), dir)
                .exit_code,
            0);
  const auto capped = rows("t.csv");
  EXPECT_EQ(capped.at("1,9").size(), 2u);
  EXPECT_EQ(capped.at("2,4").size(), 3u);
  const CliResult bad = RunCli(run + " --max-instances -1 --out " + (dir / "bad.csv").string(), dir);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("max_instances"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace mcpose

namespace mcpose {
namespace {

// The 0001/000001 detections: the cracker box (a model with its own texture) and the sugar box.
nlohmann::json Scene1Detections() {
  return nlohmann::json::parse(R"([
    {"scene_id": 1, "image_id": 1, "category_id": 2, "score": 0.9, "bbox": [326, 129, 166, 235]},
    {"scene_id": 1, "image_id": 1, "category_id": 3, "score": 0.8, "bbox": [235, 241, 120, 239]}
  ])");
}

// --appearance off gives what an estimator without colour gives: the same rows as a run, colour
// on, on models that have no colour at all.
TEST(CliColour, AppearanceOffIsDepthOnlyExactly) {
  const fs::path dir = testing::TempDir("appearance_off");
  WriteText(dir / "dets.json", Scene1Detections().dump());
  const fs::path plain = dir / "plain";
  fs::create_directories(plain);
  for (const char* name : {"003_cracker_box", "004_sugar_box"}) {
    fs::create_directories(plain / name);
    fs::copy_file(fs::path(testing::YcbvDir()) / "models" / name / "textured_simple.obj", plain / name / "textured_simple.obj");
  }
  const std::string base = "estimate --dataset " + testing::YcbvDir() + " --detections " + (dir / "dets.json").string() +
                           " --iterations 6 --seed 3 -q";
  const CliResult off = RunCli(base + " --appearance off --out " + (dir / "off.csv").string(), dir);
  ASSERT_EQ(off.exit_code, 0) << off.err;
  const CliResult none = RunCli(base + " --models " + plain.string() + " --out " + (dir / "none.csv").string(), dir);
  ASSERT_EQ(none.exit_code, 0) << none.err;
  const CliResult on = RunCli(base + " --out " + (dir / "on.csv").string() + " --out-json " + (dir / "on.json").string(), dir);
  ASSERT_EQ(on.exit_code, 0) << on.err;
  auto a = ReadResultsCsv((dir / "off.csv").string()), b = ReadResultsCsv((dir / "none.csv").string()),
       c = ReadResultsCsv((dir / "on.csv").string());
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  ASSERT_EQ(a->size(), 2u);
  for (size_t i = 0; i < a->size(); ++i) {
    EXPECT_EQ((*a)[i].T_cam_obj.R, (*b)[i].T_cam_obj.R) << i;
    EXPECT_EQ((*a)[i].T_cam_obj.t, (*b)[i].T_cam_obj.t) << i;
    EXPECT_EQ((*a)[i].score, (*b)[i].score) << i;
  }
  // With colour on, the cracker box (its own texture) is weighed with colour and its twins
  // resolved; the sugar box (no colour) is not.
  const nlohmann::json doc = nlohmann::json::parse(ReadText(dir / "on.json"));
  EXPECT_TRUE(doc["objects"][0]["colour"].get<bool>());
  EXPECT_TRUE(doc["objects"][0]["twins"]["ran"].get<bool>());
  EXPECT_EQ(doc["objects"][0]["twins"]["candidates"].get<int>(), 24);  // 12 turns of 30 degrees, and the same after a flip
  EXPECT_FALSE(doc["objects"][1]["colour"].get<bool>());
  EXPECT_FALSE(doc["objects"][1]["twins"]["ran"].get<bool>());
  EXPECT_TRUE(doc["objects"][1]["refine"]["ran"].get<bool>());
  EXPECT_NE((*a)[0].T_cam_obj.t, (*c)[0].T_cam_obj.t);
}

// capture-appearance on two frames of video 49 writes a models folder whose captured models
// carry a texture; estimate --models uses it; a bad frame list is one error naming its line.
TEST(CliColour, CaptureWritesAModelsFolderThatEstimateUses) {
  const fs::path dir = testing::TempDir("capture_cli");
  WriteText(dir / "frames.txt", "# two frames\n0049/000001\n\n0049/000002\n");
  const CliResult r = RunCli("capture-appearance --dataset " + testing::YcbvDir() + " --frames " +
                                 (dir / "frames.txt").string() + " --out " + (dir / "models").string(),
                             dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("004_sugar_box            captured"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("003_cracker_box          own"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir / "models/004_sugar_box/texture_map.png"));
  EXPECT_TRUE(fs::exists(dir / "models/003_cracker_box/texture_map.jpg"));
  EXPECT_TRUE(fs::exists(dir / "models/002_master_chef_can/textured_simple.obj"));
  WriteText(dir / "dets.json", Scene49Detections().dump());
  const CliResult e = RunCli("estimate --dataset " + testing::YcbvDir() + " --models " + (dir / "models").string() +
                                 " --detections " + (dir / "dets.json").string() + " --iterations 4 -q --out " +
                                 (dir / "r.csv").string() + " --out-json " + (dir / "r.json").string(),
                             dir);
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const nlohmann::json doc = nlohmann::json::parse(ReadText(dir / "r.json"));
  for (const auto& o : doc["objects"]) EXPECT_TRUE(o["colour"].get<bool>()) << o["name"];
  WriteText(dir / "bad.txt", "0049/000001\n0049/000077\n");
  const CliResult bad = RunCli("capture-appearance --dataset " + testing::YcbvDir() + " --frames " +
                                   (dir / "bad.txt").string() + " --out " + (dir / "out2").string(),
                               dir);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("bad.txt: line 2"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "out2"));
  // Replacing own colour: the cracker box, which these frames do not show, loses its texture
  // instead of keeping it.
  const CliResult rep = RunCli("capture-appearance --replace-own-colour --dataset " + testing::YcbvDir() +
                                   " --frames " + (dir / "frames.txt").string() + " --out " + (dir / "rep").string(),
                               dir);
  ASSERT_EQ(rep.exit_code, 0) << rep.err;
  EXPECT_NE(rep.out.find("003_cracker_box          none"), std::string::npos) << rep.out;
  const std::string obj = ReadText(dir / "rep/003_cracker_box/textured_simple.obj");
  EXPECT_EQ(obj.find("mtllib"), std::string::npos);
  EXPECT_NE(obj.find("\nf "), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "rep/003_cracker_box/texture_map.jpg"));
  EXPECT_TRUE(fs::exists(dir / "rep/003_cracker_box/points.xyz"));
}

// ---- mcpose track -----------------------------------------------------------------------------

// Video 49 frames 1-3 from the ground-truth boxes: frame 1 starts every track, later frames are
// tracked (none lost), every tracked pose within 2 cm ADD-S of the ground truth by mcpose eval,
// and the same CSV at 1 and 2 threads.
TEST(CliTrack, TracksVideo49AtAnyThreadCount) {
  const fs::path dir = testing::TempDir("track");
  std::vector<std::vector<std::string>> runs;
  for (int threads : {1, 2}) {
    const fs::path out = dir / ("t" + std::to_string(threads) + ".csv"), js = dir / "t.json";
    const CliResult r = RunCli("track -q --dataset " + testing::YcbvDir() + " --video 49 --frames 1-3 --samples 200 " +
                                   "--iterations 30 --threads " + std::to_string(threads) + " --out " + out.string() +
                                   " --out-json " + js.string(),
                               dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    runs.push_back(RowsWithoutTime(out));
    const nlohmann::json doc = nlohmann::json::parse(ReadText(js));
    ASSERT_EQ(doc["steps"].size(), 12u);  // 4 objects x 3 frames
    for (const nlohmann::json& s : doc["steps"]) {
      EXPECT_EQ(s["initialised"].get<bool>(), s["im_id"].get<int>() == 1) << s.dump();
      EXPECT_FALSE(s["lost"].get<bool>()) << s.dump();
      EXPECT_GT(s["fit"].get<double>(), 0.4) << s.dump();
    }
  }
  EXPECT_EQ(runs[0], runs[1]);
  const fs::path ej = dir / "eval.json";
  const CliResult e = RunCli("eval --dataset " + testing::YcbvDir() + " --results " + (dir / "t1.csv").string() +
                                 " --json " + ej.string(),
                             dir);
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const nlohmann::json ev = nlohmann::json::parse(ReadText(ej));
  int scored = 0;
  for (const nlohmann::json& i : ev["instances"]) {
    if (!i["has_result"].get<bool>() || i["im_id"].get<int>() == 1) continue;
    ++scored;
    EXPECT_LT(i["adds_m"].get<double>(), 0.02) << i.dump();
  }
  EXPECT_EQ(scored, 8);
}

// Frames past the video's end (even past any int) mean "to the end": the last frame alone here.
TEST(CliTrack, FramesPastTheEndMeanToTheEnd) {
  const fs::path dir = testing::TempDir("track_end");
  for (const char* range : {"10-1000000000", "10-99999999999999999999"}) {
    const CliResult r = RunCli("track -q --dataset " + testing::YcbvDir() + " --video 49 --frames " + range +
                                   " --samples 50 --iterations 2 --out " + (dir / "t.csv").string(),
                               dir);
    ASSERT_EQ(r.exit_code, 0) << range << ": " << r.err;
    auto rows = ReadResultsCsv((dir / "t.csv").string());
    ASSERT_TRUE(rows.ok()) << rows.status().ToString();
    ASSERT_FALSE(rows->empty());
    for (const PoseResult& row : *rows) EXPECT_EQ(row.im_id, 10) << range;
    fs::remove(dir / "t.csv");
  }
}

TEST(CliTrack, BadInputIsOneErrorAndNoOutput) {
  const fs::path dir = testing::TempDir("track_bad");
  const std::string base = "track --dataset " + testing::YcbvDir() + " --out " + (dir / "t.csv").string() +
                           " --out-json " + (dir / "t.json").string() + " ";
  WriteText(dir / "unknown.json",
            R"([{"scene_id": 49, "image_id": 1, "category_id": 99, "score": 1, "bbox": [10, 10, 50, 50]}])");
  WriteText(dir / "outside.json",
            R"([{"scene_id": 49, "image_id": 1, "category_id": 3, "score": 1, "bbox": [700, 10, 50, 50]}])");
  const std::pair<std::string, std::string> cases[] = {
      {"--video 49 --frames 5-2", "--frames"},
      {"--video 49 --frames two", "--frames"},
      {"--video 77", "no frame of video 77"},
      {"--video 49 --frames 1-2 --detections " + (dir / "unknown.json").string(), "unknown class"},
      {"--video 49 --frames 1-2 --detections " + (dir / "missing.json").string(), "missing.json"},
      {"--video 49 --frames 1-2 --detections " + (dir / "outside.json").string(), (dir / "outside.json").string()},
      {"--video 49 --frames 11-99999999999999999999", "no frame of video 49"},
      {"--video 49 --lost-fit 1.5", "lost_fit"},
      {"--video 49 --track-iterations 0", "iterations"},
  };
  for (const auto& [args, must_contain] : cases) {
    const CliResult r = RunCli(base + args, dir);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_NE(r.err.find(must_contain), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "t.csv")) << args;
    EXPECT_FALSE(fs::exists(dir / "t.json")) << args;
  }
}

}  // namespace
}  // namespace mcpose
