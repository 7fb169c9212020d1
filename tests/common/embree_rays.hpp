// Embree 3 as the independent reference tracer (tests and benchmarks only):
// one raplas Ray as an RTCRay, its nearest hit and its occlusion test.
#pragma once

#include <embree3/rtcore.h>

#include <limits>

#include "raplas/core/intersect.hpp"

namespace raplas {

// The ray o + t d for t in (0, tfar].
inline void set_embree_ray(RTCRay& ray, const Ray& r, float tfar) {
    ray.org_x = r.o.x;
    ray.org_y = r.o.y;
    ray.org_z = r.o.z;
    ray.tnear = 0.0f;
    ray.dir_x = r.d.x;
    ray.dir_y = r.d.y;
    ray.dir_z = r.d.z;
    ray.time = 0.0f;
    ray.tfar = tfar;
    ray.mask = 0xffffffffu;
    ray.id = 0;
    ray.flags = 0;
}

// The nearest hit of `r` in (0, inf) (rtcIntersect1); hit.geomID is
// RTC_INVALID_GEOMETRY_ID for a miss.
inline RTCRayHit embree_nearest(RTCScene scene, const Ray& r) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    set_embree_ray(rh.ray, r, std::numeric_limits<float>::infinity());
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &ctx, &rh);
    return rh;
}

// Anything along `r` in (0, r.tmax] (rtcOccluded1)?
inline bool embree_occluded(RTCScene scene, const Ray& r) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay ray;
    set_embree_ray(ray, r, r.tmax);
    rtcOccluded1(scene, &ctx, &ray);
    return ray.tfar < 0;  // set to -inf when occluded
}

}  // namespace raplas
