// Memory the front end will allocate, estimated from counts known before the
// work (docs/MEMORY.md compares the estimates with measured peak RSS).
#pragma once

#include <cstdint>
#include <vector>

#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/util/memory_budget.hpp"

namespace raplas {

// What a trace holds, known before it exists.
struct TraceShape {
    std::uint64_t spheres = 0, triangles = 0;
    std::uint64_t primary_groups = 0, shadow_groups = 0;
    std::uint32_t group_size = 16, shadow_group_size = 16;
    double primary_sphere_hits = 0, shadow_sphere_hits = 0;  // totals over the groups
    double pairless_runs = 0, pairless_spheres = 0;           // totals (traces for icc.triangle_select = any)
    bool directions = true;  // groups hold N*N ray directions (read from a file), not the ray grid
    std::uint64_t groups() const { return primary_groups + shadow_groups; }
};

// Bytes of each element in the intersectors' number format (4 or 8).
std::uint32_t format_bytes_per_value(const NumFormat& f);

// Before render_frame: bounding spheres, the per-pixel buffers and (when
// recording) the primary groups; a lower bound of the whole front end, as the
// shadow groups depend on how many pixels the primary rays hit.
std::vector<MemoryItem> frame_memory_up_front(const Scene& s, const FrameOptions& o);

// From FrameOptions::before_shadow on: the shadow phase for `lit` pixels and,
// when recording into the frame (not to a stream), the shadow groups kept. `per_group` is what a shadow group
// is expected to hold (render_frame samples some).
std::vector<MemoryItem> frame_memory_shadow(const Scene& s, const FrameOptions& o, std::uint64_t lit,
                                            const ShadowSample& per_group);

// A GroupStream's window of `groups` ray groups of size n, each with that
// many sphere-hit records and pair-less runs (FrameOptions::stream: the
// groups in memory at once).
MemoryItem stream_window_memory(std::uint64_t groups, std::uint32_t n, double sphere_hits, double pairless_runs);

// The Trace structure (make_trace / read_trace) of that shape; built by
// make_trace(scene, Frame&&), only what it adds to the frame.
MemoryItem trace_memory(const TraceShape& t, bool moved_from_frame = false);
// The serialized trace (raplas trace's file buffer).
MemoryItem trace_file_memory(const TraceShape& t);
// The shape of a frame's trace, once the primary rays are traced.
TraceShape trace_shape(const Scene& s, const Frame& f, std::uint64_t lit, const ShadowSample& per_group);
// The shape of a parsed trace.
TraceShape trace_shape(const Trace& t);
// The shape of a trace file, from its first fields and each group's counts
// (docs/TRACE.md). All zero when the file is not a trace of this version
// (the reader then says why).
TraceShape trace_file_shape(const std::string& path);

}  // namespace raplas
