#include "mcpose/capture.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <optional>
#include <sstream>

#include "mcpose/io_util.h"
#include "io/ply_io.h"
#include "mcpose/png_io.h"
#include "render/raster.h"

namespace mcpose::appearance {

namespace fs = std::filesystem;

namespace {

// The surface points colour is captured at: texel centres of the texture layout, or vertices.
struct SurfacePoints {
  std::vector<Eigen::Vector3f> p, n;  // model frame; unit normals
  std::vector<int32_t> texel;         // texel index of each point (texture mode), else empty
};

SurfacePoints TexelPoints(const Mesh& mesh, int size) {
  SurfacePoints s;
  std::vector<char> taken(static_cast<size_t>(size) * size, 0);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& uv = mesh.appearance.triangle_uv[t];
    if (!uv[0].allFinite() || !uv[1].allFinite() || !uv[2].allFinite()) continue;
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3f A = mesh.vertices_m[tri[0]], B = mesh.vertices_m[tri[1]], C = mesh.vertices_m[tri[2]];
    const Eigen::Vector3f normal = (B - A).cross(C - A);
    if (!(normal.squaredNorm() > 0)) continue;
    // Texel coordinates: texel (i, j) is centred on u = (i + 0.5) / size, v = 1 - (j + 0.5) / size.
    Eigen::Vector2d q[3];
    for (int k = 0; k < 3; ++k) q[k] = {uv[k].x() * size - 0.5, (1.0 - uv[k].y()) * size - 0.5};
    const double area = (q[1] - q[0]).x() * (q[2] - q[0]).y() - (q[1] - q[0]).y() * (q[2] - q[0]).x();
    if (std::fabs(area) < 1e-12) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({q[0].x(), q[1].x(), q[2].x()}))));
    const int x1 = std::min(size - 1, static_cast<int>(std::ceil(std::max({q[0].x(), q[1].x(), q[2].x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({q[0].y(), q[1].y(), q[2].y()}))));
    const int y1 = std::min(size - 1, static_cast<int>(std::ceil(std::max({q[0].y(), q[1].y(), q[2].y()}))));
    for (int j = y0; j <= y1; ++j) {
      for (int i = x0; i <= x1; ++i) {
        // Barycentric coordinates of the texel centre; within half a texel of the triangle counts
        // (bilinear lookups read a triangle's border texels too), the point clamped onto it.
        double b[3];
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector2d& e0 = q[(k + 1) % 3];
          const Eigen::Vector2d& e1 = q[(k + 2) % 3];
          b[k] = ((e1 - e0).x() * (j - e0.y()) - (e1 - e0).y() * (i - e0.x())) / area;
        }
        const double tolerance = 0.5 / std::max(1.0, std::sqrt(std::fabs(area)));
        if (b[0] < -tolerance || b[1] < -tolerance || b[2] < -tolerance) continue;
        const size_t texel = static_cast<size_t>(j) * size + i;
        if (taken[texel]) continue;
        taken[texel] = 1;
        double sum = 0;
        for (double& v : b) v = std::max(0.0, v), sum += v;
        const Eigen::Vector3f p = static_cast<float>(b[0] / sum) * A + static_cast<float>(b[1] / sum) * B +
                                  static_cast<float>(b[2] / sum) * C;
        s.p.push_back(p);
        s.n.push_back(normal.normalized());
        s.texel.push_back(static_cast<int32_t>(texel));
      }
    }
  }
  return s;
}

SurfacePoints VertexPoints(const Mesh& mesh) {
  SurfacePoints s;
  s.p = mesh.vertices_m;
  s.n.assign(mesh.vertices_m.size(), Eigen::Vector3f::Zero());
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3f area_normal =
        (mesh.vertices_m[t[1]] - mesh.vertices_m[t[0]]).cross(mesh.vertices_m[t[2]] - mesh.vertices_m[t[0]]);
    for (uint32_t v : t) s.n[v] += area_normal;
  }
  for (Eigen::Vector3f& n : s.n) n = n.squaredNorm() > 0 ? n.normalized() : Eigen::Vector3f::Zero();
  return s;
}

