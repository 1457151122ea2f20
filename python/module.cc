// The compiled part of the Python package (mcpose._mcpose): datasets, the estimator, the
// metrics and the results journal of the C++ library, with numpy arrays in and out. Arrays that
// come out are views of the C++ buffers (no copy) kept alive by the Python object that owns
// them; the package (python/mcpose/) wraps these into its documented API.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "mcpose/option_flags.h"
#include "mcpose/limits.h"
#include "mcpose/run.h"
#include "mcpose/options_json.h"
#include "mcpose/results_journal.h"
#include "mcpose/bop19.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/estimator.h"
#include "mcpose/eval.h"
#include "mcpose/option_table.h"
#include "mcpose/results.h"
#include "mcpose/tracker.h"
#include "mcpose/version.h"

namespace py = pybind11;

namespace mcpose::python {
namespace {

// The Python exception of a Status, its message the one the command line prints after
// "mcpose: error: <kind>: ".
[[noreturn]] void Raise(const Status& st) {
  switch (st.code()) {
    case StatusCode::kInvalidArgument: throw py::value_error(st.message());
    case StatusCode::kNotFound: {
      PyErr_SetString(PyExc_FileNotFoundError, st.message().c_str());
      throw py::error_already_set();
    }
    case StatusCode::kDataLoss: {
      PyErr_SetString(PyExc_OSError, st.message().c_str());
      throw py::error_already_set();
    }
    default: throw std::runtime_error(st.message());
  }
}
void Check(const Status& st) {
  if (!st.ok()) Raise(st);
}
template <typename T>
T Value(StatusOr<T> v) {
  if (!v.ok()) Raise(v.status());
  return std::move(v).value();
}

// A numpy view of `data` with the given shape, kept alive by `owner`.
template <typename T>
py::array View(const T* data, std::vector<py::ssize_t> shape, py::handle owner) {
  std::vector<py::ssize_t> strides(shape.size());
  py::ssize_t step = sizeof(T);
  for (size_t i = shape.size(); i-- > 0;) strides[i] = step, step *= shape[i];
  py::array a(py::dtype::of<T>(), shape, strides, data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

py::array_t<double> PoseMatrix(const SE3& T) {
  py::array_t<double> m({4, 4});
  auto r = m.mutable_unchecked<2>();
  const Eigen::Matrix4d M = T.Matrix();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r(i, j) = M(i, j);
  return m;
}

// ---- Detections as BOP dicts ------------------------------------------------------------------
py::dict DetectionDict(const Detection& d) {
  py::dict o;
  o["scene_id"] = d.scene_id;
  o["image_id"] = d.image_id;
  o["category_id"] = d.obj_id;
  o["score"] = d.score;
  o["bbox"] = py::make_tuple(d.x, d.y, d.w, d.h);
  o["time"] = d.time_s;
  return o;
}

std::vector<Detection> DetectionsFromPython(const py::iterable& list) {
  std::vector<Detection> out;
  int i = 0;
  for (const py::handle item : list) {
    const std::string where = "detection " + std::to_string(i++);
    if (!py::isinstance<py::dict>(item)) throw py::value_error(where + ": expected a dict with category_id, score, bbox");
    const py::dict d = py::reinterpret_borrow<py::dict>(item);
    Detection det;
    for (const char* key : {"category_id", "score", "bbox"})
      if (!d.contains(key)) throw py::value_error(where + ": missing '" + key + "'");
    det.obj_id = d["category_id"].cast<int>();
    det.score = d["score"].cast<double>();
    const std::vector<double> box = d["bbox"].cast<std::vector<double>>();
    if (box.size() != 4) throw py::value_error(where + ": bbox must be [x, y, w, h]");
    det.x = box[0], det.y = box[1], det.w = box[2], det.h = box[3];
    if (d.contains("scene_id")) det.scene_id = d["scene_id"].cast<int>();
    if (d.contains("image_id")) det.image_id = d["image_id"].cast<int>();
    if (d.contains("time") && !d["time"].is_none()) det.time_s = d["time"].cast<double>();
    if (const std::string problem = CheckDetection(det); !problem.empty())
      throw py::value_error(where + ": " + problem);
    out.push_back(det);
  }
  return out;
}

// ---- Results rows as plain tuples (pickled between Dask processes without loss) -------------
using RowTuple = std::tuple<int, int, int, double, std::vector<double>, std::vector<double>, double>;

RowTuple RowToTuple(const PoseResult& r) {
  std::vector<double> R(9), t(3);
  for (int k = 0; k < 9; ++k) R[k] = r.T_cam_obj.R(k / 3, k % 3);
  for (int k = 0; k < 3; ++k) t[k] = r.T_cam_obj.t(k);
  return {r.scene_id, r.im_id, r.obj_id, r.score, R, t, r.time_s};
}

PoseResult RowFromTuple(const RowTuple& row) {
  PoseResult r;
  std::vector<double> R, t;
  std::tie(r.scene_id, r.im_id, r.obj_id, r.score, R, t, r.time_s) = row;
  if (R.size() != 9 || t.size() != 3) throw py::value_error("a results row needs R (9 numbers) and t (3 numbers)");
  for (int k = 0; k < 9; ++k) r.T_cam_obj.R(k / 3, k % 3) = R[k];
  for (int k = 0; k < 3; ++k) r.T_cam_obj.t(k) = t[k];
  return r;
}

// A dataset whose meshes are read once: a Python session or a Dask worker estimates many
// images of the same classes, and a textured mesh takes longer to read than to estimate.
class MeshCachingDataset final : public Dataset {
 public:
  explicit MeshCachingDataset(std::unique_ptr<Dataset> inner) : inner_(std::move(inner)) {}
  DatasetFormat format() const override { return inner_->format(); }
  const std::string& root() const override { return inner_->root(); }
  std::vector<FrameKey> Frames() const override { return inner_->Frames(); }
  StatusOr<Frame> LoadFrame(const FrameKey& key) const override { return inner_->LoadFrame(key); }
  StatusOr<Intrinsics> LoadIntrinsics(const FrameKey& key) const override { return inner_->LoadIntrinsics(key); }
  StatusOr<ColourImage> LoadColour(const Frame& frame) const override { return inner_->LoadColour(frame); }
  std::string FrameName(const FrameKey& key) const override { return inner_->FrameName(key); }
  StatusOr<FrameKey> ParseFrameName(const std::string& name) const override { return inner_->ParseFrameName(name); }
  StatusOr<MaskImage> LoadVisibleMask(const FrameKey& key, const GtInstance& gt) const override {
    return inner_->LoadVisibleMask(key, gt);
  }
  std::vector<int> ObjectIds() const override { return inner_->ObjectIds(); }
  std::string ObjectName(int obj_id) const override { return inner_->ObjectName(obj_id); }
  std::string ModelPath(int obj_id) const override { return inner_->ModelPath(obj_id); }
  const std::string& models_dir() const override { return inner_->models_dir(); }
  StatusOr<std::vector<Eigen::Vector3f>> LoadEvalPoints(int obj_id) const override {
    return inner_->LoadEvalPoints(obj_id);
  }
  StatusOr<Mesh> LoadMesh(int obj_id) const override {
    const std::lock_guard<std::mutex> lock(mutex_);
    auto it = meshes_.find(obj_id);
    if (it == meshes_.end()) {
      MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, inner_->LoadMesh(obj_id));
      it = meshes_.emplace(obj_id, std::move(mesh)).first;
    }
    return it->second;
  }

 private:
  std::unique_ptr<Dataset> inner_;
  mutable std::mutex mutex_;
  mutable std::map<int, Mesh> meshes_;
};

// ---- Python-side holders ------------------------------------------------------------------
struct PyDataset {
  std::unique_ptr<Dataset> ds;
  std::string split;
};
struct PyFrame {
  Frame frame;
};
struct PyMesh {
  Mesh mesh;
  int obj_id = 0;
};
struct PyColour {
  ColourImage image;
};

py::array ColourArray(ColourImage image) {
  auto holder = std::make_unique<PyColour>(PyColour{std::move(image)});
  const PyColour& c = *holder;
  py::object owner = py::cast(std::move(holder));
  // RGB of the RGBA buffer: H x W x 3, strides of 4 bytes per pixel (a view, no copy).
  py::array a(py::dtype::of<uint8_t>(), {c.image.height, c.image.width, 3},
              {4 * c.image.width, 4, 1}, c.image.rgba.data(), owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

ColourImage ColourFromPython(const py::array& array, int width, int height) {
  // uint8 only: a float image (0-1 or 0-255) cast silently would be garbage, NaN included.
  if (array.dtype().kind() != 'u' || array.dtype().itemsize() != 1)
    throw py::value_error("rgb: expected a uint8 array of shape (" + std::to_string(height) + ", " +
                          std::to_string(width) + ", 3) or (..., 4), got dtype " +
                          py::str(array.dtype()).cast<std::string>());
  const auto rgb = py::array_t<uint8_t, py::array::c_style | py::array::forcecast>::ensure(array);
  if (rgb.ndim() != 3 || (rgb.shape(2) != 3 && rgb.shape(2) != 4) || rgb.shape(0) != height ||
      rgb.shape(1) != width)
    throw py::value_error("rgb: expected a uint8 array of shape (" + std::to_string(height) + ", " +
                          std::to_string(width) + ", 3) or (..., 4), the depth image's size");
  ColourImage c;
  c.width = width, c.height = height;
  c.rgba.resize(4 * static_cast<size_t>(width) * height);
  const int channels = static_cast<int>(rgb.shape(2));
  const uint8_t* src = rgb.data();
  for (size_t p = 0; p < static_cast<size_t>(width) * height; ++p) {
    for (int k = 0; k < 3; ++k) c.rgba[4 * p + k] = src[channels * p + k];
    c.rgba[4 * p + 3] = 255;  // an alpha channel is ignored, as in the frames the datasets read
  }
  return c;
}

// Locks `mutex` without holding the GIL while it waits: the thread that holds the mutex may
// need the GIL before it lets go.
std::unique_lock<std::mutex> LockReleasingGil(std::mutex& mutex) {
  py::gil_scoped_release release;
  return std::unique_lock<std::mutex>(mutex);
}

// ---- The estimator ------------------------------------------------------------------------
// An Estimator's buffers serve one estimate at a time: calls from several Python threads (the
// GIL is released while the engine runs) take turns on `mutex`.
struct PyEstimator {
  EstimatorOptions options;
  std::unique_ptr<Estimator> estimator;
  std::unique_ptr<std::mutex> mutex = std::make_unique<std::mutex>();

  // The estimator of `seed` (the options' seed when none); the caller holds `mutex`.
  Estimator& ForSeed(std::optional<uint64_t> seed) {
    const uint64_t want = seed ? *seed : options.seed;
    if (estimator->options().seed != want) {
      EstimatorOptions o = options;
      o.seed = want;
      estimator = Value(Estimator::Create(o));
    }
    return *estimator;
  }
};

py::dict ObjectDict(const ObjectRecord& r) {
  const ObjectEstimate& e = r.estimate;
  py::dict o;
  o["obj_id"] = r.obj_id;
  o["instance"] = r.instance;
  o["name"] = r.name;
  o["T_cam_obj"] = PoseMatrix(e.T_cam_obj);
  o["score"] = e.best_weight;
  o["iterations"] = static_cast<int>(e.iterations.size());
  py::dict box = DetectionDict(r.chosen_box);
  box["index"] = e.best_box;
  o["box"] = box;
  py::array_t<double> per({static_cast<py::ssize_t>(e.iterations.size()), py::ssize_t{4}});
  auto w = per.mutable_unchecked<2>();
  for (size_t i = 0; i < e.iterations.size(); ++i) {
    const IterationSummary& it = e.iterations[i];
    w(i, 0) = it.mean_weight, w(i, 1) = it.best_weight, w(i, 2) = it.score_ms, w(i, 3) = it.iteration_ms;
  }
  o["per_iteration"] = per;
  o["time_s"] = r.time_s;
  o["twins_winner"] = e.twins.winner;
  o["refine_accepted"] = e.refine.accepted;
  return o;
}

// Groups detections by class, all of one image; the image's key from the detections.
std::map<int, std::vector<Detection>> ByClass(const std::vector<Detection>& dets, FrameKey* key) {
  std::map<int, std::vector<Detection>> by_class;
  for (size_t i = 0; i < dets.size(); ++i) {
    const Detection& d = dets[i];
    if (i == 0) *key = {d.scene_id, d.image_id};
    if (d.scene_id != key->scene_id || d.image_id != key->image_id)
      throw py::value_error("detection " + std::to_string(i) + " (scene_id " + std::to_string(d.scene_id) +
                            ", image_id " + std::to_string(d.image_id) +
                            "): estimate takes the detections of one image");
    by_class[d.obj_id].push_back(d);
  }
  return by_class;
}

// At most limits::kMaxBoxesPerImage boxes in one image, as the CLI's check.
void CheckBoxCount(size_t boxes) {
  if (boxes > static_cast<size_t>(limits::kMaxBoxesPerImage))
    throw py::value_error(std::to_string(boxes) + " detections: more than " +
                          std::to_string(limits::kMaxBoxesPerImage) + " boxes in one image");
}

// The detections of one image by class, each with a mesh in `meshes` and a box inside the image.
std::map<int, std::vector<Detection>> CheckedByClass(const std::vector<Detection>& dets, const Intrinsics& K,
                                                     const std::function<bool(int)>& has_mesh, FrameKey* key) {
  CheckBoxCount(dets.size());
  std::map<int, std::vector<Detection>> by_class = ByClass(dets, key);
  for (size_t i = 0; i < dets.size(); ++i) {
    if (!has_mesh(dets[i].obj_id))
      throw py::value_error("detection " + std::to_string(i) + ": no mesh for category_id " +
                            std::to_string(dets[i].obj_id));
    if (Status st = CheckBox(dets[i], K); !st.ok())
      throw py::value_error("detection " + std::to_string(i) + " (category_id " + std::to_string(dets[i].obj_id) +
                            "): " + st.message());
  }
  return by_class;
}

// Runs `estimate(estimator)` with the estimator of `seed`, the GIL released; {obj_id: dict} of
// each class's first instance, whose "instances" lists every instance's dict, the first included.
template <typename Fn>
py::dict EstimateLocked(PyEstimator& self, std::optional<uint64_t> seed, const Fn& estimate) {
  const std::unique_lock<std::mutex> lock = LockReleasingGil(*self.mutex);
  Estimator& estimator = self.ForSeed(seed);
  StatusOr<ImageEstimate> image = Status::Ok();
  {
    py::gil_scoped_release release;
    image = estimate(estimator);
  }
  py::dict out;
  for (const ObjectRecord& r : Value(std::move(image)).objects) {
    const py::int_ obj_id(r.obj_id);
    if (r.instance == 0) {
      py::dict first = ObjectDict(r);
      py::list instances;
      instances.append(ObjectDict(r));
      first["instances"] = instances;
      out[obj_id] = first;
    } else {
      out[obj_id].cast<py::dict>()["instances"].cast<py::list>().append(ObjectDict(r));
    }
  }
  return out;
}

// ---- The tracker ---------------------------------------------------------------------------
// One frame at a time, as PyEstimator: calls from several threads take turns on `mutex`.
struct PyTracker {
  std::unique_ptr<Tracker> tracker;
  std::unique_ptr<std::mutex> mutex = std::make_unique<std::mutex>();
  // The meshes track_frame has read, kept from frame to frame (a frame must not copy them
  // again), and the dataset they came from (held, so that it is not another at the same address).
  py::object mesh_dataset;
  std::map<int, Mesh> meshes;
};

py::dict StepDict(const TrackStep& s) {
  py::dict o;
  o["obj_id"] = s.obj_id;
  o["T_cam_obj"] = PoseMatrix(s.T_cam_obj);
  o["weight"] = s.weight;
  o["fit"] = s.fit;
  o["visible"] = s.visible;
  o["initialised"] = s.initialised;
  o["lost"] = s.lost;
  o["iterations"] = s.iterations;
  o["box"] = s.box.w > 0 ? py::object(DetectionDict(s.box)) : py::object(py::none());
  o["time_s"] = s.ms / 1000.0;
  return o;
}

// Depth and intrinsics from numpy arrays, checked by the same functions as the readers' (the
// limits of include/mcpose/limits.h): depth float32 or float64 in metres, each value 0 (no
// measurement) or positive and finite up to 100 m; K a pinhole matrix within the readers' limits.
std::pair<Intrinsics, DepthImage> DepthFromPython(const py::array& depth_array, const py::array& K_array) {
  const char kind = depth_array.dtype().kind();
  if (kind != 'f') {
    std::string message = "depth: expected float32 or float64 metres, got dtype " +
                          py::str(depth_array.dtype()).cast<std::string>();
    if (kind == 'u' || kind == 'i')
      message += "; a depth image in sensor units must be scaled to metres first (e.g. depth * 1e-4 for 0.1 mm "
                 "units, depth * 1e-3 for millimetres)";
    throw py::value_error(message);
  }
  if (K_array.dtype().kind() != 'f' && K_array.dtype().kind() != 'i' && K_array.dtype().kind() != 'u')
    throw py::value_error("K: expected a 3x3 array of numbers, got dtype " + py::str(K_array.dtype()).cast<std::string>());
  const auto depth = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(depth_array);
  const auto K = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(K_array);
  if (depth.ndim() != 2) throw py::value_error("depth: expected a float32 array of shape (H, W), metres");
  if (K.ndim() != 2 || K.shape(0) != 3 || K.shape(1) != 3)
    throw py::value_error("K: expected a 3x3 array [[fx, 0, cx], [0, fy, cy], [0, 0, 1]], pixels");
  const int height = static_cast<int>(depth.shape(0)), width = static_cast<int>(depth.shape(1));
  if (width < 1 || height < 1 || width > limits::kMaxImageSide || height > limits::kMaxImageSide)
    throw py::value_error("depth: " + std::to_string(width) + "x" + std::to_string(height) + " pixels; each side 1-" +
                          std::to_string(limits::kMaxImageSide));
  if (const std::string problem = limits::CheckPinholeMatrix(K.data(), width, height); !problem.empty())
    throw py::value_error("K: " + problem);
  if (const std::string problem = limits::CheckDepthMetres(depth.data(), width, height); !problem.empty())
    throw py::value_error("depth: " + problem);
  Intrinsics intr;
  intr.fx = K.at(0, 0), intr.fy = K.at(1, 1), intr.cx = K.at(0, 2), intr.cy = K.at(1, 2);
  intr.height = height, intr.width = width;
  DepthImage d;
  d.width = intr.width, d.height = intr.height;
  d.depth_m.assign(depth.data(), depth.data() + depth.size());
  return {intr, std::move(d)};
}

}  // namespace
}  // namespace mcpose::python

PYBIND11_MODULE(_mcpose, m) {
  using namespace mcpose;
  using namespace mcpose::python;
  m.doc() = "mcpose's C++ library; use the mcpose package, which documents each call.";
  m.attr("__version__") = Version();

  py::class_<PyColour>(m, "_ColourBuffer");

  py::class_<PyMesh>(m, "Mesh")
      .def_property_readonly("obj_id", [](const PyMesh& s) { return s.obj_id; })
      .def_property_readonly("vertices", [](py::object self) {
        const PyMesh& s = self.cast<const PyMesh&>();
        return View(s.mesh.vertices_m.empty() ? nullptr : s.mesh.vertices_m[0].data(),
                    {static_cast<py::ssize_t>(s.mesh.vertices_m.size()), 3}, self);
      }, "(V, 3) float32, metres, model frame (read-only view)")
      .def_property_readonly("triangles", [](py::object self) {
        const PyMesh& s = self.cast<const PyMesh&>();
        return View(s.mesh.triangles.empty() ? nullptr : s.mesh.triangles[0].data(),
                    {static_cast<py::ssize_t>(s.mesh.triangles.size()), 3}, self);
      }, "(T, 3) uint32 vertex indices, counter-clockwise seen from outside (read-only view)")
      .def_property_readonly("has_colour", [](const PyMesh& s) { return !s.mesh.appearance.empty(); })
      .def("__repr__", [](const PyMesh& s) {
        return "<mcpose.Mesh obj_id " + std::to_string(s.obj_id) + ", " + std::to_string(s.mesh.vertices_m.size()) +
               " vertices, " + std::to_string(s.mesh.triangles.size()) + " triangles>";
      });

  py::class_<PyFrame>(m, "Frame")
      .def_property_readonly("scene_id", [](const PyFrame& s) { return s.frame.key.scene_id; })
      .def_property_readonly("image_id", [](const PyFrame& s) { return s.frame.key.image_id; })
      .def_property_readonly("key", [](const PyFrame& s) { return py::make_tuple(s.frame.key.scene_id, s.frame.key.image_id); },
                             "(scene_id, image_id)")
      .def_property_readonly("width", [](const PyFrame& s) { return s.frame.K.width; })
      .def_property_readonly("height", [](const PyFrame& s) { return s.frame.K.height; })
      .def_property_readonly("K", [](const PyFrame& s) {
        py::array_t<double> K({3, 3});
        auto k = K.mutable_unchecked<2>();
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) k(i, j) = 0;
        k(0, 0) = s.frame.K.fx, k(1, 1) = s.frame.K.fy, k(0, 2) = s.frame.K.cx, k(1, 2) = s.frame.K.cy, k(2, 2) = 1;
        return K;
      }, "(3, 3) float64 intrinsics, pixels; pixel centres at integer coordinates")
      .def_property_readonly("depth", [](py::object self) {
        const PyFrame& s = self.cast<const PyFrame&>();
        return View(s.frame.depth.depth_m.data(), {s.frame.depth.height, s.frame.depth.width}, self);
      }, "(H, W) float32 depth, metres, 0 = no measurement (read-only view, no copy)")
      .def_property_readonly("gt_obj_ids", [](const PyFrame& s) {
        py::array_t<int32_t> ids(static_cast<py::ssize_t>(s.frame.gt.size()));
        for (size_t i = 0; i < s.frame.gt.size(); ++i) ids.mutable_at(i) = s.frame.gt[i].obj_id;
        return ids;
      }, "(N,) int32 obj_ids of the ground-truth instances")
      .def_property_readonly("gt_T_cam_obj", [](const PyFrame& s) {
        py::array_t<double> T({static_cast<py::ssize_t>(s.frame.gt.size()), py::ssize_t{4}, py::ssize_t{4}});
        auto w = T.mutable_unchecked<3>();
        for (size_t n = 0; n < s.frame.gt.size(); ++n) {
          const Eigen::Matrix4d M = s.frame.gt[n].T_cam_obj.Matrix();
          for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) w(n, i, j) = M(i, j);
        }
        return T;
      }, "(N, 4, 4) float64 ground-truth poses, model to camera, metres");

