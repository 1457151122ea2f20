// Cluster culling a SIMD vector of clusters at a time (CullClustersSimd, clusters.h), with
// Highway, compiled for every target Highway knows here and dispatched at run time.
// CullCluster (clusters.cc) is its reference: each lane runs the same tests with the same float
// operations in the same order (Eigen's 3-term sums are a0 + (a1 + a2)), so the decisions
// are the same.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/check.h"
#include "render/clusters.h"

// Compiled once (foreach_target includes this file again for every target).
#ifndef MCPOSE_RENDER_CLUSTERS_SIMD_ONCE
#define MCPOSE_RENDER_CLUSTERS_SIMD_ONCE
namespace mcpose::render {
// The per-call constants: R row-major, t, camera_in_model, fx fy cx cy, z_near, and the box
// edges as CullCluster compares them (x0 - 1, x1, y0 - 1, y1).
struct CullConstants {
  float R[9], t[3], cam[3], fx, fy, cx, cy, z_near, box[4];
  bool cull_backfaces;
};
}  // namespace mcpose::render
#endif

#include "render/simd_dispatch.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/clusters_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "render/project-inl.h"

HWY_BEFORE_NAMESPACE();
namespace mcpose::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void CullClustersImpl(const float* soa, size_t stride, size_t n, const CullConstants& k, uint8_t* out) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const size_t lanes = hn::Lanes(df);
  // R x + t and the projection as CullCluster computes them (render/project-inl.h).
  const Projector<decltype(df)> proj(df, k.R, k.t, k.fx, k.fy, k.cx, k.cy);
  const auto z_near = hn::Set(df, k.z_near), one = hn::Set(df, 1.0f), zero = hn::Zero(df);
  const auto bx0 = hn::Set(df, k.box[0]), bx1 = hn::Set(df, k.box[1]), by0 = hn::Set(df, k.box[2]),
             by1 = hn::Set(df, k.box[3]);
  const auto keep_v = hn::Set(di, static_cast<int32_t>(ClusterCull::kKeep));
  const auto back_v = hn::Set(di, static_cast<int32_t>(ClusterCull::kBackface));
  const auto outside_v = hn::Set(di, static_cast<int32_t>(ClusterCull::kOutsideBox));
  HWY_ALIGN int32_t result[ClusterSet::kSoaLanes];
  for (size_t first = 0; first < n; first += lanes) {
    auto field = [&](int f) { return hn::LoadU(df, soa + static_cast<size_t>(f) * stride + first); };
    // Back-facing: the normal cone with its margin.
    const auto cutoff = field(kCutoff);
    const auto vx = hn::Sub(field(kApexX), hn::Set(df, k.cam[0]));
    const auto vy = hn::Sub(field(kApexY), hn::Set(df, k.cam[1]));
    const auto vz = hn::Sub(field(kApexZ), hn::Set(df, k.cam[2]));
    const auto len = hn::Sqrt(hn::Add(hn::Mul(vx, vx), hn::Add(hn::Mul(vy, vy), hn::Mul(vz, vz))));
    const auto dot = hn::Add(hn::Mul(vx, field(kAxisX)), hn::Add(hn::Mul(vy, field(kAxisY)), hn::Mul(vz, field(kAxisZ))));
    const auto facing_away = hn::And(hn::And(hn::Lt(cutoff, hn::Set(df, 1.0f - kConeMargin)), hn::Gt(len, zero)),
                                     hn::Ge(dot, hn::Mul(hn::Add(cutoff, hn::Set(df, kConeMargin)), len)));
    const auto back = k.cull_backfaces ? facing_away : hn::Lt(one, zero);

    // The bounding sphere's cube.
    decltype(hn::Zero(df)) px, py, pz;
    proj.Transform(field(kCenterX), field(kCenterY), field(kCenterZ), px, py, pz);
    const auto rad = field(kRadius);
    const auto z0 = hn::Sub(pz, rad), z1 = hn::Add(pz, rad);
    const auto sphere_near = hn::Not(hn::Gt(z0, z_near));
    const auto i0 = hn::Div(one, z0), i1 = hn::Div(one, z1);
    const auto ax = hn::Sub(px, rad), bx = hn::Add(px, rad), ay = hn::Sub(py, rad), by = hn::Add(py, rad);
    const auto u0 = hn::Add(hn::Mul(proj.fx, hn::Min(hn::Mul(ax, i0), hn::Mul(ax, i1))), proj.cx);
    const auto u1 = hn::Add(hn::Mul(proj.fx, hn::Max(hn::Mul(bx, i0), hn::Mul(bx, i1))), proj.cx);
    const auto v0 = hn::Add(hn::Mul(proj.fy, hn::Min(hn::Mul(ay, i0), hn::Mul(ay, i1))), proj.cy);
    const auto v1 = hn::Add(hn::Mul(proj.fy, hn::Max(hn::Mul(by, i0), hn::Mul(by, i1))), proj.cy);
    const auto sphere_out =
        hn::Or(hn::Or(hn::Lt(u1, bx0), hn::Gt(u0, bx1)), hn::Or(hn::Lt(v1, by0), hn::Gt(v0, by1)));

    // The 8 corners of the vertices' box.
    const auto lo_x = field(kBoxLoX), lo_y = field(kBoxLoY), lo_z = field(kBoxLoZ);
    const auto hi_x = field(kBoxHiX), hi_y = field(kBoxHiY), hi_z = field(kBoxHiZ);
    auto cu0 = hn::Set(df, INFINITY), cu1 = hn::Set(df, -INFINITY), cv0 = cu0, cv1 = cu1;
    auto corner_near = hn::Lt(one, zero);  // none
    for (int c = 0; c < 8; ++c) {
      decltype(hn::Zero(df)) cu, cv, qz;
      proj.Project((c & 1) ? hi_x : lo_x, (c & 2) ? hi_y : lo_y, (c & 4) ? hi_z : lo_z, cu, cv, qz);
      corner_near = hn::Or(corner_near, hn::Not(hn::Gt(qz, z_near)));
      cu0 = hn::Min(cu0, cu), cu1 = hn::Max(cu1, cu), cv0 = hn::Min(cv0, cv), cv1 = hn::Max(cv1, cv);
    }
    const auto corner_out =
        hn::Or(hn::Or(hn::Lt(cu1, bx0), hn::Gt(cu0, bx1)), hn::Or(hn::Lt(cv1, by0), hn::Gt(cv0, by1)));

    // CullCluster's order: back-facing; a near sphere keeps; the sphere outside; a near corner
    // keeps; the corners outside.
    const auto outside = hn::AndNot(sphere_near, hn::Or(sphere_out, hn::AndNot(corner_near, corner_out)));
    const auto why = hn::IfThenElse(hn::RebindMask(di, back), back_v,
                                    hn::IfThenElse(hn::RebindMask(di, outside), outside_v, keep_v));
    hn::Store(why, di, result);
    for (size_t j = 0; j < lanes && first + j < n; ++j) out[first + j] = static_cast<uint8_t>(result[j]);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace mcpose::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mcpose::render {

HWY_EXPORT(CullClustersImpl);

void CullClustersSimd(const ClusterSet& set, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                      const Eigen::Vector3f& camera_in_model, const RasterParams& params, ClusterCull* out) {
  const size_t n = set.clusters.size();
  if (n == 0) return;
  MCPOSE_CHECK(set.soa.size() == set.soa_stride * kClusterFields && set.soa_stride >= n);
  CullConstants k;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) k.R[3 * i + j] = R(i, j);
    k.t[i] = t[i], k.cam[i] = camera_in_model[i];
  }
  k.fx = params.fx, k.fy = params.fy, k.cx = params.cx, k.cy = params.cy, k.z_near = params.z_near_m;
  k.cull_backfaces = params.cull_backfaces;
  const PixelRect& box = params.box;
  k.box[0] = static_cast<float>(box.x0) - 1.0f, k.box[1] = static_cast<float>(box.x1);
  k.box[2] = static_cast<float>(box.y0) - 1.0f, k.box[3] = static_cast<float>(box.y1);
  MCPOSE_DYNAMIC_DISPATCH(CullClustersImpl)(set.soa.data(), set.soa_stride, n, k, reinterpret_cast<uint8_t*>(out));
}

}  // namespace mcpose::render
#endif  // HWY_ONCE
