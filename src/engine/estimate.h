// One object class's estimate in one image: the filter, then (with colour) twin resolution,
// then refinement. Estimator::Estimate and the tracker both run it.
#pragma once

#include <cstdint>
#include <span>

#include "engine/context.h"
#include "filter/particles.h"
#include "mcpose/estimator.h"

namespace mcpose::engine {

// Also gives, in *posterior when not null, the filter's last weighted generation moved by the
// correction that twin resolution and refinement applied to the answer (the same rigid motion
// for every sample), so the samples stay around the pose returned.
StatusOr<ObjectEstimate> EstimateObject(Context& context, const Intrinsics& K, const DepthImage& depth,
                                        const ColourImage* colour, const Mesh& mesh, std::span<const Detection> boxes,
                                        uint64_t stream_id, filter::ParticleSet* posterior = nullptr);

// Moves every sample by the rigid motion that takes pose `from` to pose `to` (camera frame):
// T_i' = (T_to T_from^-1) T_i.
void MoveSamples(const SE3& from, const SE3& to, filter::ParticleSet* samples);

}  // namespace mcpose::engine
