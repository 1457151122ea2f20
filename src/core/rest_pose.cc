#include "core/rest_pose.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include <Eigen/Geometry>

namespace mcpose {

namespace {

// Andrew's monotone chain: the convex hull of 2-D points, counter-clockwise.
std::vector<Eigen::Vector2d> Hull2d(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  if (p.size() < 3) return p;
  const auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  return h;
}

// Signed distance of q inside the counter-clockwise convex polygon h (negative outside), and its area.
double InsideMargin(const std::vector<Eigen::Vector2d>& h, const Eigen::Vector2d& q, double* area) {
  double margin = INFINITY;
  *area = 0;
  for (size_t i = 0; i < h.size(); ++i) {
    const Eigen::Vector2d a = h[i], b = h[(i + 1) % h.size()];
    const Eigen::Vector2d e = b - a;
    const double len = e.norm();
    *area += 0.5 * (a.x() * b.y() - b.x() * a.y());
    if (len <= 0) continue;
    margin = std::min(margin, (e.x() * (q - a).y() - e.y() * (q - a).x()) / len);
  }
  return margin;
}

struct QhullDeleter {
  void operator()(qhT* qh) const {
    qh_freeqhull(qh, !qh_ALL);
    int curlong = 0, totlong = 0;
    qh_memfreeshort(qh, &curlong, &totlong);
    delete qh;
  }
};

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

Eigen::Vector3d CentreOfMass(const Mesh& mesh) {
  // Signed tetrahedra from the origin: a closed, outward-wound mesh sums to its volume.
  double volume = 0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices_m[t[0]].cast<double>(), b = mesh.vertices_m[t[1]].cast<double>(),
                          c = mesh.vertices_m[t[2]].cast<double>();
    const double v = a.dot(b.cross(c)) / 6;
    volume += v;
    moment += v * (a + b + c) / 4;
  }
  if (volume > 1e-12) return moment / volume;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& v : mesh.vertices_m) mean += v.cast<double>();
  return mesh.vertices_m.empty() ? mean : mean / static_cast<double>(mesh.vertices_m.size());
}

StatusOr<std::vector<RestPose>> StableRestPoses(const Mesh& mesh, double min_margin_m) {
  if (mesh.vertices_m.size() < 4) return InvalidArgument("a rest pose needs a mesh of at least four vertices");
  const Eigen::Vector3d com = CentreOfMass(mesh);
  std::vector<coordT> points;
  points.reserve(3 * mesh.vertices_m.size());
  for (const auto& v : mesh.vertices_m)
    for (int a = 0; a < 3; ++a) points.push_back(static_cast<coordT>(v[a]));
  std::unique_ptr<std::FILE, FileCloser> devnull(std::fopen("/dev/null", "w"));
  std::unique_ptr<qhT, QhullDeleter> holder(new qhT);
  qhT* qh = holder.get();  // the name qhull's macros use
  qh_zero(qh, devnull.get());
  // Facets merged where their centrums lie within 1 mm of each other's planes: a scanned face is
  // never quite flat, and an object rests on the whole face, not on one of its slivers.
  char flags[] = "qhull C-0.001";
  const int exitcode = qh_new_qhull(qh, 3, static_cast<int>(mesh.vertices_m.size()), points.data(), False, flags,
                                    nullptr, devnull.get());
  if (exitcode != 0) return InvalidArgument("cannot build the convex hull of the mesh (flat or degenerate)");

  std::vector<RestPose> out;
  facetT* facet;
  FORALLfacets {
    const Eigen::Vector3d n(facet->normal[0], facet->normal[1], facet->normal[2]);
    const double height = -(n.dot(com) + facet->offset);
    if (!(height > 0)) continue;
    // The face's corners in a basis of its plane, and the centre of mass's foot on it.
    const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
    std::vector<Eigen::Vector2d> corners;
    vertexT *vertex, **vertexp;
    FOREACHvertex_(facet->vertices) {
      const Eigen::Vector3d p(vertex->point[0], vertex->point[1], vertex->point[2]);
      corners.emplace_back(p.dot(u), p.dot(w));
    }
    const std::vector<Eigen::Vector2d> polygon = Hull2d(corners);
    if (polygon.size() < 3) continue;
    double area = 0;
    const Eigen::Vector3d foot = com + height * n;
    if (InsideMargin(polygon, Eigen::Vector2d(foot.dot(u), foot.dot(w)), &area) < min_margin_m) continue;
    RestPose r;
    r.R = Eigen::Quaterniond::FromTwoVectors(n, Eigen::Vector3d(0, 0, -1)).toRotationMatrix();
    r.height = height;
    r.face_area = area;
    out.push_back(r);
  }
  std::sort(out.begin(), out.end(), [](const RestPose& a, const RestPose& b) { return a.height < b.height; });
  return out;
}

}  // namespace mcpose