struct Sample {
  int32_t point;
  uint8_t rgb[3];
};

// The mesh's z-buffer over the whole image at the view's pose.
std::vector<float> RenderView(const Mesh& mesh, const PosedView& v) {
  render::RasterParams params;
  params.fx = static_cast<float>(v.K.fx), params.fy = static_cast<float>(v.K.fy);
  params.cx = static_cast<float>(v.K.cx), params.cy = static_cast<float>(v.K.cy);
  params.box = render::PixelRect{0, 0, v.K.width, v.K.height};
  params.cull_backfaces = true;
  std::vector<render::ScreenVertex> sv(mesh.vertices_m.size());
  render::ProjectVertices(mesh.vertices_m, v.T_cam_obj.R.cast<float>(), v.T_cam_obj.t.cast<float>(), params, sv);
  std::vector<float> z(static_cast<size_t>(params.box.area()), INFINITY);
  render::RasterizeDepthReference(sv, mesh.triangles, params, z.data(), nullptr);
  return z;
}

// Fills unknown texels next to known ones with their known neighbours' mean, `rounds` times:
// bilinear lookups on a triangle's border then read no unknown texel across the seam.
void PadTexture(ColourImage* t, int rounds) {
  for (int r = 0; r < rounds; ++r) {
    const ColourImage src = *t;
    for (int y = 0; y < t->height; ++y)
      for (int x = 0; x < t->width; ++x) {
        if (src.at(x, y)[3] != 0) continue;
        int sum[3] = {0, 0, 0}, n = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= t->width || yy >= t->height || src.at(xx, yy)[3] == 0) continue;
            for (int c = 0; c < 3; ++c) sum[c] += src.at(xx, yy)[c];
            ++n;
          }
        if (n == 0) continue;
        uint8_t* q = t->rgba.data() + 4 * (static_cast<size_t>(y) * t->width + x);
        for (int c = 0; c < 3; ++c) q[c] = static_cast<uint8_t>((sum[c] + n / 2) / n);
        q[3] = 255;
      }
  }
}

}  // namespace

bool CaptureOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (!(depth_agreement_m > 0 && std::isfinite(depth_agreement_m))) return fail("depth_agreement_m must be > 0");
  if (!(visibility_m > 0 && std::isfinite(visibility_m))) return fail("visibility_m must be > 0");
  if (!(max_view_angle_deg > 0 && max_view_angle_deg < 90)) return fail("max_view_angle_deg must lie in (0, 90)");
  if (texture_size < 16 || texture_size > 4096) return fail("texture_size must lie in [16, 4096]");
  return true;
}

