// Malformed inputs a hostile tester would try, each written into a copy of a real dataset: the
// command refuses it with one line naming the file, exits non-zero and leaves no output file.
// A frame whose boxes hold no valid depth is not an error: a warning and no row.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mcpose/png_io.h"
#include "io/ycbv_dataset.h"
#include "mcpose/dataset.h"
#include "mcpose/results.h"
#include "cli_run.h"
#include "dataset_copy.h"
#include "test_data.h"

namespace mcpose {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::CliResult;
using testing::ReadText;
using testing::Replace;
using testing::RunCli;
using testing::WriteText;

enum class Layout { kYcbv, kBop };
enum class Command { kEstimate, kEval, kEvalWithBoxes };

struct HostileCase {
  std::string name;
  Layout layout;
  Command command;
  // Breaks one file of the dataset copy (or the detections / results beside it); returns the
  // text the error must contain: the path of the broken file.
  std::function<std::string(const fs::path& root)> breaker;
};

// Detections of scene 49 image 1 (both layouts hold it).
json Scene49Detections() {
  return json::parse(R"([
    {"scene_id": 49, "image_id": 1, "category_id": 3, "score": 0.9, "bbox": [233, 132, 197, 208]},
    {"scene_id": 49, "image_id": 1, "category_id": 6, "score": 0.8, "bbox": [434, 89, 97, 84]}
  ])");
}

// Results equal to the ground truth of scene 49 image 1 of the real dataset.
void WriteGroundTruthResults(Layout layout, const fs::path& csv) {
  const std::string root = layout == Layout::kYcbv ? testing::YcbvDir() : testing::BopDir();
  auto dataset = Dataset::Open(root, "test", "");
  ASSERT_TRUE(dataset.ok()) << dataset.status().ToString();
  auto frame = (*dataset)->LoadFrame(FrameKey{49, 1});
  ASSERT_TRUE(frame.ok()) << frame.status().ToString();
  std::vector<PoseResult> rows;
  for (const GtInstance& gt : frame->gt) {
    PoseResult r;
    r.scene_id = 49, r.im_id = 1, r.obj_id = gt.obj_id, r.score = 1, r.T_cam_obj = gt.T_cam_obj, r.time_s = 1;
    rows.push_back(r);
  }
  ASSERT_TRUE(WriteResultsCsv(csv.string(), rows).ok());
}

CliResult RunCase(Layout layout, Command command, const fs::path& root, const fs::path& dir) {
  if (command == Command::kEstimate) {
    return RunCli("estimate --dataset " + root.string() + " --detections " + (dir / "dets.json").string() + " --out " +
                      (dir / "res.csv").string() + " --out-json " + (dir / "res.json").string() +
                      " --iterations 2 --samples 16 --appearance off --quiet",
                  dir);
  }
  (void)layout;
  const std::string boxes = command == Command::kEvalWithBoxes ? " --detections " + (dir / "dets.json").string() : "";
  return RunCli("eval --dataset " + root.string() + " --results " + (dir / "in.csv").string() + boxes + " --json " +
                    (dir / "eval.json").string(),
                dir);
}

class HostileInput : public ::testing::TestWithParam<HostileCase> {};

