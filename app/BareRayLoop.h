#pragma once
// The yardstick for a ray-traced pass's speed: the same rays, replayed through Embree in a bare
// parallel loop with nothing else per ray. bench records the rays of one run of the chain
// (RayScene::setRayLog) and times them here, so "pass rays/s ÷ bare rays/s" is how much of
// Embree's speed the pass keeps.
#include "foundation/RayScene.h"

#include <vector>

namespace fp::app {

/// Seconds to test every ray for occlusion on all threads: in packets of `width` (8 or 16)
/// consecutive rays (rtcOccluded8/16, as the pass groups them) or, for width 1, one at a time
/// (rtcOccluded1). With `closestHits` (packets only) each packet's blocked rays then find their
/// closest hit (rtcIntersect8/16 on those lanes), as a shadow pass's packets do when its hit
/// distance is read. `blocked` receives the number of occluded rays so the work cannot be optimised away
/// (and can be checked).
double timeBareOcclusion(const RayScene& scene, const std::vector<Ray>& rays, int width,
                         bool closestHits, uint64_t& blocked);

/// Seconds to find every ray's closest hit on all threads, one ray at a time (`width` 1:
/// rtcIntersect1, as reflections and the hybrid ask for them) or in packets of consecutive rays
/// (8 or 16: rtcIntersect8/16, as the ray-traced GI's waves do); `hits` receives how many hit.
double timeBareClosestHit(const RayScene& scene, const std::vector<Ray>& rays, int width,
                          uint64_t& hits);

}  // namespace fp::app