StatusOr<MeshAppearance> CaptureFromViews(const Mesh& mesh, std::span<const PosedView> views,
                                          const CaptureOptions& options, CaptureStats* stats) {
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("invalid capture options: " + error);
  MCPOSE_RETURN_IF_ERROR(mesh.Validate("mesh"));
  for (size_t i = 0; i < views.size(); ++i) {
    const PosedView& v = views[i];
    const std::string where = "view " + std::to_string(i) + ": ";
    if (!v.K.IsValid(&error)) return InvalidArgument(where + error);
    const int w = v.K.width, h = v.K.height;
    if (!v.depth || !v.colour || !v.visible || v.depth->width != w || v.depth->height != h || v.colour->width != w ||
        v.colour->height != h || v.visible->width != w || v.visible->height != h)
      return InvalidArgument(where + "depth, colour and mask must all be " + std::to_string(w) + "x" + std::to_string(h));
  }
  const bool texture_mode = !mesh.appearance.triangle_uv.empty();
  const SurfacePoints points = texture_mode ? TexelPoints(mesh, options.texture_size) : VertexPoints(mesh);
  CaptureStats local;
  local.points = static_cast<int>(points.p.size());
  const double min_cos = std::cos(options.max_view_angle_deg * M_PI / 180);

  // ---- Colour samples of every point from every view that sees it ------------------------
  std::vector<Sample> samples;
  for (const PosedView& v : views) {
    const std::vector<float> zbuf = RenderView(mesh, v);
    const Eigen::Matrix3f R = v.T_cam_obj.R.cast<float>();
    const Eigen::Vector3f t = v.T_cam_obj.t.cast<float>();
    const size_t before = samples.size();
    for (size_t i = 0; i < points.p.size(); ++i) {
      const Eigen::Vector3f c = R * points.p[i] + t;
      if (!(c.z() > 0.05f)) continue;
      // Facing the camera, not too grazing.
      const float cos_view = -(R * points.n[i]).dot(c) / c.norm();
      if (!(cos_view > min_cos)) continue;
      const long x = std::lround(v.K.fx * c.x() / c.z() + v.K.cx), y = std::lround(v.K.fy * c.y() / c.z() + v.K.cy);
      if (x < 0 || y < 0 || x >= v.K.width || y >= v.K.height) continue;
      const size_t px = static_cast<size_t>(y) * v.K.width + static_cast<size_t>(x);
      // Not hidden by the object itself, nor by others; the sensor saw this surface there.
      if (!(std::fabs(zbuf[px] - c.z()) < options.visibility_m)) continue;
      if (v.visible->values[px] == 0) continue;
      const float zo = v.depth->depth_m[px];
      if (!(zo > 0 && std::fabs(zo - c.z()) < options.depth_agreement_m)) continue;
      const uint8_t* rgba = v.colour->rgba.data() + 4 * px;
      if (rgba[3] == 0) continue;
      samples.push_back({static_cast<int32_t>(i), {rgba[0], rgba[1], rgba[2]}});
    }
    if (samples.size() > before) ++local.views;
  }
  local.samples = static_cast<int64_t>(samples.size());

  // ---- Per point, the per-channel median of its samples -----------------------------------
  std::stable_sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) { return a.point < b.point; });
  std::vector<Rgba8> colour(points.p.size());
  std::vector<uint8_t> channel;
  for (size_t a = 0; a < samples.size();) {
    size_t b = a;
    while (b < samples.size() && samples[b].point == samples[a].point) ++b;
    Rgba8& out = colour[static_cast<size_t>(samples[a].point)];
    for (int c = 0; c < 3; ++c) {
      channel.clear();
      for (size_t k = a; k < b; ++k) channel.push_back(samples[k].rgb[c]);
      std::nth_element(channel.begin(), channel.begin() + channel.size() / 2, channel.end());
      (c == 0 ? out.r : c == 1 ? out.g : out.b) = channel[channel.size() / 2];
    }
    out.a = 255;
    ++local.known;
    a = b;
  }
  if (stats) *stats = local;

  // ---- Into the mesh's texture layout, or onto its vertices --------------------------------
  MeshAppearance out;
  if (!texture_mode) {
    out.vertex_colours = std::move(colour);
    return out;
  }
  auto texture = std::make_shared<ColourImage>();
  texture->width = texture->height = options.texture_size;
  texture->rgba.assign(4 * static_cast<size_t>(options.texture_size) * options.texture_size, 0);
  for (size_t i = 0; i < points.p.size(); ++i) {
    const Rgba8& c = colour[i];
    uint8_t* q = texture->rgba.data() + 4 * static_cast<size_t>(points.texel[i]);
    q[0] = c.r, q[1] = c.g, q[2] = c.b, q[3] = c.a;
  }
  PadTexture(texture.get(), 2);
  out.triangle_uv = mesh.appearance.triangle_uv;
  out.texture = std::move(texture);
  return out;
}

