#include "track/motion.h"

#include "core/check.h"
#include "core/rng.h"
#include "filter/diffuse.h"
#include "filter/resample.h"

namespace mcpose::track {

namespace {
// Substream of a tracked frame's starting samples.
constexpr uint64_t kMotionStream = 0x7EAC;
}  // namespace

filter::ParticleSet PredictSamples(const filter::ParticleSet& posterior, const MotionModel& motion, int n,
                                   uint64_t seed, uint64_t stream_id) {
  MCPOSE_CHECK(posterior.size() > 0 && n >= 0);
  filter::CdfSampler sampler;
  sampler.Build(posterior.weight, 1.0, motion.cdf_table_size);
  filter::ParticleSet samples;
  samples.Resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    Rng rng(seed, stream_id, kMotionStream, static_cast<uint64_t>(i));
    const int parent = sampler.Draw(rng.Uniform(), nullptr);
    filter::Diffuse(posterior.R_cam_obj[parent], posterior.t_cam_obj_m[parent], motion.sigma_r_rad, motion.sigma_t_m,
                    rng, &samples.R_cam_obj[i], &samples.t_cam_obj_m[i]);
    samples.box[i] = 0;
  }
  return samples;
}

}  // namespace mcpose::track
