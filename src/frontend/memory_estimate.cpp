#include "raplas/frontend/memory_estimate.hpp"

#include <cstring>
#include <fstream>
#include <string>

namespace raplas {

namespace {

std::string count(std::uint64_t n) {
    std::string s = std::to_string(n);
    for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(std::size_t(i), ",");
    return s;
}

std::uint64_t groups_of(int w, int h, int n) {
    return std::uint64_t((w + n - 1) / n) * std::uint64_t((h + n - 1) / n);
}

// A recorded group: the RayGroup and its GroupResult (planes, nearest hits).
double recorded_group_bytes(std::uint32_t n) {
    return double(sizeof(RayGroup) + sizeof(GroupResult)) + 2.0 * n * sizeof(Plane) + double(n) * n * sizeof(Hit);
}

// A TraceGroup: planes, nearest hits and, when read from a file, the ray
// directions (a trace built in memory keeps the ray grid instead).
double trace_group_bytes(std::uint32_t n, bool directions) {
    return double(sizeof(TraceGroup)) + 2.0 * n * sizeof(Plane) +
           double(n) * n * ((directions ? sizeof(Vec3f) : 0) + sizeof(Hit));
}

// A group in the file (docs/TRACE.md), without its sphere-hit records.
double file_group_bytes(std::uint32_t n) { return 1 + 4 + 8 + 12 + 4 + 16 + 2.0 * n * 16 + double(n) * n * (12 + 12) + 32 + 8; }
double file_hit_bytes(std::uint32_t n) { return 4 + 2.0 * ((n + 7) / 8); }

}  // namespace

std::uint32_t format_bytes_per_value(const NumFormat& f) { return f.kind == NumFormat::Kind::f32 ? 4 : 8; }

std::vector<MemoryItem> frame_memory_up_front(const Scene& s, const FrameOptions& o) {
    const std::uint64_t tris = s.mesh.triangle_count();
    const std::uint64_t spheres = (tris + std::uint64_t(s.tris_per_sphere) - 1) / std::uint64_t(s.tris_per_sphere);
    const std::uint64_t npix = std::uint64_t(s.width) * std::uint64_t(s.height);
    const double fb = format_bytes_per_value(o.format);
    std::vector<MemoryItem> items;
    // Sphere and Triangle Memory, the tracer's copies in the format, and the
    // sphere builder's working arrays (about as much again).
    const double set = double(spheres) * (sizeof(Sphere) + 8) + double(tris) * (sizeof(TriangleRec) + 8);
    items.push_back({"spheres and triangles (" + count(spheres) + " spheres, " + count(tris) + " triangles)",
                     // (the builder's arrays hold no copy of the records' V1, V2)
                     2 * set - double(tris) * 2 * sizeof(Vec3f) + double(spheres) * 4 * fb + double(tris) * 12 * fb});
    // Per pixel: primary ray, nearest hit, work counts, visibility, shading
    // terms, linear and 8-bit colour.
    items.push_back({"image " + std::to_string(s.width) + "x" + std::to_string(s.height),
                     double(npix) * (sizeof(Ray) + sizeof(Hit) + 2 * 8 + 4 + 4 + 12 + 3)});
    const std::uint64_t pg = groups_of(s.width, s.height, s.group_size);
    const std::uint32_t n = std::uint32_t(s.group_size);
    double per_group = double(sizeof(RayGroup) + sizeof(GroupResult)) + 2.0 * n * sizeof(Plane) + double(n) * n * sizeof(Hit);
    if (o.stream) per_group = double(sizeof(RayGroup)) + sizeof(GroupCounts) + 8;  // planes and results go to the stream
    if (o.per_ray) per_group += double(n) * n * 8;
    items.push_back({"primary ray groups (" + count(pg) + ")", double(pg) * per_group});
    if (o.stream) {
        // The trace header's copy of the geometry.
        items.push_back({"stream header", double(spheres) * (sizeof(Sphere) + 8) + double(tris) * (sizeof(TriangleRec) + 4)});
    }
    return items;
}

std::vector<MemoryItem> frame_memory_shadow(const Scene& s, const FrameOptions& o, std::uint64_t lit,
                                            const ShadowSample& per_group) {
    const std::uint64_t npix = std::uint64_t(s.width) * std::uint64_t(s.height);
    std::vector<MemoryItem> items;
    // The shadow phase's arrays, one slot per lit pixel, and the shading term.
    const bool kept = o.record && !o.stream;
    items.push_back({"shadow phase (" + count(lit) + " lit pixels)",
                     double(lit) * (8 + (kept ? sizeof(RayGroup) + sizeof(GroupResult) : 0) + sizeof(GroupCounts)) +
                         double(npix) * 4});
    if (kept) {
        const std::uint32_t ns = std::uint32_t(s.shadow_group_size);
        items.push_back({"shadow ray groups recorded (" + count(lit) + ")",
                         double(lit) * (recorded_group_bytes(ns) - sizeof(RayGroup) - sizeof(GroupResult) +
                                        per_group.sphere_hits * sizeof(SphereHitRec) +  // exact-size lists
                                        (o.pairless ? per_group.pairless_runs * sizeof(SphereRun) : 0.0))});
    }
    return items;
}

MemoryItem stream_window_memory(std::uint64_t groups, std::uint32_t n, double sphere_hits, double pairless_runs) {
    return {"stream window (" + count(groups) + " ray groups)",
            double(groups) * (trace_group_bytes(n, false) + sphere_hits * sizeof(SphereHitRec) +
                              pairless_runs * sizeof(SphereRun))};
}

TraceShape trace_shape(const Scene& s, const Frame& f, std::uint64_t lit, const ShadowSample& per_group) {
    TraceShape t;
    t.spheres = f.spheres.sphere_count();
    t.triangles = f.spheres.triangle_count();
    t.primary_groups = f.primary.size();
    t.shadow_groups = lit;
    t.group_size = std::uint32_t(s.group_size);
    t.shadow_group_size = std::uint32_t(s.shadow_group_size);
    t.primary_sphere_hits = double(f.primary_counts.sphere_hits);
    t.shadow_sphere_hits = double(lit) * per_group.sphere_hits;
    t.pairless_runs = double(f.primary_pairless_runs) + double(lit) * per_group.pairless_runs;
    t.pairless_spheres = double(f.primary_counts.pairless) + double(lit) * per_group.pairless_spheres;
    t.directions = false;  // make_trace keeps the ray grid
    return t;
}

TraceShape trace_shape(const Trace& tr) {
    TraceShape t;
    t.spheres = tr.spheres.size();
    t.triangles = tr.triangles.size();
    t.primary_groups = tr.primary_groups;
    t.shadow_groups = tr.groups.size() - tr.primary_groups;
    t.group_size = tr.group_size;
    t.shadow_group_size = tr.shadow_group_size;
    t.directions = false;
    for (const auto& g : tr.groups) t.directions = t.directions || !g.dirs.empty();
    for (std::size_t i = 0; i < tr.groups.size(); ++i) {
        (i < tr.primary_groups ? t.primary_sphere_hits : t.shadow_sphere_hits) += double(tr.groups[i].sphere_hits.size());
        t.pairless_runs += double(tr.groups[i].pairless.size());
        t.pairless_spheres += double(tr.groups[i].counts.pairless);
    }
    return t;
}

TraceShape trace_file_shape(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    const std::streamoff size = in.tellg();
    in.seekg(0);
    auto get = [&](auto& v) { return bool(in.read(reinterpret_cast<char*>(&v), sizeof v)); };
    auto skip = [&](std::uint64_t n) { return n <= std::uint64_t(size) && bool(in.seekg(std::streamoff(n), std::ios::cur)); };
    auto skip_str = [&] {
        std::uint32_t n = 0;
        return get(n) && n <= 4096 && skip(n);
    };
    char magic[8];
    std::uint32_t version = 0, header = 0, dims[5] = {}, pairless = 0;
    std::uint64_t reserved[2] = {}, spheres = 0, tris = 0, groups = 0, read = 0;
    std::uint32_t primary = 0;
    bool headed = false, totalled = false;
    TraceShape t;
    if (!in || size < 32 || !in.read(magic, 8) || std::memcmp(magic, "RAPLTRC\n", 8) != 0 || !get(version) ||
        !trace_version_read(version) || !get(header) || !get(reserved[0]) || !get(reserved[1]))
        return t;
    TraceShape g;
    // Block by block (docs/TRACE.md): the HEAD's sizes, each group's counts
    // (its records skipped), the TOTAL's group count.
    for (;;) {
        std::uint32_t kind = 0;
        std::uint64_t bytes = 0, sum = 0;
        if (!get(kind) || !get(bytes) || !get(sum) || bytes > std::uint64_t(size)) return t;
        const std::streamoff end = in.tellg() + std::streamoff(bytes);
        if (kind == std::uint32_t(TraceBlock::head)) {
            if (!skip_str() || !skip_str()) return t;
            for (auto& d : dims)
                if (!get(d)) return t;
            if (!get(pairless) || !get(spheres) || spheres > std::uint64_t(size) / kTraceSphereBytes ||
                !skip(spheres * kTraceSphereBytes) || !get(tris) || tris > std::uint64_t(size) / kTraceTriangleBytes ||
                !skip(tris * kTraceTriangleBytes) || !get(primary))
                return t;
            headed = true;
        } else if (kind == std::uint32_t(TraceBlock::groups) && headed) {
            std::uint32_t count = 0;
            if (!get(count)) return t;
            for (std::uint32_t i = 0; i < count; ++i, ++read) {
                std::uint8_t gkind = 0;
                std::uint32_t gn = 0;
                std::uint64_t counts[4] = {}, nh = 0, nr = 0, rb = 0;
                if (!get(gkind) || !get(gn) || gn < 1 || gn > 64 ||
                    !skip(4 + 4 + 12 + 4 + 16 + 32 * std::uint64_t(gn) + 12 * std::uint64_t(gn) * gn))
                    return t;
                for (auto& c : counts)
                    if (!get(c)) return t;
                if (!get(nh) || nh > std::uint64_t(size) || !skip(nh * (4 + 2 * ((gn + 7) / 8)))) return t;
                if (pairless && (!get(nr) || !get(rb) || !skip(rb))) return t;
                if (!skip(12 * std::uint64_t(gn) * gn)) return t;
                (read < primary ? g.primary_sphere_hits : g.shadow_sphere_hits) += double(nh);
                g.pairless_runs += double(nr);
                g.pairless_spheres += double(counts[3]);
            }
        } else if (kind == std::uint32_t(TraceBlock::total) && headed) {
            if (!get(groups) || groups < primary || groups > std::uint64_t(size)) return t;
            totalled = true;
        } else if (kind == std::uint32_t(TraceBlock::end) && totalled) {
            break;
        } else {
            return t;
        }
        if (!in.seekg(end)) return t;
    }
    const std::uint32_t n = dims[2], ns = dims[3];  // width, height, group size, shadow group size, K
    if (n < 1 || n > 64 || ns < 1 || ns > 64 || read != groups) return t;
    g.spheres = spheres;
    g.triangles = tris;
    g.primary_groups = primary;
    g.shadow_groups = groups - primary;
    g.group_size = n;
    g.shadow_group_size = ns;
    return g;
}

MemoryItem trace_memory(const TraceShape& t, bool moved_from_frame) {
    const double geometry = double(t.spheres) * (sizeof(Sphere) + 8) + double(t.triangles) * (sizeof(TriangleRec) + 4);
    if (moved_from_frame) {
        // make_trace(scene, Frame&&): the groups' planes, nearest hits and
        // sphere-hit lists change owner (counted with the frame); new are the
        // group records and, as the primary groups' lists are not in the
        // frame's estimate, those lists.
        const double b = geometry + double(t.groups()) * sizeof(TraceGroup) + t.primary_sphere_hits * sizeof(SphereHitRec);
        return {"trace (" + count(t.groups()) + " ray groups, moved from the frame)", b};
    }
    const double b = geometry + double(t.primary_groups) * trace_group_bytes(t.group_size, t.directions) +
                     double(t.shadow_groups) * trace_group_bytes(t.shadow_group_size, t.directions) +
                     (t.primary_sphere_hits + t.shadow_sphere_hits) * sizeof(SphereHitRec) +
                     t.pairless_runs * sizeof(SphereRun);
    return {"trace (" + count(t.groups()) + " ray groups)", b};
}

MemoryItem trace_file_memory(const TraceShape& t) {
    // (pair-less runs: two varints of one or two bytes each, and 16 bytes of counts per group)
    const double b = 64 + double(t.spheres) * kTraceSphereBytes + double(t.triangles) * kTraceTriangleBytes +
                     double(t.primary_groups) * file_group_bytes(t.group_size) +
                     double(t.shadow_groups) * file_group_bytes(t.shadow_group_size) +
                     t.primary_sphere_hits * file_hit_bytes(t.group_size) +
                     t.shadow_sphere_hits * file_hit_bytes(t.shadow_group_size) +
                     (t.pairless_runs > 0 ? 2.5 * t.pairless_runs + 16.0 * double(t.groups()) : 0.0);
    return {"trace file buffer", b};
}

}  // namespace raplas
