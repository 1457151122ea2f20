// libFuzzer targets, one per file reader. This file is compiled once; each executable adds a
// one-line file defining kFuzzTargetName, one entry of kTargets (see fuzz/CMakeLists.txt). A target writes the
// input where its reader expects a file and reads it; any status is fine, a crash, leak or
// sanitizer report is a bug. Seed corpora come from the data folder (scripts/fuzz.sh).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <unistd.h>

#include <spdlog/spdlog.h>

#include "io/bop_dataset.h"
#include "mcpose/io_util.h"
#include "io/jpeg_io.h"
#include "io/obj_io.h"
#include "io/ply_io.h"
#include "mcpose/png_io.h"
#include "io/ycbv_dataset.h"
#include "mcpose/bop19.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/results.h"

namespace mcpose::fuzz {

extern const char kFuzzTargetName[];  // the executable's target (fuzz/CMakeLists.txt writes it)

namespace {

namespace fs = std::filesystem;

// A folder of this process for the files the readers open.
const fs::path& WorkDir() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("mcpose_fuzz_" + std::to_string(getpid()));
    fs::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(WorkDir(), ec);
    });
    return d;
  }();
  return dir;
}

void Write(const fs::path& path, std::string_view bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) std::abort();
  std::fclose(f);
}

std::string InputFile(std::string_view bytes, const char* name) {
  const fs::path path = WorkDir() / name;
  Write(path, bytes);
  return path.string();
}

// A minimal BOP dataset (one object, one 4 x 4 frame) with every file valid; a BOP target
// replaces one of its files with the input and opens the dataset and its frames.
const fs::path& BopRoot() {
  static const fs::path root = [] {
    const fs::path r = WorkDir() / "bop";
    fs::create_directories(r / "models");
    fs::create_directories(r / "test/000001/depth");
    Write(r / "models/models_info.json", R"({"1": {"diameter": 100.0}})");
    Mesh tetra;
    tetra.vertices_m = {{0, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0}, {0, 0, 0.1f}};
    tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    if (!io::WritePlyMesh((r / "models/obj_000001.ply").string(), tetra, 1000.0).ok()) std::abort();
    Write(r / "camera.json", R"({"width": 4, "height": 4, "depth_scale": 0.1})");
    Write(r / "test/000001/scene_camera.json", R"({"1": {"cam_K": [500, 0, 2, 0, 500, 2, 0, 0, 1], "depth_scale": 0.1}})");
    Write(r / "test/000001/scene_gt.json",
          R"({"1": [{"obj_id": 1, "cam_R_m2c": [1, 0, 0, 0, 1, 0, 0, 0, 1], "cam_t_m2c": [0, 0, 800]}]})");
    io::Gray16Image depth{4, 4, std::vector<uint16_t>(16, 8000)};
    if (!io::WriteGray16Png((r / "test/000001/depth/000001.png").string(), depth).ok()) std::abort();
    return r;
  }();
  return root;
}

// Replaces `relative` in the BOP dataset with the input, reads what it holds, restores it.
void FuzzBopFile(std::string_view bytes, const char* relative) {
  const fs::path file = BopRoot() / relative;
  const fs::path saved = file.string() + ".valid";
  if (!fs::exists(saved)) fs::copy_file(file, saved);
  Write(file, bytes);
  StatusOr<std::unique_ptr<Dataset>> dataset = io::OpenBopDataset(BopRoot().string(), "test", "");
  if (dataset.ok()) {
    for (const FrameKey& key : (*dataset)->Frames()) {
      StatusOr<Frame> frame = (*dataset)->LoadFrame(key);
      if (frame.ok())
        for (const GtInstance& gt : frame->gt) (void)(*dataset)->LoadEvalPoints(gt.obj_id);
    }
  }
  fs::copy_file(saved, file, fs::copy_options::overwrite_existing);
}

// An OBJ that names the material file "m.mtl"; the MTL target writes the input there.
constexpr std::string_view kObjWithMaterial =
    "mtllib m.mtl\nv 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n";

struct Target {
  const char* name;
  void (*run)(std::string_view bytes);
};

constexpr Target kTargets[] = {
    {"png_depth", [](std::string_view b) { (void)io::ReadDepthPng(InputFile(b, "d.png"), 1e-4); }},
    {"png_colour", [](std::string_view b) { (void)io::ReadColourPng(InputFile(b, "c.png")); }},
    {"png_label", [](std::string_view b) { (void)io::ReadMaskPng(InputFile(b, "l.png")); }},
    {"jpeg", [](std::string_view b) { (void)io::ReadColourImage(InputFile(b, "c.jpg")); }},
    {"meta_mat", [](std::string_view b) { (void)io::ReadYcbvMeta(InputFile(b, "meta.mat")); }},
    {"obj", [](std::string_view b) { (void)io::ReadObjMesh(InputFile(b, "m.obj")); }},
    {"mtl",
     [](std::string_view b) {
       InputFile(b, "m.mtl");
       (void)io::ReadObjMesh(InputFile(kObjWithMaterial, "with_material.obj"));
     }},
    {"ply", [](std::string_view b) { (void)io::ReadPlyMesh(InputFile(b, "m.ply"), 1000.0); }},
    {"points_xyz", [](std::string_view b) { (void)io::ReadXyzPoints(InputFile(b, "points.xyz")); }},
    {"bop_models_info", [](std::string_view b) { FuzzBopFile(b, "models/models_info.json"); }},
    {"bop_camera", [](std::string_view b) { FuzzBopFile(b, "camera.json"); }},
    {"bop_scene_camera", [](std::string_view b) { FuzzBopFile(b, "test/000001/scene_camera.json"); }},
    {"bop_scene_gt", [](std::string_view b) { FuzzBopFile(b, "test/000001/scene_gt.json"); }},
    {"detections_json", [](std::string_view b) { (void)ReadDetectionsJson(InputFile(b, "dets.json")); }},
    {"results_csv", [](std::string_view b) { (void)ReadResultsCsv(InputFile(b, "res.csv")); }},
    {"bop19_models_info", [](std::string_view b) { (void)ReadModelsInfo(InputFile(b, "models_info.json")); }},
    {"bop19_targets", [](std::string_view b) { (void)ReadBop19Targets(InputFile(b, "targets.json")); }},
};

const Target& Selected() {
  for (const Target& t : kTargets)
    if (std::string_view(t.name) == kFuzzTargetName) return t;
  std::abort();
}

}  // namespace
}  // namespace mcpose::fuzz

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spdlog::set_level(spdlog::level::off);  // readers' warnings would flood the fuzzer's output
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const mcpose::fuzz::Target& target = mcpose::fuzz::Selected();
  target.run(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
