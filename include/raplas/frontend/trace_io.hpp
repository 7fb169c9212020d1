// The profile trace: the workload the timing model consumes. Versioned
// binary format: a file header, then blocks, each with its size and
// checksum, written and read one at a time (docs/TRACE.md); the reader
// rejects truncated, corrupt or foreign-version files with a one-line
// InputError naming the file, also when the damage is late in a stream.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "raplas/frontend/frame.hpp"

namespace raplas {

// 2: triangle records carry V1 and V2; 3: groups may carry their pair-less
// spheres; 4: blocks (written and read as a stream); 5: the blocks'
// checksums are XXH3-64 instead of FNV-1a. Version 5 is written; 4 and 5
// are read.
constexpr std::uint32_t kTraceVersion = 5;
constexpr std::uint32_t kTraceOldestVersion = 4;
constexpr bool trace_version_read(std::uint32_t v) { return v >= kTraceOldestVersion && v <= kTraceVersion; }
// A block's checksum in a trace of format `version` (4 or 5): FNV-1a 64 from
// the start value 1469598103934665603 in version 4, XXH3-64 (seed 0) from 5.
std::uint64_t trace_block_checksum(std::uint32_t version, const char* p, std::size_t n);
constexpr std::uint64_t kTraceFileHeaderBytes = 32;  // magic, version, header size, two reserved u64
constexpr std::uint64_t kTraceBlockHeaderBytes = 20;  // u32 kind, u64 payload bytes, u64 payload checksum
// Block kinds, in the order a trace holds them: HEAD, GROUPS... (the primary
// groups), TOTAL, GROUPS... (the shadow groups), END.
enum class TraceBlock : std::uint32_t { head = 1, groups = 2, total = 3, end = 4 };
// A GROUPS block holds at most this many groups, and is closed once it
// reaches this many bytes (and at the last primary group).
constexpr std::uint32_t kTraceBlockGroups = 256;
constexpr std::uint64_t kTraceBlockTargetBytes = std::uint64_t(1) << 20;
// Bytes of one sphere and one triangle record in the file (docs/TRACE.md).
constexpr std::uint64_t kTraceSphereBytes = 24;    // vec3 centre, f32 radius, u32 first, u32 count
constexpr std::uint64_t kTraceTriangleBytes = 76;  // vec3 V0, E1, E2, E, V1, V2, i32 mesh index

struct TraceGroup {
    GroupKind kind = GroupKind::primary;
    std::uint32_t n = 0;
    std::int32_t px = 0, py = 0;
    Vec3f origin;
    float tmax = 0;
    std::uint64_t row_valid = 0, col_valid = 0;
    std::vector<Plane> planes;            // 2N
    std::vector<Vec3f> dirs;              // N*N ray directions, index v*N + h; empty: from the grid below
    Vec3d grid_corner, du, dv;            // (traces built in memory) grid point (h, v) = corner + (h+.5) du + (v+.5) dv
    std::vector<SphereHitRec> sphere_hits;  // spheres with a row and a column plane hit, in stream order
    std::vector<SphereRun> pairless;        // spheres cut by row planes only or column planes only (Trace::pairless)
    GroupCounts counts;
    std::vector<Hit> hits;                // N*N nearest hits found by the front end

    // Ray (h, v): the stored direction, or the one group_ray() computes from
    // the grid (the same expression, so the same bits).
    Vec3f dir(std::uint32_t h, std::uint32_t v) const {
        if (!dirs.empty()) return dirs[std::size_t(v) * n + h];
        return to_f(grid_corner + du * (h + 0.5) + dv * (v + 0.5) - to_d(origin));
    }
    Ray ray(std::uint32_t h, std::uint32_t v) const { return Ray{origin, dir(h, v), 0.0f, tmax}; }
    bool ray_valid(std::uint32_t h, std::uint32_t v) const { return (row_valid >> v & 1) && (col_valid >> h & 1); }
};

struct Trace {
    std::string scene_name;
    NumFormat format;
    std::uint32_t width = 0, height = 0;
    std::uint32_t group_size = 0, shadow_group_size = 0, tris_per_sphere = 0;
    std::vector<Sphere> spheres;
    std::vector<std::uint32_t> first_tri, tri_count;
    std::vector<TriangleRec> triangles;
    std::vector<std::int32_t> tri_mesh_index;
    // Whether the groups carry their pair-less spheres (what a Triangle
    // Selector that keeps every sphere any plane cuts needs: a trace made
    // for icc.triangle_select = any); otherwise their lists are empty.
    bool pairless = false;
    std::uint32_t primary_groups = 0;     // groups [0, primary_groups) are primary, the rest shadow
    std::vector<TraceGroup> groups;       // issue order
    // Read from a file or pipe (read_trace): the reader's content_hash(); 0
    // for a trace made in memory.
    std::uint64_t content_hash = 0;

