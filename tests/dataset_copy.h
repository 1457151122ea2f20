// Copies of the real datasets in a temp folder, small files copied and large ones linked, so a
// test can replace one file at a time by a broken one.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "test_data.h"

namespace mcpose::testing {

inline void WriteText(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// Replaces the file (or link) at `p` by a file holding `text`.
inline void Replace(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::remove(p);
  WriteText(p, text);
}

// A BOP dataset in a temp folder: JSON files copied, images and models linked.
inline std::filesystem::path MakeBopCopy(const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path src = BopDir();
  const fs::path dst = TempDir(name) / "bop";
  fs::create_directories(dst / "models");
  fs::create_directories(dst / "test/000049/depth");
  fs::copy_file(src / "models/models_info.json", dst / "models/models_info.json");
  for (const auto& e : fs::directory_iterator(src / "models"))
    if (e.path().extension() == ".ply") fs::create_symlink(e.path(), dst / "models" / e.path().filename());
  for (const char* f : {"scene_camera.json", "scene_gt.json", "scene_gt_info.json"})
    fs::copy_file(src / "test/000049" / f, dst / "test/000049" / f);
  for (const auto& e : fs::directory_iterator(src / "test/000049/depth"))
    fs::create_symlink(e.path(), dst / "test/000049/depth" / e.path().filename());
  fs::create_directory_symlink(src / "test/000049/mask_visib", dst / "test/000049/mask_visib");
  for (const char* f : {"camera.json"}) fs::copy_file(src / f, dst / f);
  return dst;
}

// A YCB-Video dataset in a temp folder holding frame 0049/000001 only: classes.txt and the
// frame's meta.mat copied, its images and the model folders linked. OwnModel turns one model's
// link into a folder of copies, so its files can be replaced.
inline std::filesystem::path MakeYcbvCopy(const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path src = YcbvDir();
  const fs::path dst = TempDir(name) / "ycbv";
  fs::create_directories(dst / "models");
  fs::create_directories(dst / "data/0049");
  fs::copy_file(src / "classes.txt", dst / "classes.txt");
  for (const auto& e : fs::directory_iterator(src / "models"))
    if (e.is_directory()) fs::create_directory_symlink(e.path(), dst / "models" / e.path().filename());
  fs::copy_file(src / "data/0049/000001-meta.mat", dst / "data/0049/000001-meta.mat");
  for (const char* f : {"000001-color.png", "000001-depth.png", "000001-label.png", "000001-box.txt"})
    fs::create_symlink(src / "data/0049" / f, dst / "data/0049" / f);
  return dst;
}

inline std::filesystem::path OwnModel(const std::filesystem::path& ycbv, const std::string& model) {
  namespace fs = std::filesystem;
  const fs::path dir = ycbv / "models" / model;
  const fs::path src = fs::read_symlink(dir);
  fs::remove(dir);
  fs::create_directory(dir);
  for (const auto& e : fs::directory_iterator(src)) fs::copy_file(e.path(), dir / e.path().filename());
  return dir;
}

}  // namespace mcpose::testing