TEST_P(HostileInput, OneLineNamingTheFileNonZeroExitNoOutput) {
  const HostileCase& c = GetParam();
  const fs::path root =
      c.layout == Layout::kYcbv ? testing::MakeYcbvCopy("hostile_" + c.name) : testing::MakeBopCopy("hostile_" + c.name);
  const fs::path dir = root.parent_path();
  WriteText(dir / "dets.json", Scene49Detections().dump());
  WriteGroundTruthResults(c.layout, dir / "in.csv");
  const std::string must_contain = c.breaker(root);
  const CliResult r = RunCase(c.layout, c.command, root, dir);
  EXPECT_NE(r.exit_code, 0) << c.name << "\n" << r.err;
  EXPECT_NE(r.err.find("mcpose: error:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(must_contain), std::string::npos) << "expected '" << must_contain << "' in: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  for (const char* out : {"res.csv", "res.json", "eval.json"}) {
    EXPECT_FALSE(fs::exists(dir / out)) << c.name << ": " << out << " left behind";
    EXPECT_TRUE(testing::LeftBeside(dir / out).empty()) << c.name << ": a temporary file of " << out << " left behind";
  }
}

// ---- Editing helpers ------------------------------------------------------------------------

void WriteDepth(const fs::path& p, int width, int height, uint16_t value) {
  fs::remove(p);
  io::Gray16Image image{width, height, std::vector<uint16_t>(static_cast<size_t>(width) * height, value)};
  ASSERT_TRUE(io::WriteGray16Png(p.string(), image).ok());
}

uint32_t Crc32(const unsigned char* p, size_t n) {
  uint32_t crc = 0xffffffffu;
  for (size_t i = 0; i < n; ++i) {
    crc ^= p[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

// The real depth PNG with its header claiming width x height (CRC fixed, so only the size lies).
void WriteDepthClaimingSize(const fs::path& p, uint32_t width, uint32_t height) {
  std::string bytes = ReadText(fs::canonical(p));
  auto put32 = [&](size_t at, uint32_t v) {
    for (int k = 0; k < 4; ++k) bytes[at + k] = static_cast<char>((v >> (24 - 8 * k)) & 0xff);
  };
  put32(16, width), put32(20, height);
  put32(29, Crc32(reinterpret_cast<const unsigned char*>(bytes.data()) + 12, 17));
  Replace(p, bytes);
}

fs::path Meta(const fs::path& ycbv) { return ycbv / "data/0049/000001-meta.mat"; }

// Rewrites meta.mat with `edit` applied to what it holds.
std::string EditMeta(const fs::path& ycbv, const std::function<void(io::YcbvMeta&)>& edit) {
  const fs::path p = Meta(ycbv);
  auto meta = io::ReadYcbvMeta(p.string());
  EXPECT_TRUE(meta.ok()) << meta.status().ToString();
  edit(*meta);
  fs::remove(p);
  EXPECT_TRUE(io::WriteYcbvMeta(p.string(), *meta).ok());
  return p.string();
}

// Rewrites meta.mat (uncompressed), then overwrites the bytes at `offset` in the dimensions
// sub-element of its first variable (intrinsic_matrix: miINT32 tag, 8 bytes, 3, 3) with `with`.
std::string PatchFirstDimensions(const fs::path& ycbv, size_t offset, const std::string& with) {
  const std::string p = EditMeta(ycbv, [](io::YcbvMeta&) {});
  std::string bytes = ReadText(p);
  const std::string dims("\x05\0\0\0\x08\0\0\0\x03\0\0\0\x03\0\0\0", 16);
  const size_t at = bytes.find(dims);
  EXPECT_NE(at, std::string::npos);
  bytes.replace(at + offset, with.size(), with);
  Replace(p, bytes);
  return p;
}

// The sugar box's OBJ (class 3) with `edit` applied to its text.
std::string EditObj(const fs::path& ycbv, const std::function<void(std::string&)>& edit) {
  const fs::path p = testing::OwnModel(ycbv, "004_sugar_box") / "textured_simple.obj";
  std::string text = ReadText(p);
  edit(text);
  Replace(p, text);
  return p.string();
}

// Replaces the first vertex line of an OBJ text by `line`.
std::function<void(std::string&)> FirstVertex(const std::string& line) {
  return [line](std::string& text) {
    const size_t at = text.find("\nv ") + 1;
    text.replace(at, text.find('\n', at) - at, line);
  };
}

// The sugar box's PLY (obj 3) of the BOP copy replaced by `text`.
std::string ReplacePly(const fs::path& bop, const std::string& text) {
  const fs::path p = bop / "models/obj_000003.ply";
  Replace(p, text);
  return p.string();
}

// An ascii PLY tetrahedron (mm) with one vertex line and one face line given.
std::string AsciiPly(const std::string& vertex0, const std::string& face0) {
  return "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 2\nproperty list uchar int vertex_indices\nend_header\n" +
         vertex0 + "\n100 0 0\n0 100 0\n0 0 100\n" + face0 + "\n3 0 1 3\n";
}

// A BOP JSON file of scene 49 edited as JSON.
std::string EditJson(const fs::path& p, const std::function<void(json&)>& edit) {
  json j = json::parse(ReadText(p));
  edit(j);
  Replace(p, j.dump());
  return p.string();
}

// The same JSON object with its key "1" written twice (the second copy first).
std::string DuplicateKeyOne(const fs::path& p) {
  const json j = json::parse(ReadText(p));
  Replace(p, "{\"1\": " + j["1"].dump() + ", " + j.dump().substr(1));
  return p.string();
}

fs::path SceneCamera(const fs::path& bop) { return bop / "test/000049/scene_camera.json"; }
fs::path SceneGt(const fs::path& bop) { return bop / "test/000049/scene_gt.json"; }

std::string EditResults(const fs::path& root, const std::function<void(std::string&)>& edit) {
  const fs::path p = root.parent_path() / "in.csv";
  std::string text = ReadText(p);
  edit(text);
  Replace(p, text);
  return p.string();
}

const Layout Y = Layout::kYcbv;
const Layout B = Layout::kBop;
const Command E = Command::kEstimate;
const Command V = Command::kEval;
const Command D = Command::kEvalWithBoxes;

// The detections file with `edit` applied to the first box.
std::function<std::string(const fs::path&)> EditFirstBox(const std::function<void(json&)>& edit) {
  return [edit](const fs::path& r) {
    json d = Scene49Detections();
    edit(d[0]);
    Replace(r.parent_path() / "dets.json", d.dump());
    return (r.parent_path() / "dets.json").string();
  };
}

// `p` replaced by a link to /dev/zero (endless).
std::string LinkToDevZero(const fs::path& p) {
  fs::remove(p);
  fs::create_symlink("/dev/zero", p);
  return p.string();
}

// A PNG whose IDAT chunk holds garbage (its CRC fixed, so only the image data is bad).
std::string GarbageInsideIdat(const fs::path& p) {
  std::string bytes = ReadText(fs::canonical(p));
  const size_t idat = bytes.find("IDAT");
  EXPECT_NE(idat, std::string::npos);
  const uint32_t length = (static_cast<uint8_t>(bytes[idat - 4]) << 24) | (static_cast<uint8_t>(bytes[idat - 3]) << 16) |
                          (static_cast<uint8_t>(bytes[idat - 2]) << 8) | static_cast<uint8_t>(bytes[idat - 1]);
  for (uint32_t i = length / 3; i < 2 * length / 3; ++i) bytes[idat + 4 + i] = static_cast<char>(i * 131 + 7);
  const uint32_t crc = Crc32(reinterpret_cast<const unsigned char*>(bytes.data()) + idat, 4 + length);
  for (int k = 0; k < 4; ++k) bytes[idat + 4 + length + k] = static_cast<char>((crc >> (24 - 8 * k)) & 0xff);
  Replace(p, bytes);
  return p.string();
}

const HostileCase kCases[] = {
    // ---- Images of a frame that disagree in size, and image headers that lie ----
    {"depth_larger_than_colour_and_label", Y, E, [](const fs::path& r) {
       WriteDepth(r / "data/0049/000001-depth.png", 1280, 960, 8000);
       return (r / "data/0049/000001-color.png").string(); }},
    {"depth_one_row_taller", Y, E, [](const fs::path& r) {
       WriteDepth(r / "data/0049/000001-depth.png", 640, 481, 8000);
       return (r / "data/0049/000001-color.png").string(); }},
    {"label_of_another_size", Y, V, [](const fs::path& r) {
       const fs::path p = r / "data/0049/000001-label.png";
       fs::remove(p);
       MaskImage m{320, 240, std::vector<uint8_t>(320 * 240, 3)};
       EXPECT_TRUE(io::WriteMaskPng(p.string(), m).ok());
       return p.string(); }},
    {"label_of_16_bits", Y, V, [](const fs::path& r) {
       WriteDepth(r / "data/0049/000001-label.png", 640, 480, 3);
       return (r / "data/0049/000001-label.png").string(); }},
    {"depth_header_claims_60000_square", Y, E, [](const fs::path& r) {
       WriteDepthClaimingSize(r / "data/0049/000001-depth.png", 60000, 60000);
       return (r / "data/0049/000001-depth.png").string(); }},
    {"depth_header_claims_10e6_square", B, E, [](const fs::path& r) {
       WriteDepthClaimingSize(r / "test/000049/depth/000001.png", 1000000, 1000000);
       return (r / "test/000049/depth/000001.png").string(); }},
    {"depth_header_claims_16000_square", B, E, [](const fs::path& r) {  // within the side limit, beyond the bytes
       WriteDepthClaimingSize(r / "test/000049/depth/000001.png", 16000, 16000);
       return (r / "test/000049/depth/000001.png").string(); }},
    // ---- meta.mat: intrinsics, depth scale, poses, sizes ----
    {"meta_fx_1e308", Y, E, [](const fs::path& r) { return EditMeta(r, [](io::YcbvMeta& m) { m.K(0, 0) = 1e308; }); }},
    {"meta_fx_1e_minus_300", Y, E, [](const fs::path& r) { return EditMeta(r, [](io::YcbvMeta& m) { m.K(0, 0) = 1e-300; }); }},
    {"meta_factor_depth_1e_minus_300", Y, E, [](const fs::path& r) {
       return EditMeta(r, [](io::YcbvMeta& m) { m.factor_depth = 1e-300; }); }},
    {"meta_factor_depth_1e300", Y, E, [](const fs::path& r) {
       return EditMeta(r, [](io::YcbvMeta& m) { m.factor_depth = 1e300; }); }},
    {"meta_rotation_all_zero", Y, V, [](const fs::path& r) {
       return EditMeta(r, [](io::YcbvMeta& m) { m.poses[0].R.setZero(); }); }},
    {"meta_rotation_scaled_3x", Y, V, [](const fs::path& r) {
       return EditMeta(r, [](io::YcbvMeta& m) { m.poses[0].R *= 3; }); }},
    {"meta_translation_1e308", Y, V, [](const fs::path& r) {
       return EditMeta(r, [](io::YcbvMeta& m) { m.poses[0].t.x() = 1e308; }); }},
    {"meta_intrinsics_claim_a_huge_size", Y, E, [](const fs::path& r) {
       return PatchFirstDimensions(r, 8, std::string("\xff\xff\xff\x7f\xff\xff\xff\x7f", 8)); }},
    // The dimensions tag of the first variable claims 4,227,858,432 bytes (a rank of 10^9).
    {"meta_dimensions_tag_claims_4_gb", Y, E, [](const fs::path& r) {
       return PatchFirstDimensions(r, 4, std::string("\0\0\0\xfc", 4)); }},
    // ---- Meshes and points ----
    {"obj_nan_vertex", Y, E, [](const fs::path& r) { return EditObj(r, FirstVertex("v nan 0 0")); }},
    {"obj_inf_vertex", Y, E, [](const fs::path& r) { return EditObj(r, FirstVertex("v 0 inf 0")); }},
    {"obj_1e20_vertex", Y, E, [](const fs::path& r) { return EditObj(r, FirstVertex("v 0 0 1e20")); }},
    {"obj_3e38_vertex", Y, E, [](const fs::path& r) { return EditObj(r, FirstVertex("v 3e38 0 0")); }},
    {"obj_vertex_with_letters", Y, E, [](const fs::path& r) { return EditObj(r, FirstVertex("v 0.01 abc 0.02")); }},
    {"obj_vertex_with_two_coordinates", Y, E, [](const fs::path& r) { return EditObj(r, FirstVertex("v 0.01 0.02")); }},
    {"obj_face_index_overflows_int", Y, E, [](const fs::path& r) {
       return EditObj(r, [](std::string& t) { t += "\nf 1 2 99999999999\n"; }); }},
    {"obj_truncated", Y, E, [](const fs::path& r) {
       return EditObj(r, [](std::string& t) {
         size_t at = 0;
         for (int i = 0; i < 100; ++i) at = t.find("\nv ", at + 1);
         t.resize(at + 8);
       }); }},
    {"obj_flipped_byte", Y, E, [](const fs::path& r) {
       return EditObj(r, [](std::string& t) {
         const size_t at = t.find("\nv ") + 4;  // a character of the first coordinate
         t[at] = static_cast<char>(t[at] ^ 0x40);
       }); }},
    {"points_xyz_1e308", Y, V, [](const fs::path& r) {
       const fs::path p = testing::OwnModel(r, "004_sugar_box") / "points.xyz";
       std::string text = ReadText(p);
       Replace(p, "1e308 0 0\n" + text);
       return p.string(); }},
    {"ply_nan_face_index", B, E, [](const fs::path& r) { return ReplacePly(r, AsciiPly("0 0 0", "3 0 nan 1")); }},
    {"ply_fractional_face_index", B, E, [](const fs::path& r) { return ReplacePly(r, AsciiPly("0 0 0", "3 0 1.5 2")); }},
    {"ply_list_count_1e308", B, E, [](const fs::path& r) { return ReplacePly(r, AsciiPly("0 0 0", "1e308 0 1 2")); }},
    {"ply_face_index_beyond_vertices", B, E, [](const fs::path& r) { return ReplacePly(r, AsciiPly("0 0 0", "3 0 1 7")); }},
    {"ply_nan_vertex", B, E, [](const fs::path& r) { return ReplacePly(r, AsciiPly("nan 0 0", "3 0 2 1")); }},
    {"ply_inf_vertex", B, E, [](const fs::path& r) { return ReplacePly(r, AsciiPly("0 inf 0", "3 0 2 1")); }},
    {"ply_1e20_vertex", B, E, [](const fs::path& r) { return ReplacePly(r, AsciiPly("0 0 1e20", "3 0 2 1")); }},
    {"ply_3e38_vertex", B, E, [](const fs::path& r) { return ReplacePly(r, AsciiPly("3e38 0 0", "3 0 2 1")); }},
    {"ply_truncated_binary", B, E, [](const fs::path& r) {
       const fs::path p = r / "models/obj_000003.ply";
       const std::string bytes = ReadText(fs::canonical(p));
       Replace(p, bytes.substr(0, bytes.size() * 2 / 3));
       return p.string(); }},
    // ---- BOP JSON ----
    {"scene_camera_fx_1e308", B, E, [](const fs::path& r) {
       return EditJson(SceneCamera(r), [](json& j) { j["1"]["cam_K"][0] = 1e308; }); }},
    {"scene_camera_fy_1e_minus_300", B, E, [](const fs::path& r) {
       return EditJson(SceneCamera(r), [](json& j) { j["1"]["cam_K"][4] = 1e-300; }); }},
    {"scene_camera_depth_scale_1e_minus_300", B, E, [](const fs::path& r) {
       return EditJson(SceneCamera(r), [](json& j) { j["1"]["depth_scale"] = 1e-300; }); }},
    {"scene_camera_depth_scale_1e300", B, E, [](const fs::path& r) {
       return EditJson(SceneCamera(r), [](json& j) { j["1"]["depth_scale"] = 1e300; }); }},
    {"scene_camera_duplicate_key", B, E, [](const fs::path& r) { return DuplicateKeyOne(SceneCamera(r)); }},
    {"scene_gt_duplicate_key", B, V, [](const fs::path& r) { return DuplicateKeyOne(SceneGt(r)); }},
    {"scene_gt_rotation_all_zero", B, V, [](const fs::path& r) {
       return EditJson(SceneGt(r), [](json& j) { j["1"][0]["cam_R_m2c"] = json::array({0, 0, 0, 0, 0, 0, 0, 0, 0}); }); }},
    {"scene_gt_rotation_scaled_3x", B, V, [](const fs::path& r) {
       return EditJson(SceneGt(r), [](json& j) {
         for (auto& v : j["1"][0]["cam_R_m2c"]) v = 3 * v.get<double>();
       }); }},
    {"scene_gt_translation_1e308", B, V, [](const fs::path& r) {
       return EditJson(SceneGt(r), [](json& j) { j["1"][0]["cam_t_m2c"][2] = 1e308; }); }},
    {"models_info_key_names_no_model", B, E, [](const fs::path& r) {
       return EditJson(r / "models/models_info.json", [](json& j) { j["99"] = j["1"]; }); }},
    {"models_info_06_beside_6", B, E, [](const fs::path& r) {
       return EditJson(r / "models/models_info.json", [](json& j) { j["06"] = j["6"]; }); }},
    // ---- Detections and results ----
    {"detection_box_of_1e9_pixels", B, E, [](const fs::path& r) {
       json d = Scene49Detections();
       d[0]["bbox"] = json::array({10, 10, 1e9, 1e9});
       Replace(r.parent_path() / "dets.json", d.dump());
       return (r.parent_path() / "dets.json").string(); }},
    {"results_obj_id_0", B, V, [](const fs::path& r) {
       return EditResults(r, [](std::string& t) {
         const size_t at = t.find("\n49,1,") + 6;
         t.replace(at, t.find(',', at) - at, "0");
       }); }},
    {"results_negative_scene_id", Y, V, [](const fs::path& r) {
       return EditResults(r, [](std::string& t) { t.replace(t.find("\n49,1,") + 1, 2, "-4"); }); }},
    {"detection_of_an_unknown_class", Y, E, EditFirstBox([](json& d) { d["category_id"] = 99; })},
    {"detection_box_outside_the_image", B, E, EditFirstBox([](json& d) { d["bbox"] = json::array({700, 10, 50, 50}); })},
    {"detection_image_not_in_the_dataset", Y, E, EditFirstBox([](json& d) { d["image_id"] = 777; })},
    {"detections_20000_in_one_image", B, E, [](const fs::path& r) {
       json d = json::array();
       for (int i = 0; i < 20000; ++i) d.push_back(Scene49Detections()[i % 2]);
       Replace(r.parent_path() / "dets.json", d.dump());
       return (r.parent_path() / "dets.json").string(); }},
    // ---- eval and its boxes: the same checks as estimate ----
    {"eval_detection_of_an_unknown_class", B, D, EditFirstBox([](json& d) { d["category_id"] = 99; })},
    {"eval_detection_box_outside_the_image", Y, D, EditFirstBox([](json& d) { d["bbox"] = json::array({10, 900, 5, 5}); })},
    {"eval_detection_image_not_in_the_dataset", B, D, EditFirstBox([](json& d) { d["scene_id"] = 50; })},
    // ---- Readers: values a sensor cannot produce, data that is not what it claims ----
    {"label_png_garbage_inside_idat", Y, V, [](const fs::path& r) {
       return GarbageInsideIdat(r / "data/0049/000001-label.png"); }},
    {"depth_png_garbage_inside_idat", B, E, [](const fs::path& r) {
       return GarbageInsideIdat(r / "test/000049/depth/000001.png"); }},
    {"depth_png_a_link_to_dev_zero", Y, E, [](const fs::path& r) {
       return LinkToDevZero(r / "data/0049/000001-depth.png"); }},
    {"meta_mat_a_link_to_dev_zero", Y, V, [](const fs::path& r) { return LinkToDevZero(Meta(r)); }},
    {"models_info_nested_100000_deep", B, E, [](const fs::path& r) {
       const fs::path p = r / "models/models_info.json";
       Replace(p, std::string(100000, '[') + std::string(100000, ']'));
       return p.string(); }},
    {"ply_element_of_2147483647_items_without_properties", B, E, [](const fs::path& r) {
       return ReplacePly(r, "ply\nformat binary_little_endian 1.0\nelement junk 2147483647\nelement vertex 3\n"
                            "property float x\nproperty float y\nproperty float z\nend_header\n" +
                            std::string(36, '\0')); }},
};

INSTANTIATE_TEST_SUITE_P(Cases, HostileInput, ::testing::ValuesIn(kCases),
                         [](const auto& info) { return info.param.name; });

// A frame whose depth is all zero or all saturated: each class gets one warning naming the
// depth image and the class, and no row; the run succeeds.
class NoValidDepth : public ::testing::TestWithParam<int> {};

TEST_P(NoValidDepth, WarnsPerClassAndWritesNoRow) {
  const fs::path bop = testing::MakeBopCopy("no_depth_" + std::to_string(GetParam()));
  const fs::path dir = bop.parent_path();
  const fs::path depth = bop / "test/000049/depth/000001.png";
  WriteDepth(depth, 640, 480, static_cast<uint16_t>(GetParam()));
  WriteText(dir / "dets.json", Scene49Detections().dump());
  const CliResult r = RunCli("estimate --dataset " + bop.string() + " --detections " + (dir / "dets.json").string() +
                                 " --out " + (dir / "res.csv").string() + " --iterations 2 --samples 16 --quiet",
                             dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // One warning line per class, naming the depth image, on stderr.
  const std::string& log = r.err;
  for (const char* cls : {"class 3 ", "class 6 "}) {
    const size_t at = log.find(cls);
    ASSERT_NE(at, std::string::npos) << log;
    const size_t begin = log.rfind('\n', at) == std::string::npos ? 0 : log.rfind('\n', at);
    EXPECT_NE(log.substr(begin, at - begin).find(depth.string()), std::string::npos) << log;
    EXPECT_EQ(log.find(cls, at + 1), std::string::npos) << log;
  }
  auto rows = ReadResultsCsv((dir / "res.csv").string());
  ASSERT_TRUE(rows.ok()) << rows.status().ToString();
  EXPECT_TRUE(rows->empty());
}

INSTANTIATE_TEST_SUITE_P(ZeroAndSaturated, NoValidDepth, ::testing::Values(0, 65535));

}  // namespace
}  // namespace mcpose