    GroupCounts total_counts() const;
};

// Builds the trace from a frame rendered with FrameOptions::record (and
// FrameOptions::pairless for a trace that carries the pair-less spheres).
Trace make_trace(const Scene& scene, const Frame& frame, const NumFormat& format, bool pairless = false);
// The same trace, taking the groups' records and hits out of the frame as it
// goes (the frame's groups are left empty): peak memory stays near one copy.
Trace make_trace(const Scene& scene, Frame&& frame, const NumFormat& format, bool pairless = false);

// The trace's header from a frame whose spheres and primary groups are made:
// everything but the groups.
Trace trace_header(const Scene& scene, const Frame& frame, const NumFormat& format, bool pairless);
// One group of the trace, taking the group's records and hits out of the
// group and its result (as make_trace does with a frame's).
TraceGroup trace_group(RayGroup&& g, GroupResult&& r, bool pairless);

std::string serialize_trace(const Trace& t);
// What the machine is given to do, as 16 hex digits (FNV-1a, 64 bits, over
// the trace's payload without the scene name, with the group count moved
// after the groups): the same for a trace built in memory, the same trace
// read from a file and the groups streamed from the front end; the pair-less
// spheres count only with `pairless` (icc.triangle_select = any), so a trace
// made for both readings and one made for `both` alone give the same hash
// under `both`.
std::string workload_hash(const Trace& t, bool pairless);
// The same hash group by group, in issue order: from the trace's header (its
// groups are not read), then add() each group; value() after the last.
class WorkloadHasher {
public:
    WorkloadHasher(const Trace& header, bool pairless);
    void add(const TraceGroup& g);
    std::string value() const;

private:
    bool pairless_;
    std::uint64_t hash_ = 0, groups_ = 0;
};
// Writes a trace block by block to `sink`: header() once, then group() for
// each group in issue order with total() right after the last primary group
// (before the first shadow group), then finish(). What it writes of a whole
// Trace is serialize_trace()'s bytes.
class TraceWriter {
public:
    using Sink = std::function<void(const char* data, std::size_t n)>;
    explicit TraceWriter(Sink sink);
    void header(const Trace& header);  // everything but the groups
    void group(const TraceGroup& g);
    void total(std::uint64_t groups);
    void finish();
    std::uint64_t bytes() const { return bytes_; }  // written so far
    std::uint64_t groups() const { return groups_; }

private:
    void block(TraceBlock kind, const std::string& payload);
    void flush();
    Sink sink_;
    std::string pending_;  // the open GROUPS block's groups
    std::uint32_t pending_count_ = 0;
    std::uint64_t bytes_ = 0, groups_ = 0, primary_ = 0;
    bool pairless_ = false, headed_ = false, totalled_ = false;
};

// Reads a trace block by block, from a file, a pipe or bytes in memory,
// checking each block (size, checksum, contents) as it arrives: only the
// header and the block being read are held. Throws InputError (one line,
// naming the file and, where it applies, the byte offset).
class TraceReader {
public:
    explicit TraceReader(const std::string& path);  // a file or a pipe; reads up to the HEAD block
    TraceReader(const std::string& bytes, const std::string& name);  // in memory
    ~TraceReader();
    TraceReader(const TraceReader&) = delete;
    TraceReader& operator=(const TraceReader&) = delete;

    const Trace& header() const { return header_; }  // its groups stay empty
    // The header moved out, for a reader that is only to give the groups:
    // header() then holds only what the groups' checks read (the triangles
    // per sphere, the primary group count, the pair-less flag).
    Trace take_header();
    // The next group in issue order into `g`; false once the END block is
    // read (and nothing follows it).
    bool next(TraceGroup& g);
    bool total_known() const { return total_known_; }
    std::uint64_t total() const { return total_; }
    std::uint64_t groups_read() const { return groups_read_; }
    std::uint64_t bytes_read() const;
    // A hash of every block read so far (kind, size and checksum of each,
    // so of every byte of the trace): once the END block is read, the
    // identity of the trace's content, whether it came from a file or a pipe.
    std::uint64_t content_hash() const { return content_; }

    struct Source;

private:
    bool next_block();  // false at END
    std::unique_ptr<Source> src_;
    std::string name_;
    std::uint32_t version_ = kTraceVersion;  // the file's format version
    Trace header_;
    std::size_t spheres_ = 0, triangles_ = 0;  // the header's counts
    std::string payload_;    // the current GROUPS block
    std::size_t pos_ = 0;    // next byte of it
    std::uint64_t payload_at_ = 0;  // its offset in the file
    std::uint32_t left_ = 0;  // groups of it not yet read
    std::uint64_t blocks_ = 0, groups_read_ = 0, total_ = 0;
    std::uint64_t content_ = 0xcbf29ce484222325ull;
    bool total_known_ = false, ended_ = false;
};

Trace parse_trace(const std::string& bytes, const std::string& name);
void write_trace(const std::string& path, const Trace& t);  // atomic
// The whole trace, read block by block from a file or a pipe.
Trace read_trace(const std::string& path);

}  // namespace raplas
