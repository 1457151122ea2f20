// The workload file `mcpose-tools hw-workload` writes (format in docs/hardware.md): per object
// its box's depth bounds, its mesh in the core's formats and its samples with the C++ model's
// counts. Read by the testbenches.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "hw/raster_core.h"
#include "hw/weight_merger.h"

namespace mcpose::hw::sim {

// The core's vertex RAM as synthesized (VW = 11).
inline constexpr int kVertexIndexBits = 11;
inline constexpr size_t kMaxVertices = size_t{1} << kVertexIndexBits;

struct WorkloadSample {
  Pose pose;
  Counts counts;  // the C++ model's
};

struct WorkloadObject {
  int obj_id = 0;
  std::string name;
  Camera camera;
  bool cull = true;
  WeightCoefficients weight;
  int32_t eps = 0;              // depth units
  std::vector<int32_t> depth;   // the box's observed depth, depth units (0: none)
  std::vector<DepthBounds> bounds;  // hw::InlierBounds of each
  std::vector<ModelVertex> model;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<WorkloadSample> samples;
};

[[noreturn]] inline void WorkloadError(const std::string& path, const std::string& what) {
  std::fprintf(stderr, "%s: %s\n", path.c_str(), what.c_str());
  std::exit(2);
}

// Every object of the file; exits with a message naming the file on a malformed one.
inline std::vector<WorkloadObject> ReadWorkload(const std::string& path, size_t max_box_words) {
  std::ifstream in(path);
  if (!in) WorkloadError(path, "cannot open");
  std::string line, word, key;
  std::getline(in, line);
  if (line.rfind("# mcpose hardware workload v3", 0) != 0)
    WorkloadError(path, "not a workload file (mcpose-tools hw-workload writes them)");
  std::vector<WorkloadObject> objects;
  while (in >> word && word != "end") {
    if (word != "object") WorkloadError(path, "expected 'object', got '" + word + "'");
    WorkloadObject o;
    int scene = 0, image = 0, cull = 1;
    size_t n = 0;
    in >> o.obj_id >> o.name >> key >> scene >> image;
    Camera& c = o.camera;
    in >> key >> c.fx >> c.fy >> c.cx >> c.cy >> c.z_near >> c.width >> c.height >> cull;
    o.cull = cull != 0;
    int occlusion_aware = 0;
    in >> key >> o.weight.a >> o.weight.b >> o.weight.c >> o.weight.score >> occlusion_aware;
    if (!in || key != "weight") WorkloadError(path, "object " + std::to_string(o.obj_id) + ": bad weight line");
    o.weight.occlusion_aware = occlusion_aware != 0;
    in >> key >> n >> o.eps;
    if (!in || key != "depth" || n != static_cast<size_t>(c.width) * static_cast<size_t>(c.height) ||
        n > max_box_words || o.eps < 1)
      WorkloadError(path, "object " + std::to_string(o.obj_id) + ": bad camera or depth");
    o.depth.resize(n);
    for (int32_t& d : o.depth) in >> d;
    for (int32_t d : o.depth) o.bounds.push_back(InlierBounds(d, o.eps));
    in >> key >> n;
    if (!in || n > kMaxVertices)
      WorkloadError(path, "object " + std::to_string(o.obj_id) + ": more vertices than the core's vertex RAM (" +
                              std::to_string(kMaxVertices) + ")");
    o.model.resize(n);
    for (ModelVertex& v : o.model) {
      int x = 0, y = 0, z = 0;
      in >> x >> y >> z;
      v = {static_cast<int16_t>(x), static_cast<int16_t>(y), static_cast<int16_t>(z)};
    }
    in >> key >> n;
    o.triangles.resize(n);
    for (auto& t : o.triangles) {
      in >> t[0] >> t[1] >> t[2];
      if (t[0] >= o.model.size() || t[1] >= o.model.size() || t[2] >= o.model.size())
        WorkloadError(path, "object " + std::to_string(o.obj_id) + ": triangle with a vertex out of range");
    }
    in >> key >> n;
    if (!in || key != "samples") WorkloadError(path, "object " + std::to_string(o.obj_id) + ": bad mesh");
    o.samples.resize(n);
    for (WorkloadSample& s : o.samples) {
      for (int32_t& r : s.pose.R) in >> r;
      for (int32_t& t : s.pose.t) in >> t;
      in >> s.counts.inliers >> s.counts.rendered >> s.counts.occluded;
    }
    if (!in) WorkloadError(path, "object " + std::to_string(o.obj_id) + ": samples cut short");
    objects.push_back(std::move(o));
  }
  if (word != "end") WorkloadError(path, "no 'end': the file is cut short");
  return objects;
}

}  // namespace mcpose::hw::sim