namespace {

// The YCB-Video OBJ text with its material lines replaced by `mtllib <mtl>` at the top and
// `usemtl captured` before the first face: the same geometry and texture layout, the captured
// texture as its material.
std::string ObjWithCapturedMaterial(const std::string& text, const std::string& mtl) {
  std::ostringstream out;
  out << "mtllib " << mtl << "\n";
  bool used = false;
  for (std::string_view line : io::SplitLines(text)) {
    const std::string_view trimmed = io::Trim(line);
    if (trimmed.starts_with("mtllib") || trimmed.starts_with("usemtl")) continue;
    if (!used && trimmed.starts_with("f ")) out << "usemtl captured\n", used = true;
    out << line << "\n";
  }
  return out.str();
}

// The OBJ without its material lines: the model's geometry with no colour.
std::string ObjWithoutMaterial(const std::string& text) {
  std::ostringstream out;
  for (std::string_view line : io::SplitLines(text)) {
    const std::string_view trimmed = io::Trim(line);
    if (!trimmed.starts_with("mtllib") && !trimmed.starts_with("usemtl")) out << line << "\n";
  }
  return out.str();
}

// Through io::WriteFileAtomic, as every output: no half-copied file under the final name.
Status CopyFile(const std::string& from, const std::string& to) {
  MCPOSE_ASSIGN_OR_RETURN(const std::string contents, io::ReadFileToString(from));
  return io::WriteFileAtomic(to, contents);
}

}  // namespace