  py::class_<PyDataset>(m, "Dataset")
      .def(py::init([](const std::string& path, const std::string& split, const std::string& models) {
             return PyDataset{std::make_unique<MeshCachingDataset>(Value(Dataset::Open(path, split, models))), split};
           }),
           py::arg("path"), py::arg("split") = "test", py::arg("models") = "")
      .def_property_readonly("root", [](const PyDataset& s) { return s.ds->root(); })
      .def_property_readonly("format", [](const PyDataset& s) {
        return s.ds->format() == DatasetFormat::kYcbv ? "ycbv" : "bop";
      })
      .def_property_readonly("frames", [](const PyDataset& s) {
        std::vector<std::pair<int, int>> out;
        for (const FrameKey& k : s.ds->Frames()) out.emplace_back(k.scene_id, k.image_id);
        return out;
      })
      .def_property_readonly("object_ids", [](const PyDataset& s) { return s.ds->ObjectIds(); })
      .def("object_name", [](const PyDataset& s, int id) { return s.ds->ObjectName(id); })
      .def("frame_name", [](const PyDataset& s, int scene, int image) { return s.ds->FrameName({scene, image}); })
      .def("load_frame", [](const PyDataset& s, int scene, int image) {
        return PyFrame{Value(s.ds->LoadFrame({scene, image}))};
      })
      .def("load_colour", [](const PyDataset& s, const PyFrame& f) {
        return ColourArray(Value(s.ds->LoadColour(f.frame)));
      })
      .def("load_mesh", [](const PyDataset& s, int obj_id) { return PyMesh{Value(s.ds->LoadMesh(obj_id)), obj_id}; })
      .def("eval_points", [](const PyDataset& s, int obj_id) {
        const std::vector<Eigen::Vector3f> p = Value(s.ds->LoadEvalPoints(obj_id));
        py::array_t<float> a({static_cast<py::ssize_t>(p.size()), py::ssize_t{3}});
        auto w = a.mutable_unchecked<2>();
        for (size_t i = 0; i < p.size(); ++i)
          for (int k = 0; k < 3; ++k) w(i, k) = p[i](k);
        return a;
      })
      .def("detections_from_gt", [](const PyDataset& s, double jitter, double distractors, uint64_t seed) {
        GtDetectionOptions o;
        o.jitter = jitter, o.distractors = distractors, o.seed = seed;
        py::list out;
        for (const Detection& d : Value(DetectionsFromGroundTruth(*s.ds, o))) out.append(DetectionDict(d));
        return out;
      }, py::arg("jitter") = 0.1, py::arg("distractors") = 0.3, py::arg("seed") = 0);

