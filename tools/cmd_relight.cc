// mcpose-tools relight: a YCB-Video dataset whose real colour images are photometrically
// transformed (synth/photometric.h), everything else linked to the original; the input of
// scripts/accuracy_photometric.sh.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/common.h"
#include "mcpose/io_util.h"
#include "mcpose/png_io.h"
#include "mcpose/photometric.h"
#include "tools.h"

namespace mcpose::tools {

namespace {

namespace fs = std::filesystem;

struct RelightArgs {
  std::string dataset, out, transform;
  uint64_t seed = 0;
};

Status Fail(const fs::path& path, const std::string& what, const std::error_code& ec) {
  return Internal(path.string() + ": " + what + " (" + ec.message() + ")");
}

// Fills `dst` (an empty folder) with the dataset: every top-level entry but data/ linked, data/
// rebuilt with each *-color.png transformed and the frame's other files linked.
Status WriteRelit(const fs::path& src, const fs::path& dst, const synth::PhotometricTransform& t, uint64_t seed) {
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(src, ec)) {
    if (e.path().filename() == "data") continue;
    fs::create_symlink(e.path(), dst / e.path().filename(), ec);
    if (ec) return Fail(dst / e.path().filename(), "cannot create link", ec);
  }
  if (ec) return Fail(src, "cannot list folder", ec);
  std::vector<fs::path> videos;
  for (const fs::directory_entry& e : fs::directory_iterator(src / "data", ec))
    if (e.is_directory()) videos.push_back(e.path());
  if (ec) return Fail(src / "data", "cannot list folder", ec);
  std::sort(videos.begin(), videos.end());
  int frames = 0;
  for (const fs::path& video : videos) {
    const fs::path out_video = dst / "data" / video.filename();
    fs::create_directories(out_video, ec);
    if (ec) return Fail(out_video, "cannot create folder", ec);
    std::vector<fs::path> files;
    for (const fs::directory_entry& e : fs::directory_iterator(video, ec)) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
      const std::string name = f.filename().string();
      const std::string suffix = "-color.png";
      if (name.size() <= suffix.size() || name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
        fs::create_symlink(f, out_video / name, ec);
        if (ec) return Fail(out_video / name, "cannot create link", ec);
        continue;
      }
      MCPOSE_ASSIGN_OR_RETURN(ColourImage image, io::ReadColourPng(f.string()));
      // Each frame its own noise, the same for a seed whatever else the dataset holds.
      const uint64_t frame_seed = synth::PhotometricFrameSeed(seed, video.filename().string() + "/" + name);
      MCPOSE_ASSIGN_OR_RETURN(ColourImage relit, synth::ApplyPhotometric(t, image, frame_seed));
      MCPOSE_RETURN_IF_ERROR(io::WriteColourPng((out_video / name).string(), relit));
      std::fprintf(stderr, "\rframes %d", ++frames);
    }
  }
  std::fprintf(stderr, "\rframes %d relit (%s)\n", frames, t.ToString().c_str());
  if (frames == 0) return InvalidArgument(src.string() + ": no data/<video>/*-color.png to relight");
  return Status::Ok();
}

Status RunRelight(const RelightArgs& a) {
  MCPOSE_ASSIGN_OR_RETURN(synth::PhotometricTransform t, synth::ParsePhotometricTransform(a.transform));
  const fs::path src = fs::absolute(a.dataset).lexically_normal();
  std::error_code ec;
  if (!fs::is_directory(src / "data", ec) || !fs::is_regular_file(src / "classes.txt", ec))
    return InvalidArgument(a.dataset + ": not a YCB-Video dataset (no data/ and classes.txt); relight reads that layout");
  const fs::path out = fs::absolute(a.out).lexically_normal();
  if (fs::exists(fs::symlink_status(out, ec)))
    return InvalidArgument(a.out + ": already exists; relight writes a new folder");
  const fs::path parent = out.parent_path();
  if (!fs::is_directory(parent, ec)) return NotFound(a.out + ": folder " + parent.string() + " does not exist");
  // Written beside the target under a fresh name, renamed into place when whole.
  MCPOSE_ASSIGN_OR_RETURN(const fs::path tmp, io::CreateFolderBeside(out.string(), ".tmp-"));
  Status status = WriteRelit(src, tmp, t, a.seed);
  if (status.ok()) {
    fs::rename(tmp, out, ec);
    if (ec) status = Fail(out, "cannot rename " + tmp.string() + " to it", ec);
  }
  if (!status.ok()) fs::remove_all(tmp, ec);
  return status;
}

}  // namespace

void AddRelightCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<RelightArgs>();
  CLI::App* cmd = app.add_subcommand(
      "relight",
      "A copy of a YCB-Video dataset whose real colour images are photometrically transformed (depth, labels, "
      "poses and models linked, untouched): the input of scripts/accuracy_photometric.sh");
  cmd->add_option("--dataset", args->dataset, "YCB-Video dataset root (native layout)")->required();
  cmd->add_option("--out", args->out, "Folder to write (must not exist); written whole or not at all")->required();
  cmd->add_option("--transform", args->transform,
                  "none, exposure:G (linear light times G), gamma:G, white-balance:R,G,B (linear gains), "
                  "saturation:F, clip:L (values above L * 255 clipped), jpeg:Q (quality), noise:S (levels)")
      ->required();
  cmd->add_option("--seed", args->seed, "Seed of the noise")->check(SeedCheck())->capture_default_str();
  cmd->callback([args, status] { *status = RunRelight(*args); });
}

}  // namespace mcpose::tools
