// Embree 3 as the independent reference tracer (tests and benchmarks only):
// a mesh as an Embree geometry; one raplas Ray as an RTCRay, its nearest hit
// and its occlusion test.
#pragma once

#include <embree3/rtcore.h>

#include <limits>

#include "raplas/core/intersect.hpp"
#include "raplas/scene/mesh.hpp"

namespace raplas {

// The mesh's vertices into an Embree vertex buffer of 16-byte stride (Embree
// may read 16 bytes at the last vertex).
inline void fill_embree_vertices(float* vb, const Mesh& mesh) {
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        vb[4 * i + 0] = mesh.vertices[i].x;
        vb[4 * i + 1] = mesh.vertices[i].y;
        vb[4 * i + 2] = mesh.vertices[i].z;
        vb[4 * i + 3] = 0.0f;
    }
}

// A triangle geometry of the mesh, both buffers filled, triangles in mesh
// order (primID = mesh triangle index); not committed. Its vertex buffer goes
// to *vertices when asked for (to be refilled for a refit).
inline RTCGeometry new_embree_mesh(RTCDevice device, const Mesh& mesh, float** vertices = nullptr) {
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           4 * sizeof(float), mesh.vertices.size()));
    fill_embree_vertices(vb, mesh);
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), mesh.triangles.size()));
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
        for (std::size_t k = 0; k < 3; ++k) ib[3 * i + k] = mesh.triangles[i][k];
    if (vertices) *vertices = vb;
    return geom;
}

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