  m.def("read_detections", [](const std::string& path) {
    py::list out;
    for (const Detection& d : Value(ReadDetectionsJson(path))) out.append(DetectionDict(d));
    return out;
  });
  m.def("write_detections", [](const std::string& path, const py::iterable& dets) {
    Check(WriteDetectionsJson(path, DetectionsFromPython(dets)));
  });
  m.def("is_switch", &IsEstimatorSwitch);
  m.def("option_fields", [] {
    // The options table: each field's key, flag, type, default (as JSON gives it), values,
    // unit and doc.
    const nlohmann::json defaults = io::OptionsToJson(EstimatorOptions{});
    static const char* const kTypes[] = {"int", "seed", "float", "bool", "enum"};
    const py::object loads = py::module_::import("json").attr("loads");
    py::list fields;
    for (const OptionField& f : EstimatorOptionFields()) {
      py::dict d;
      d["key"] = f.key;
      d["flag"] = f.flag ? py::object(py::str(f.flag)) : py::object(py::none());
      d["type"] = kTypes[static_cast<int>(f.type)];
      d["default"] = loads(defaults.at(io::OptionPointer(f.key)).dump());
      d["choices"] = std::vector<std::string>(f.names.begin(), f.names.end());
      d["values"] = f.BoundsText();
      d["unit"] = f.unit;
      d["doc"] = f.doc;
      fields.append(d);
    }
    return fields;
  });
  m.def("check_detections", [](const PyDataset& ds, const py::iterable& detections, const std::string& source) {
    Value(GroupDetections(*ds.ds, DetectionsFromPython(detections), source));
  });

