// The visual report on real YCB-Video frames: the ground truth drawn by the report's renderer
// lands on the frame's label masks, and the report of the main job's 26 frames, made by the
// command line from an estimate run, opens in a headless browser with every image present.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli_run.h"
#include "mcpose/png_io.h"
#include "mcpose/dataset.h"
#include "report/overlay.h"
#include "test_data.h"

namespace mcpose {
namespace {

namespace fs = std::filesystem;
using testing::CliResult;
using testing::ReadText;
using testing::RunCli;

constexpr const char* kChromium = "/usr/bin/chromium";

int Count(const std::string& text, const std::string& needle) {
  int n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

// Each ground-truth silhouette the report draws, against the frame's visible (label) mask, on
// every real frame. Where the ground-truth objects hide each other, the silhouette's visible
// part (the pixels where this object's render is the nearest) is compared: IoU >= 0.9 for every
// object in view. For an object no other hides, the silhouette itself is compared (IoU >= 0.9)
// and the outline the report draws runs along the mask's border. The median IoU of those tells
// the camera convention apart: 0.997 with pixel centres at integer coordinates, 0.983 with
// centres at half-integers.
TEST(ReportReal, GroundTruthSilhouettesMatchTheLabelMasks) {
  auto ds = Dataset::Open(testing::YcbvDir());
  ASSERT_TRUE(ds.ok()) << ds.status().ToString();
  std::vector<double> unoccluded_iou;
  double min_visible_iou = 1;
  int compared = 0;
  for (const FrameKey& key : (*ds)->Frames()) {
    auto frame = (*ds)->LoadFrame(key);
    ASSERT_TRUE(frame.ok()) << frame.status().ToString();
    std::vector<DepthImage> rendered;
    for (const GtInstance& gt : frame->gt) {
      auto mesh = (*ds)->LoadMesh(gt.obj_id);
      ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
      rendered.push_back(report::RenderDepth(*mesh, gt.T_cam_obj, frame->K));
    }
    for (size_t g = 0; g < frame->gt.size(); ++g) {
      const std::string what = (*ds)->FrameName(key) + " obj " + std::to_string(frame->gt[g].obj_id);
      auto mask = (*ds)->LoadVisibleMask(key, frame->gt[g]);
      ASSERT_TRUE(mask.ok()) << mask.status().ToString();
      const MaskImage silhouette = report::Silhouette(rendered[g]);
      int inter = 0, uni = 0, visible = 0, drawn = 0, hidden = 0, front_inter = 0, front_uni = 0;
      for (size_t i = 0; i < silhouette.values.size(); ++i) {
        const bool s = silhouette.values[i] != 0, m = mask->values[i] != 0;
        bool front = s;  // drawn here and nearer than every other ground-truth object
        for (size_t o = 0; o < rendered.size() && front; ++o)
          front = o == g || !(rendered[o].depth_m[i] > 0 && rendered[o].depth_m[i] < rendered[g].depth_m[i]);
        inter += s && m, uni += s || m, visible += m, drawn += s, hidden += s && !front;
        front_inter += front && m, front_uni += front || m;
      }
      if (visible == 0) continue;  // out of view: nothing to compare
      ++compared;
      const double inside = static_cast<double>(inter) / visible, iou = static_cast<double>(inter) / uni;
      const double visible_iou = static_cast<double>(front_inter) / front_uni;
      const double hidden_share = static_cast<double>(hidden) / drawn;
      min_visible_iou = std::min(min_visible_iou, visible_iou);
      EXPECT_GE(inside, 0.95) << what;
      EXPECT_GE(visible_iou, 0.9) << what << ", hidden share " << hidden_share;
      if (hidden_share > 0.01) continue;
      unoccluded_iou.push_back(iou);
      EXPECT_GE(iou, 0.9) << what;
      // The outline the report draws lies on the mask's border, to a pixel.
      const MaskImage outline = report::Outline(silhouette), border = report::Outline(*mask);
      int on = 0, all = 0;
      for (int y = 0; y < outline.height; ++y)
        for (int x = 0; x < outline.width; ++x) {
          if (!outline.at(x, y)) continue;
          ++all;
          bool near = false;
          for (int dy = -1; dy <= 1 && !near; ++dy)
            for (int dx = -1; dx <= 1 && !near; ++dx) {
              const int xx = x + dx, yy = y + dy;
              near = xx >= 0 && yy >= 0 && xx < border.width && yy < border.height && border.at(xx, yy);
            }
          on += near;
        }
      EXPECT_GE(static_cast<double>(on) / all, 0.9) << what;
    }
  }
  EXPECT_EQ(compared, 108);  // every instance of the main job is in view
  ASSERT_GE(unoccluded_iou.size(), 20u);  // the convention check ran on enough objects
  std::sort(unoccluded_iou.begin(), unoccluded_iou.end());
  const double median = unoccluded_iou[unoccluded_iou.size() / 2];
  std::printf("  %d objects: visible-part IoU min %.3f; %zu unhidden: silhouette IoU min %.3f, median %.3f\n",
              compared, min_visible_iou, unoccluded_iou.size(), unoccluded_iou.front(), median);
  EXPECT_GE(median, 0.99);
}

// Mean and variance of the grey values of an image.
std::pair<double, double> GreyStats(const ColourImage& image) {
  double sum = 0, sum2 = 0;
  const size_t n = static_cast<size_t>(image.width) * image.height;
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* p = image.rgba.data() + 4 * i;
    const double g = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
    sum += g, sum2 += g * g;
  }
  const double mean = sum / n;
  return {mean, sum2 / n - mean * mean};
}

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The main job's frames (every real frame, its detector-like boxes with distractors), estimated
// with few samples and iterations to stay quick, then reported and opened in Chromium. The
// checks of the folder run without a browser; without Chromium the test ends there, skipped.
TEST(ReportReal, MainJobReportOpensInAHeadlessBrowser) {
  const fs::path dir = testing::TempDir("report_main_job");
  const std::string data = " --dataset " + testing::YcbvDir();
  const std::string dets = (dir / "dets.json").string(), csv = (dir / "results.csv").string(),
                    detail = (dir / "results.json").string();
  CliResult r = RunCli("detections-from-gt" + data + " --out " + dets + " --jitter 0.1 --distractors 0.3 --seed 0", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunCli("estimate" + data + " --detections " + dets + " --out " + csv + " --out-json " + detail +
                 " --iterations 3 --samples 64 --threads 2 -q",
             dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;

  const fs::path out = dir / "report";
  auto start = std::chrono::steady_clock::now();
  r = RunCli("report" + data + " --results " + csv + " --detections " + dets + " --detail " + detail +
                 " --gt --out " + out.string(),
             dir);
  const double report_s = Seconds(start);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("report: 26 images, 108 objects"), std::string::npos) << r.out;

  // The page: one section per frame, one card per object, each with its convergence plot; no
  // script and nothing from the network.
  const std::string html = ReadText(out / "index.html");
  EXPECT_EQ(Count(html, "<h2 id=\"img-"), 26);
  EXPECT_EQ(Count(html, "<div class=\"obj\""), 108);
  EXPECT_EQ(Count(html, ">convergence</text>"), 108);
  EXPECT_EQ(Count(html, "<script"), 0);
  EXPECT_EQ(Count(html, "http"), Count(html, "xmlns=\"http://www.w3.org/2000/svg\""));
  EXPECT_GE(Count(html, "stroke=\"#ff1744\""), 1);  // distractor boxes are marked

  // Every image the page names exists in the folder, and every file there is used.
  std::set<std::string> sources;
  const std::regex src_attr("src=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), src_attr); it != std::sregex_iterator(); ++it)
    sources.insert((*it)[1].str());
  EXPECT_GE(sources.size(), 26u + 108u);  // frames and residual maps
  for (const std::string& s : sources) {
    EXPECT_FALSE(fs::path(s).is_absolute()) << s;
    EXPECT_TRUE(fs::is_regular_file(out / s)) << "missing image " << s;
  }
  int64_t bytes = 0;
  for (const auto& f : fs::recursive_directory_iterator(out)) {
    if (!f.is_regular_file()) continue;
    bytes += static_cast<int64_t>(f.file_size());
    const std::string rel = fs::relative(f.path(), out).string();
    if (rel != "index.html" && rel != ".mcpose-report") {
      EXPECT_TRUE(sources.contains(rel)) << "unused file " << rel;
    }
  }
  EXPECT_LT(bytes, 30'000'000);

  // The browser: a screenshot of the page as loaded from disk, not blank, within a few seconds
  // (Chromium's own start on an empty page takes about 1 s of that).
  if (!fs::exists(kChromium)) GTEST_SKIP() << kChromium << " is not installed (scripts/install_deps.sh installs it)";
  const fs::path shot = dir / "screenshot.png";
  start = std::chrono::steady_clock::now();
  r = testing::RunProgram(std::string("timeout 120 ") + kChromium,
                          "--headless --no-sandbox --disable-gpu --user-data-dir=" + (dir / "chromium").string() +
                              " --screenshot=" + shot.string() + " --window-size=1280,2000 file://" +
                              fs::absolute(out / "index.html").string(),
                          dir);
  const double browser_s = Seconds(start);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(browser_s, 8.0);
  auto image = io::ReadColourPng(shot.string());
  ASSERT_TRUE(image.ok()) << image.status().ToString();
  EXPECT_EQ(image->width, 1280);
  EXPECT_EQ(image->height, 2000);
  const auto [mean, variance] = GreyStats(*image);
  // A blank page has variance 0; this page without its images (text, tables, plots) about
  // 1400, with the first frame in view about 4800.
  EXPECT_GT(variance, 2500) << "mean grey " << mean;
  std::printf("  report of 26 frames: %.1f s, %.1f MB in %zu images; chromium screenshot %.1f s; grey mean %.0f, "
              "variance %.0f\n",
              report_s, bytes / 1e6, sources.size(), browser_s, mean, variance);
}

// Bad input: one error line naming the file and the problem, exit code 1, and no report folder
// (nor its temporary folder) written.
TEST(ReportReal, BadInputGetsOneErrorLineAndNoReport) {
  const fs::path dir = testing::TempDir("report_bad_input");
  const std::string ycbv = testing::YcbvDir(), data = " --dataset " + ycbv;
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  const std::string header = "scene_id,im_id,obj_id,score,R,t,time\n";
  const std::string csv = write("results.csv", header + "49,1,3,0.9,1 0 0 0 1 0 0 0 1,0 0 800,-1\n");
  const std::string short_r = write("short_r.csv", header + "49,1,3,0.9,1 0 0 0 1,0 0 800,-1\n");
  const std::string no_header = write("no_header.csv", "49,1,3,0.9,1 0 0 0 1 0 0 0 1,0 0 800,-1\n");
  const std::string bad_class = write("bad_class.csv", header + "49,1,99,0.9,1 0 0 0 1 0 0 0 1,0 0 800,-1\n");
  const std::string bad_image = write("bad_image.csv", header + "49,7777,3,0.9,1 0 0 0 1 0 0 0 1,0 0 800,-1\n");
  const std::string detail = write("detail.json", "{ objects");
  const std::string missing = (dir / "missing.csv").string(), not_data = (dir / "not_data").string();
  fs::create_directories(not_data);
  struct Case {
    std::string args, error;
  };
  const std::vector<Case> cases = {
      {data + " --results " + missing, missing + ": file does not exist"},
      {data + " --results " + short_r, short_r + ": line 2: R must be 9 space-separated finite numbers"},
      {data + " --results " + no_header, no_header + ": line 1: expected the header"},
      {data + " --results " + bad_class, bad_class + ": a row of scene_id 49, im_id 1: obj_id 99 is not a class"},
      {data + " --results " + bad_image, bad_image + ": a row of scene_id 49, im_id 7777: the dataset " + ycbv +
                                             " has no such image"},
      {data + " --results " + csv + " --detail " + detail, detail + ": malformed JSON"},
      {" --dataset " + not_data + " --results " + csv, not_data + ": not a dataset folder"},
      {" --dataset " + (dir / "no_such_dataset").string() + " --results " + csv,
       (dir / "no_such_dataset").string() + ": dataset folder does not exist"},
  };
  for (const Case& c : cases) {
    const CliResult r = RunCli("report" + c.args + " --out " + (dir / "report").string(), dir);
    EXPECT_EQ(r.exit_code, 1) << c.args;
    EXPECT_EQ(r.err.rfind("mcpose: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(c.error), std::string::npos) << r.err;
    EXPECT_EQ(Count(r.err, "\n"), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "report")) << c.args;
    EXPECT_TRUE(testing::LeftBeside(dir / "report").empty()) << c.args;
  }

  // A folder that is not a report is not replaced.
  fs::create_directories(dir / "mine");
  std::ofstream(dir / "mine" / "notes.txt") << "keep";
  CliResult r = RunCli("report" + data + " --results " + csv + " --out " + (dir / "mine").string(), dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find((dir / "mine").string() + ": exists, is not empty and is not a report of mcpose"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(Count(r.err, "\n"), 1) << r.err;
  EXPECT_EQ(ReadText(dir / "mine" / "notes.txt"), "keep");
  EXPECT_TRUE(testing::LeftBeside(dir / "mine").empty());
  // Nor is a folder that merely holds an index.html.
  std::ofstream(dir / "mine" / "index.html") << "<p>mine</p>";
  r = RunCli("report" + data + " --results " + csv + " --out " + (dir / "mine").string(), dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(ReadText(dir / "mine" / "index.html"), "<p>mine</p>");

  // The same results into a fresh folder: a report of the one detected image, which a second
  // run replaces.
  const fs::path dets = dir / "dets.json";
  std::ofstream(dets) << R"([{"scene_id": 49, "image_id": 1, "category_id": 3, "score": 0.9, "bbox": [233, 132, 197, 208]}])";
  const std::string args = "report" + data + " --results " + csv + " --detections " + dets.string() +
                           " --out " + (dir / "report").string();
  r = RunCli(args, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("report: 1 image, 4 objects"), std::string::npos) << r.out;
  // A user's folder named like the report's temporary folder is left alone.
  fs::create_directories(dir / "report.tmp");
  std::ofstream(dir / "report.tmp" / "notes.txt") << "keep";
  // Replaced by a second run, named with a trailing slash.
  r = RunCli(args + "/", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "report" / "index.html"));
  EXPECT_EQ(ReadText(dir / "report.tmp" / "notes.txt"), "keep");
  fs::remove_all(dir / "report.tmp");
  EXPECT_TRUE(testing::LeftBeside(dir / "report").empty());
  // A file the report did not write keeps the folder from being replaced.
  std::ofstream(dir / "report" / "images" / "mine.png") << "not the report's";
  r = RunCli(args, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("holds images/mine.png, which no report wrote"), std::string::npos) << r.err;
  EXPECT_EQ(ReadText(dir / "report" / "images" / "mine.png"), "not the report's");
  EXPECT_TRUE(fs::exists(dir / "report" / "index.html"));
  EXPECT_TRUE(testing::LeftBeside(dir / "report").empty());
}

}  // namespace
}  // namespace mcpose