StatusOr<std::vector<ObjectCapture>> CaptureDataset(const Dataset& dataset, std::span<const FrameKey> frames,
                                                    const CaptureOptions& options, bool replace_own_colour,
                                                    const std::string& out_dir) {
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("invalid capture options: " + error);
  std::error_code ec;
  if (fs::exists(out_dir, ec) && fs::equivalent(out_dir, dataset.models_dir(), ec))
    return InvalidArgument(out_dir + ": is the dataset's own models folder; write the captured models elsewhere");

  // ---- Read every frame first: nothing is written unless all of it could be read ----------
  struct LoadedFrame {
    Frame frame;
    ColourImage colour;
    std::vector<std::pair<int, MaskImage>> masks;  // (obj_id, visible mask) per instance
  };
  std::vector<LoadedFrame> loaded;
  loaded.reserve(frames.size());
  for (const FrameKey& key : frames) {
    LoadedFrame f;
    MCPOSE_ASSIGN_OR_RETURN(f.frame, dataset.LoadFrame(key));
    MCPOSE_ASSIGN_OR_RETURN(f.colour, dataset.LoadColour(f.frame));
    for (const GtInstance& gt : f.frame.gt) {
      MCPOSE_ASSIGN_OR_RETURN(MaskImage mask, dataset.LoadVisibleMask(key, gt));
      if (mask.width != f.frame.depth.width || mask.height != f.frame.depth.height)
        return InvalidArgument(dataset.FrameName(key) + ": the visible mask of obj_id " + std::to_string(gt.obj_id) +
                               " is " + std::to_string(mask.width) + "x" + std::to_string(mask.height) +
                               ", not the depth image's size");
      f.masks.emplace_back(gt.obj_id, std::move(mask));
    }
    loaded.push_back(std::move(f));
  }

  // ---- Capture each object ---------------------------------------------------------------
  std::vector<ObjectCapture> report;
  std::map<int, Mesh> meshes;
  std::set<int> own_colour;  // objects whose model has colour of its own
  for (int obj_id : dataset.ObjectIds()) {
    ObjectCapture oc;
    oc.obj_id = obj_id;
    oc.name = dataset.ObjectName(obj_id);
    MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, dataset.LoadMesh(obj_id));
    const bool own = !mesh.appearance.empty();
    if (own) own_colour.insert(obj_id);
    if (own && !replace_own_colour) {
      oc.source = ObjectCapture::Source::kOwnColour;
    } else {
      std::vector<PosedView> views;
      for (const LoadedFrame& f : loaded)
        for (size_t g = 0; g < f.frame.gt.size(); ++g)
          if (f.frame.gt[g].obj_id == obj_id)
            views.push_back({f.frame.K, &f.frame.depth, &f.colour, &f.masks[g].second, f.frame.gt[g].T_cam_obj});
      if (!views.empty()) {
        MCPOSE_ASSIGN_OR_RETURN(MeshAppearance captured, CaptureFromViews(mesh, views, options, &oc.stats));
        if (oc.stats.known > 0) {
          mesh.appearance = std::move(captured);
          oc.source = ObjectCapture::Source::kCaptured;
        }
      }
      // Replaced, but no frame showed it: its own colour is dropped all the same, so that no
      // appearance but the listed frames' reaches the models folder.
      if (oc.source == ObjectCapture::Source::kNone) mesh.appearance = {};
    }
    meshes.emplace(obj_id, std::move(mesh));
    report.push_back(oc);
  }

  // ---- Write the models folder -----------------------------------------------------------
  fs::create_directories(out_dir, ec);
  if (ec) return NotFound(out_dir + ": cannot create folder (" + ec.message() + ")");
  const bool ycbv = dataset.format() == DatasetFormat::kYcbv;
  if (!ycbv) MCPOSE_RETURN_IF_ERROR(CopyFile(dataset.models_dir() + "/models_info.json", out_dir + "/models_info.json"));
  for (const ObjectCapture& oc : report) {
    const std::string from = dataset.ModelPath(oc.obj_id);
    if (!ycbv) {
      const std::string to = out_dir + "/" + fs::path(from).filename().string();
      const bool dropped = oc.source == ObjectCapture::Source::kNone && own_colour.count(oc.obj_id);
      if (oc.source == ObjectCapture::Source::kCaptured || dropped) {
        MCPOSE_RETURN_IF_ERROR(io::WritePlyMesh(to, meshes.at(oc.obj_id), 1000.0));
      } else {
        MCPOSE_RETURN_IF_ERROR(CopyFile(from, to));
      }
      continue;
    }
    const std::string dir = out_dir + "/" + oc.name;
    fs::create_directories(dir, ec);
    if (ec) return NotFound(dir + ": cannot create folder (" + ec.message() + ")");
    if (oc.source == ObjectCapture::Source::kNone && own_colour.count(oc.obj_id)) {
      // Its own colour dropped: the OBJ without its material, and its points.
      MCPOSE_ASSIGN_OR_RETURN(std::string obj_text, io::ReadFileToString(from + "/textured_simple.obj"));
      MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(dir + "/textured_simple.obj", ObjWithoutMaterial(obj_text)));
      if (fs::exists(from + "/points.xyz", ec)) MCPOSE_RETURN_IF_ERROR(CopyFile(from + "/points.xyz", dir + "/points.xyz"));
      continue;
    }
    if (oc.source != ObjectCapture::Source::kCaptured) {
      // The model's own files as they are (with its colour, if it has some).
      for (const fs::directory_entry& e : fs::directory_iterator(from, ec))
        if (e.is_regular_file()) MCPOSE_RETURN_IF_ERROR(CopyFile(e.path().string(), dir + "/" + e.path().filename().string()));
      if (ec) return DataLoss(from + ": cannot list folder (" + ec.message() + ")");
      continue;
    }
    MCPOSE_ASSIGN_OR_RETURN(std::string obj_text, io::ReadFileToString(from + "/textured_simple.obj"));
    MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(dir + "/textured_simple.obj",
                                               ObjWithCapturedMaterial(obj_text, "textured_simple.obj.mtl")));
    MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(
        dir + "/textured_simple.obj.mtl",
        "# Captured by mcpose capture-appearance from posed frames; alpha 0 marks surface no frame showed.\n"
        "newmtl captured\nKd 1 1 1\nmap_Kd texture_map.png\n"));
    MCPOSE_RETURN_IF_ERROR(io::WriteColourPng(dir + "/texture_map.png", *meshes.at(oc.obj_id).appearance.texture));
    if (fs::exists(from + "/points.xyz", ec)) MCPOSE_RETURN_IF_ERROR(CopyFile(from + "/points.xyz", dir + "/points.xyz"));
  }
  return report;
}

}  // namespace mcpose::appearance