  py::class_<PyEstimator>(m, "Estimator")
      .def(py::init([](const std::vector<std::string>& args, const std::string& options_json) {
        PyEstimator e;
        EstimatorOptions base;
        if (!options_json.empty()) {
          const nlohmann::json j = nlohmann::json::parse(options_json, nullptr, /*allow_exceptions=*/false);
          if (j.is_discarded()) Raise(InvalidArgument("options: not JSON"));
          base = Value(io::OptionsFromJson(j));
        }
        e.options = Value(ParseEstimatorOptions(args, base));
        e.estimator = Value(Estimator::Create(e.options));
        return e;
      }), py::arg("args"), py::arg("options_json") = "")
      .def_property_readonly("options_json", [](const PyEstimator& s) { return io::OptionsToJson(s.options).dump(); })
      .def("estimate",
           [](PyEstimator& self, const py::array& depth, const py::array& K, const py::iterable& detections,
              const py::dict& meshes, const std::optional<py::array>& rgb,
              std::optional<uint64_t> seed) {
             auto [intr, d] = DepthFromPython(depth, K);
             std::optional<ColourImage> colour;
             if (rgb) colour = ColourFromPython(*rgb, intr.width, intr.height);
             std::map<int, const Mesh*> mesh_of;
             for (const auto& [id, mesh] : meshes) mesh_of[id.cast<int>()] = &mesh.cast<const PyMesh&>().mesh;
             FrameKey key;
             const auto by_class = CheckedByClass(DetectionsFromPython(detections), intr,
                                                  [&](int id) { return mesh_of.count(id) > 0; }, &key);
             return EstimateLocked(self, seed, [&](Estimator& estimator) {
               return EstimateImage(estimator, key, intr, d, colour ? &*colour : nullptr, by_class, mesh_of, nullptr,
                                    nullptr);
             });
           },
           py::arg("depth"), py::arg("K"), py::arg("detections"), py::arg("meshes"), py::arg("rgb") = py::none(),
           py::arg("seed") = py::none())
      .def("estimate_frame",
           [](PyEstimator& self, const PyFrame& frame, const py::iterable& detections, const PyDataset& ds,
              std::optional<uint64_t> seed) {
             const Frame& f = frame.frame;
             std::vector<Detection> dets = DetectionsFromPython(detections);
             std::erase_if(dets, [&](const Detection& d) {
               return d.scene_id != f.key.scene_id || d.image_id != f.key.image_id;
             });
             FrameKey key;
             const auto by_class = CheckedByClass(dets, f.K, [](int) { return true; }, &key);
             std::map<int, Mesh> meshes;
             std::map<int, const Mesh*> mesh_of;
             for (const auto& [id, boxes] : by_class)
               mesh_of[id] = &meshes.emplace(id, Value(ds.ds->LoadMesh(id))).first->second;
             return EstimateLocked(self, seed, [&](Estimator& estimator) {
               return EstimateFrame(estimator, *ds.ds, f, by_class, mesh_of, nullptr);
             });
           },
           py::arg("frame"), py::arg("detections"), py::arg("dataset"), py::arg("seed") = py::none())
      .def("run",
           [](PyEstimator& self, const PyDataset& ds, const py::iterable& detections, const std::string& source) {
             const std::vector<Detection> dets = DetectionsFromPython(detections);
             const std::unique_lock<std::mutex> lock = LockReleasingGil(*self.mutex);
             Estimator& estimator = self.ForSeed(std::nullopt);
             StatusOr<RunReport> report = Status::Ok();
             {
               py::gil_scoped_release release;
               report = RunEstimation(estimator, *ds.ds, dets, source, nullptr);
             }
             std::vector<RowTuple> rows;
             for (const PoseResult& r : Value(std::move(report)).results) rows.push_back(RowToTuple(r));
             return rows;
           },
           py::arg("dataset"), py::arg("detections"), py::arg("source") = "detections",
           "Checks and estimates like `mcpose estimate`; the results rows as tuples")
      .def("fingerprint", [](const PyEstimator& self, const py::iterable& detections, const PyDataset& ds) {
        return io::RunFingerprint(self.options, DetectionsFromPython(detections),
                                  {ds.ds->root(), ds.split, ds.ds->models_dir()});
      });

  py::class_<PyTracker>(m, "Tracker")
      .def(py::init([](const std::vector<std::string>& args) {
        PyTracker t;
        t.tracker = Value(Tracker::Create(Value(ParseTrackerOptions(args))));
        return t;
      }))
      .def_property_readonly("options_json", [](const PyTracker& s) {
        return io::TrackerOptionsToJson(s.tracker->options()).dump();
      })
      .def_property_readonly("tracked_ids", [](const PyTracker& s) {
        const std::unique_lock<std::mutex> lock = LockReleasingGil(*s.mutex);
        return s.tracker->TrackedIds();
      })
      .def("reset", [](PyTracker& s, int obj_id) {
        const std::unique_lock<std::mutex> lock = LockReleasingGil(*s.mutex);
        s.tracker->Reset(obj_id);
      })
      .def("track",
           [](PyTracker& self, const py::array& depth, const py::array& K, const PyMesh& mesh, int obj_id,
              const py::iterable& boxes, const std::optional<py::array>& rgb,
              uint64_t stream_id) {
             auto [intr, d] = DepthFromPython(depth, K);
             std::optional<ColourImage> colour;
             if (rgb) colour = ColourFromPython(*rgb, intr.width, intr.height);
             std::vector<Detection> dets = DetectionsFromPython(boxes);
             for (size_t i = 0; i < dets.size(); ++i) {
               if (dets[i].obj_id != obj_id)
                 throw py::value_error("box " + std::to_string(i) + ": category_id " + std::to_string(dets[i].obj_id) +
                                       " is not the tracked class " + std::to_string(obj_id));
               if (Status st = CheckBox(dets[i], intr); !st.ok())
                 throw py::value_error("box " + std::to_string(i) + ": " + st.message());
             }
             const std::unique_lock<std::mutex> lock = LockReleasingGil(*self.mutex);
             StatusOr<TrackStep> step = Status::Ok();
             {
               py::gil_scoped_release release;
               step = self.tracker->Track(intr, d, colour ? &*colour : nullptr, mesh.mesh, obj_id, dets, stream_id);
             }
             return StepDict(Value(std::move(step)));
           },
           py::arg("depth"), py::arg("K"), py::arg("mesh"), py::arg("obj_id"), py::arg("boxes"),
           py::arg("rgb") = py::none(), py::arg("stream_id") = 0)
      .def("track_frame", [](PyTracker& self, const PyFrame& frame, const py::iterable& detections, py::object dataset) {
        const PyDataset& ds = dataset.cast<const PyDataset&>();
        const Frame& f = frame.frame;
        std::map<int, std::vector<Detection>> boxes;
        for (const Detection& d : DetectionsFromPython(detections))
          if (d.scene_id == f.key.scene_id && d.image_id == f.key.image_id) {
            if (Status st = CheckBox(d, f.K); !st.ok())
              throw py::value_error("detection of category_id " + std::to_string(d.obj_id) + ": " + st.message());
            boxes[d.obj_id].push_back(d);
          }
        size_t count = 0;
        for (const auto& [id, dets] : boxes) count += dets.size();
        CheckBoxCount(count);
        const std::unique_lock<std::mutex> lock = LockReleasingGil(*self.mutex);
        std::set<int> classes;
        for (int id : self.tracker->TrackedIds()) classes.insert(id);
        for (const auto& [id, dets] : boxes) classes.insert(id);
        if (!self.mesh_dataset.is(dataset)) self.meshes.clear(), self.mesh_dataset = dataset;
        std::map<int, const Mesh*> mesh_of;
        for (int id : classes) {
          auto it = self.meshes.find(id);
          if (it == self.meshes.end()) it = self.meshes.emplace(id, Value(ds.ds->LoadMesh(id))).first;
          mesh_of[id] = &it->second;
        }
        StatusOr<std::vector<TrackStep>> steps = Status::Ok();
        {
          py::gil_scoped_release release;
          steps = TrackFrame(*self.tracker, f, mesh_of, boxes, [&] { return ds.ds->LoadColour(f); });
        }
        py::dict out;
        for (const TrackStep& s : Value(std::move(steps))) out[py::int_(s.obj_id)] = StepDict(s);
        return out;
      });

  py::class_<io::ResultsJournal>(m, "ResultsJournal")
      .def(py::init([](const std::string& out, const std::string& fingerprint, bool resume) {
        return Value(io::ResultsJournal::Open(out, fingerprint, resume));
      }))
      .def_property_readonly("kept_images", &io::ResultsJournal::kept_images)
      .def("has", [](const io::ResultsJournal& j, int scene, int image) { return j.Has({scene, image}); })
      .def("append", [](io::ResultsJournal& j, int scene, int image, const std::vector<RowTuple>& rows) {
        std::vector<PoseResult> r;
        for (const RowTuple& t : rows) r.push_back(RowFromTuple(t));
        Check(j.Append({scene, image}, r));
      })
      .def("finish", [](io::ResultsJournal& j) { Check(j.Finish()); });

  m.def("add", [](const py::array_t<float, py::array::c_style | py::array::forcecast>& points,
                  const py::array_t<double, py::array::c_style | py::array::forcecast>& T_est,
                  const py::array_t<double, py::array::c_style | py::array::forcecast>& T_gt, bool symmetric) {
    if (points.ndim() != 2 || points.shape(1) != 3) throw py::value_error("points: expected an (N, 3) array, metres");
    if (T_est.ndim() != 3 || T_gt.ndim() != 3 || T_est.shape(0) != T_gt.shape(0) || T_est.shape(1) != 4 ||
        T_est.shape(2) != 4 || T_gt.shape(1) != 4 || T_gt.shape(2) != 4)
      throw py::value_error("T_est, T_gt: expected two (B, 4, 4) arrays of the same B, metres");
    std::vector<Eigen::Vector3f> p(points.shape(0));
    for (size_t i = 0; i < p.size(); ++i) p[i] = {points.at(i, 0), points.at(i, 1), points.at(i, 2)};
    py::array_t<double> out(T_est.shape(0));
    for (py::ssize_t b = 0; b < T_est.shape(0); ++b) {
      SE3 a, g;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) a.R(i, j) = T_est.at(b, i, j), g.R(i, j) = T_gt.at(b, i, j);
        a.t(i) = T_est.at(b, i, 3), g.t(i) = T_gt.at(b, i, 3);
      }
      out.mutable_at(b) = symmetric ? AddS(p, a, g) : Add(p, a, g);
    }
    return out;
  });
  m.def("auc", [](const std::vector<double>& errors_m, double max_m) { return AccuracyAuc(errors_m, max_m); });

  // BOP19: the symmetries of an object from a models_info.json, the MSSD and MSPD of poses, and
  // the whole evaluation of results rows on a dataset (mcpose eval --metrics bop19).
  m.def("bop19_symmetries", [](const std::string& models_info, int obj_id) {
    const std::map<int, ModelInfo> info = Value(ReadModelsInfo(models_info));
    const auto it = info.find(obj_id);
    if (it == info.end()) throw py::value_error(models_info + ": no object " + std::to_string(obj_id));
    const std::vector<SE3> sym = SymmetryTransformations(it->second);
    py::array_t<double> out({static_cast<py::ssize_t>(sym.size()), py::ssize_t{4}, py::ssize_t{4}});
    auto o = out.mutable_unchecked<3>();
    for (size_t k = 0; k < sym.size(); ++k)
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
          o(k, i, j) = i == 3 ? (j == 3 ? 1.0 : 0.0) : (j == 3 ? sym[k].t(i) : sym[k].R(i, j));
    return std::make_pair(it->second.diameter_m, out);
  });
  m.def("bop19_pose_errors", [](const py::array_t<float, py::array::c_style | py::array::forcecast>& points,
                                const py::array_t<double, py::array::c_style | py::array::forcecast>& T_est,
                                const py::array_t<double, py::array::c_style | py::array::forcecast>& T_gt,
                                const py::array_t<double, py::array::c_style | py::array::forcecast>& symmetries,
                                const py::array_t<double, py::array::c_style | py::array::forcecast>& K) {
    if (points.ndim() != 2 || points.shape(1) != 3) throw py::value_error("points: expected an (N, 3) array, metres");
    if (T_est.ndim() != 2 || T_gt.ndim() != 2 || T_est.shape(0) != 4 || T_est.shape(1) != 4 || T_gt.shape(0) != 4 ||
        T_gt.shape(1) != 4)
      throw py::value_error("T_est, T_gt: expected (4, 4) arrays, metres");
    if (symmetries.ndim() != 3 || symmetries.shape(1) != 4 || symmetries.shape(2) != 4 || symmetries.shape(0) < 1)
      throw py::value_error("symmetries: expected an (S, 4, 4) array, the identity among them");
    if (K.ndim() != 2 || K.shape(0) != 3 || K.shape(1) != 3) throw py::value_error("K: expected a (3, 3) array");
    const auto pose = [](const py::array_t<double, py::array::c_style | py::array::forcecast>& T, py::ssize_t k) {
      SE3 out;
      const bool batch = T.ndim() == 3;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) out.R(i, j) = batch ? T.at(k, i, j) : T.at(i, j);
        out.t(i) = batch ? T.at(k, i, 3) : T.at(i, 3);
      }
      return out;
    };
    std::vector<Eigen::Vector3f> p(static_cast<size_t>(points.shape(0)));
    for (size_t i = 0; i < p.size(); ++i) p[i] = {points.at(i, 0), points.at(i, 1), points.at(i, 2)};
    std::vector<SE3> sym;
    for (py::ssize_t k = 0; k < symmetries.shape(0); ++k) sym.push_back(pose(symmetries, k));
    Intrinsics intr{K.at(0, 0), K.at(1, 1), K.at(0, 2), K.at(1, 2), 0, 0};
    const SE3 a = pose(T_est, 0), g = pose(T_gt, 0);
    return std::make_pair(Mssd(p, a, g, sym), Mspd(p, a, g, sym, intr));
  });
  m.def("evaluate_bop19", [](const PyDataset& ds, const std::vector<RowTuple>& rows, const std::string& models_info,
                             const std::string& targets) {
    std::vector<PoseResult> results;
    for (const RowTuple& r : rows) results.push_back(RowFromTuple(r));
    const std::map<int, ModelInfo> info = Value(ReadModelsInfo(models_info));
    std::optional<std::vector<Bop19Target>> t;
    if (!targets.empty()) t = Value(ReadBop19Targets(targets));
    StatusOr<Bop19Report> report = Status::Ok();
    {
      py::gil_scoped_release release;
      report = EvaluateBop19(*ds.ds, results, info, t ? &*t : nullptr, Bop19Options{});
    }
    const Bop19Report r = Value(std::move(report));
    const auto summary = [](const Bop19Summary& s) {
      py::dict d;
      d["obj_id"] = s.obj_id, d["name"] = s.name, d["targets"] = s.targets;
      d["ar"] = s.ar, d["ar_vsd"] = s.ar_vsd, d["ar_mssd"] = s.ar_mssd, d["ar_mspd"] = s.ar_mspd;
      return d;
    };
    py::dict out;
    out["overall"] = summary(r.overall);
    py::list per_object;
    for (const Bop19Summary& s : r.per_object) per_object.append(summary(s));
    out["per_object"] = per_object;
    return out;
  });
  m.def("ycbv_symmetric_ids", [] {
    const std::set<int> s = YcbvSymmetricObjectIds();
    return std::vector<int>(s.begin(), s.end());
  });
}
