#include "raplas/frontend/trace_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <type_traits>
#include <utility>

#include <xxhash.h>

#include "raplas/core/bits.hpp"
#include "raplas/util/atomic_file.hpp"
#include "raplas/util/input_file.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"

namespace raplas {

// Version 4's checksum is FNV-1a over 64 bits from the start value
// 1469598103934665603 (not FNV's usual 14695981039346656037), one byte at a
// time (about 1.3 ns a byte); version 5's XXH3-64 reads 32 bytes a step.
std::uint64_t trace_block_checksum(std::uint32_t version, const char* p, std::size_t n) {
    if (version <= 4) return fnv1a64(std::string_view(p, n), 1469598103934665603ull);
    return XXH3_64bits(p, n);
}

namespace {

constexpr char kMagic[8] = {'R', 'A', 'P', 'L', 'T', 'R', 'C', '\n'};
constexpr std::size_t kHeaderBytes = kTraceFileHeaderBytes;
// Sanity limits that keep a corrupt header from asking for absurd memory.
constexpr std::uint64_t kMaxCount = std::uint64_t(1) << 32;


// The encodings of the trace's values, over a sink's bytes(p, n).
template <class Sink>
struct Puts {
    template <class T> void put(const T& v) { sink().bytes(reinterpret_cast<const char*>(&v), sizeof(T)); }
    void put_vec(const Vec3f& v) { put(v.x); put(v.y); put(v.z); }
    void put_str(const std::string& s) {
        put(std::uint32_t(s.size()));
        sink().bytes(s.data(), s.size());
    }
    void put_mask(std::uint64_t m, std::uint32_t bytes_) {
        char b[8];
        for (std::uint32_t i = 0; i < bytes_; ++i) b[i] = char((m >> (8 * i)) & 0xff);
        sink().bytes(b, bytes_);
    }

private:
    Sink& sink() { return static_cast<Sink&>(*this); }
};

// Appends to `out`; with `hashing` it feeds the bytes to an FNV-1a hash
// instead (workload_hash).
struct Writer : Puts<Writer> {
    std::string out;
    bool hashing = false;
    std::uint64_t hash = 0xcbf29ce484222325ull;
    void bytes(const char* p, std::size_t n) {
        if (hashing) hash = fnv1a64(std::string_view(p, n), hash);
        else out.append(p, n);
    }
};

// Reads one block's payload; `base` is the payload's offset in the file (for messages).
struct Reader {
    const std::string& in;
    std::size_t pos;
    const std::string& name;
    std::uint64_t base = 0;
    InputError fail(const std::string& why) const {
        return InputError(name + ": corrupt trace at byte " + std::to_string(base + pos) + ": " + why);
    }
    void need(std::size_t n) const {
        if (in.size() - pos < n) throw fail("truncated");
    }
    template <class T> T get() {
        need(sizeof(T));
        return take<T>();
    }
    Vec3f get_vec() {
        need(12);
        return take_vec();
    }
    // The same, for bytes a need() or get_count() has checked already.
    template <class T> T take() {
        T v;
        std::memcpy(&v, in.data() + pos, sizeof(T));
        pos += sizeof(T);
        return v;
    }
    Vec3f take_vec() { float x = take<float>(), y = take<float>(), z = take<float>(); return {x, y, z}; }
    std::uint64_t take_mask(std::uint32_t bytes) {
        std::uint64_t m = 0;
        for (std::uint32_t i = 0; i < bytes; ++i) m |= std::uint64_t(static_cast<unsigned char>(in[pos + i])) << (8 * i);
        pos += bytes;
        return m;
    }
    std::string get_str() {
        auto n = get<std::uint32_t>();
        if (n > 4096) throw fail("string too long");
        need(n);
        std::string s = in.substr(pos, n);
        pos += n;
        return s;
    }
    std::uint32_t get_varint() {
        std::uint64_t v = 0;
        for (int shift = 0;; shift += 7) {
            const auto b = get<std::uint8_t>();
            v |= std::uint64_t(b & 0x7f) << shift;
            if (v > 0xffffffffull || (shift == 28 && (b & 0x80))) throw fail("run length beyond 32 bits");
            if (!(b & 0x80)) return std::uint32_t(v);
        }
    }
    std::uint64_t get_count(std::uint64_t per_item_bytes) {
        auto n = get<std::uint64_t>();
        if (n > kMaxCount || n * per_item_bytes > in.size() - pos) throw fail("count " + std::to_string(n) + " exceeds the file");
        return n;
    }
};

std::uint32_t mask_bytes(std::uint32_t n) { return (n + 7) / 8; }

}  // namespace

GroupCounts Trace::total_counts() const {
    GroupCounts c;
    for (const auto& g : groups) c += g.counts;
    return c;
}

namespace {

// From a non-const group and result, the records and hits are moved out and
// their memory freed.
template <class G, class R>
TraceGroup trace_group_impl(G& g, R& r, bool pairless) {
    TraceGroup tg;
    tg.kind = g.kind;
    tg.n = g.n;
    tg.px = g.px;
    tg.py = g.py;
    tg.origin = g.origin;
    tg.tmax = g.tmax;
    tg.row_valid = g.row_valid;
    tg.col_valid = g.col_valid;
    tg.planes = g.planes;
    tg.grid_corner = g.grid_corner;  // directions computed on use: 72 bytes instead of 12 N^2
    tg.du = g.du;
    tg.dv = g.dv;
    tg.counts = r.counts;
    if (!pairless) tg.counts.pairless = 0;  // a trace for the row-and-column reading only
    if constexpr (std::is_const_v<R>) {
        tg.sphere_hits = r.sphere_list;
        if (pairless) tg.pairless = r.pairless;
        tg.hits = r.hits;
    } else {
        tg.sphere_hits = std::move(r.sphere_list);
        if (pairless) tg.pairless = std::move(r.pairless);
        tg.hits = std::move(r.hits);
        r = GroupResult{};
        g.planes = std::vector<Plane>{};
    }
    return tg;
}

template <class FrameRef>
Trace make_trace_impl(const Scene& scene, FrameRef& f, const NumFormat& format, bool pairless) {
    Trace t = trace_header(scene, f, format, pairless);
    t.groups.reserve(f.primary.size() + f.shadow.size());
    for (std::size_t i = 0; i < f.primary.size(); ++i) t.groups.push_back(trace_group_impl(f.primary[i], f.primary_results.at(i), pairless));
    for (std::size_t i = 0; i < f.shadow.size(); ++i) t.groups.push_back(trace_group_impl(f.shadow[i], f.shadow_results.at(i), pairless));
    return t;
}

}  // namespace

Trace trace_header(const Scene& scene, const Frame& f, const NumFormat& format, bool pairless) {
    Trace t;
    t.scene_name = scene.name;
    t.format = format;
    t.width = std::uint32_t(scene.width);
    t.height = std::uint32_t(scene.height);
    t.group_size = std::uint32_t(scene.group_size);
    t.shadow_group_size = std::uint32_t(scene.shadow_group_size);
    t.tris_per_sphere = std::uint32_t(scene.tris_per_sphere);
    t.spheres = f.spheres.spheres;
    t.first_tri = f.spheres.first_tri;
    t.tri_count = f.spheres.tri_count;
    t.triangles = f.spheres.triangles;
    t.tri_mesh_index = f.spheres.tri_mesh_index;
    t.pairless = pairless;
    t.primary_groups = std::uint32_t(f.primary.size());
    return t;
}

TraceGroup trace_group(RayGroup&& g, GroupResult&& r, bool pairless) { return trace_group_impl(g, r, pairless); }

Trace make_trace(const Scene& scene, const Frame& f, const NumFormat& format, bool pairless) {
    return make_trace_impl(scene, f, format, pairless);
}

Trace make_trace(const Scene& scene, Frame&& f, const NumFormat& format, bool pairless) {
    Trace t = make_trace_impl(scene, f, format, pairless);
    f.primary_results = {};
    f.shadow_results = {};
    f.shadow = {};
    return t;
}

namespace {

// The payload (docs/TRACE.md) is the header part, the group count and the
// groups. For the workload hash, `as_workload` leaves out the scene name and
// writes the pair-less spheres only when `pairless`.
void write_header(Writer& w, const Trace& t, bool as_workload, bool pairless) {
    // Its size up front: the geometry is most of a header (29 MB for the
    // conference), and a string grown by doubling would hold its last two
    // sizes at once while it copies.
    if (!w.hashing)
        w.out.reserve(w.out.size() + 256 + t.scene_name.size() + t.format.name().size() + 24 * t.spheres.size() +
                      76 * t.triangles.size());
    if (!as_workload) w.put_str(t.scene_name);
    w.put_str(t.format.name());
    w.put(t.width); w.put(t.height);
    w.put(t.group_size); w.put(t.shadow_group_size); w.put(t.tris_per_sphere);
    w.put(std::uint32_t(pairless ? 1 : 0));
    w.put(std::uint64_t(t.spheres.size()));
    for (std::size_t i = 0; i < t.spheres.size(); ++i) {
        w.put_vec(t.spheres[i].c);
        w.put(t.spheres[i].r);
        w.put(t.first_tri[i]);
        w.put(t.tri_count[i]);
    }
    w.put(std::uint64_t(t.triangles.size()));
    for (std::size_t i = 0; i < t.triangles.size(); ++i) {
        const auto& tr = t.triangles[i];
        w.put_vec(tr.v0); w.put_vec(tr.e1); w.put_vec(tr.e2); w.put_vec(tr.n);
        w.put_vec(tr.v1); w.put_vec(tr.v2);
        w.put(t.tri_mesh_index[i]);
    }
    w.put(t.primary_groups);
}

// Gathers a group's small puts and hands them to the writer in pieces of up
// to 4 KiB: the same bytes, in one call per piece instead of one per value.
struct Batch : Puts<Batch> {
    explicit Batch(Writer& out) : w(out) {}
    Writer& w;
    std::size_t n = 0;
    char buf[4096];
    void bytes(const char* p, std::size_t k) {
        if (n + k > sizeof buf) flush();
        if (k > sizeof buf) return w.bytes(p, k);
        std::memcpy(buf + n, p, k);
        n += k;
    }
    void flush() {
        if (n) w.bytes(buf, n);
        n = 0;
    }
};

void write_group(Writer& out, const TraceGroup& g, bool as_workload, bool pairless) {
    Batch w(out);
    w.put(std::uint8_t(g.kind));
    w.put(g.n);
    w.put(g.px); w.put(g.py);
    w.put_vec(g.origin);
    w.put(g.tmax);
    w.put(g.row_valid); w.put(g.col_valid);
    for (const auto& p : g.planes) { w.put_vec(p.n); w.put(p.w); }
    for (std::uint32_t v = 0; v < g.n; ++v)
        for (std::uint32_t h = 0; h < g.n; ++h) w.put_vec(g.dir(h, v));
    w.put(g.counts.plane_tests); w.put(g.counts.sphere_hits); w.put(g.counts.rt_tests);
    w.put(as_workload && !pairless ? std::uint64_t(0) : g.counts.pairless);
    w.put(std::uint64_t(g.sphere_hits.size()));
    const std::uint32_t mb = mask_bytes(g.n);
    for (const auto& s : g.sphere_hits) { w.put(s.sphere); w.put_mask(s.rows, mb); w.put_mask(s.cols, mb); }
    if (pairless) {
        // Runs: the gap before each (from sphere 0, then from one past the
        // previous run's end) and its length - 1, as LEB128 varints (7 bits
        // a byte, low bits first; at most 5 bytes each), after the run count
        // and their byte count.
        w.put(std::uint64_t(g.pairless.size()));
        std::string runs(10 * g.pairless.size(), '\0');
        char* q = runs.data();
        auto varint = [&q](std::uint32_t v) {
            do {
                *q++ = char(std::uint8_t(v & 0x7f) | std::uint8_t(v >= 0x80 ? 0x80 : 0));
                v >>= 7;
            } while (v);
        };
        std::uint32_t next = 0;
        for (const SphereRun& r : g.pairless) {
            varint(r.first - next);
            varint(r.count - 1);
            next = r.end() + 1;
        }
        const std::size_t len = std::size_t(q - runs.data());
        w.put(std::uint64_t(len));
        w.bytes(runs.data(), len);
    }
    for (const auto& h : g.hits) { w.put(h.t); w.put(h.tri); }
    w.flush();
}

}  // namespace

// The hash covers the header part, the groups and then the group count (last,
// so that it can be computed as a stream delivers the groups).
WorkloadHasher::WorkloadHasher(const Trace& header, bool pairless) : pairless_(header.pairless && pairless) {
    Writer w;
    w.hashing = true;
    write_header(w, header, true, pairless_);
    hash_ = w.hash;
}

void WorkloadHasher::add(const TraceGroup& g) {
    Writer w;
    w.hashing = true;
    w.hash = hash_;
    write_group(w, g, true, pairless_);
    hash_ = w.hash;
    ++groups_;
}

std::string WorkloadHasher::value() const {
    Writer w;
    w.hashing = true;
    w.hash = hash_;
    w.put(groups_);
    return hex64(w.hash);
}

std::string workload_hash(const Trace& t, bool pairless) {
    WorkloadHasher h(t, pairless);
    for (const auto& g : t.groups) h.add(g);
    return h.value();
}

namespace {

// The HEAD block's payload (docs/TRACE.md): everything of the trace but its groups.
void parse_head(Reader& r, Trace& t) {
    t.scene_name = r.get_str();
    try {
        t.format = NumFormat::parse(r.get_str());
    } catch (const std::invalid_argument& e) {
        throw r.fail(e.what());
    }
    t.width = r.get<std::uint32_t>(); t.height = r.get<std::uint32_t>();
    t.group_size = r.get<std::uint32_t>(); t.shadow_group_size = r.get<std::uint32_t>();
    t.tris_per_sphere = r.get<std::uint32_t>();
    const auto pairless = r.get<std::uint32_t>();
    if (pairless > 1) throw r.fail("bad pair-less flag " + std::to_string(pairless));
    t.pairless = pairless == 1;
    auto ns = r.get_count(kTraceSphereBytes);
    t.spheres.resize(ns); t.first_tri.resize(ns); t.tri_count.resize(ns);
    for (std::size_t i = 0; i < ns; ++i) {
        t.spheres[i].c = r.get_vec();
        t.spheres[i].r = r.get<float>();
        t.first_tri[i] = r.get<std::uint32_t>();
        t.tri_count[i] = r.get<std::uint32_t>();
    }
    auto nt = r.get_count(kTraceTriangleBytes);
    t.triangles.resize(nt); t.tri_mesh_index.resize(nt);
    for (std::size_t i = 0; i < nt; ++i) {
        auto& tr = t.triangles[i];
        tr.v0 = r.get_vec(); tr.e1 = r.get_vec(); tr.e2 = r.get_vec(); tr.n = r.get_vec();
        tr.v1 = r.get_vec(); tr.v2 = r.get_vec();
        t.tri_mesh_index[i] = r.get<std::int32_t>();
    }
    // Sphere Memory must tile Triangle Memory in order.
    std::uint64_t next = 0;
    for (std::size_t i = 0; i < ns; ++i) {
        if (t.first_tri[i] != next || t.tri_count[i] == 0) throw r.fail("sphere " + std::to_string(i) + " does not follow its predecessor's triangles");
        next += t.tri_count[i];
    }
    if (next != nt) throw r.fail("spheres cover " + std::to_string(next) + " of " + std::to_string(nt) + " triangles");
    t.primary_groups = r.get<std::uint32_t>();
    if (r.pos != r.in.size()) throw r.fail("trailing bytes in the HEAD block");
}

// Group gi of trace t (whose header is read) from a GROUPS block.
// (`ns` spheres and `nt` triangles: t's, or their counts once its geometry is taken)
void parse_group(Reader& r, const Trace& t, std::size_t ns, std::size_t nt, std::uint64_t gi, TraceGroup& g) {
    g = TraceGroup{};
    auto kind = r.get<std::uint8_t>();
    if (kind > 1) throw r.fail("bad group kind");
    g.kind = GroupKind(kind);
    if ((gi < t.primary_groups) != (g.kind == GroupKind::primary)) throw r.fail("group kinds out of order");
    g.n = r.get<std::uint32_t>();
    if (g.n == 0 || g.n > 64) throw r.fail("group size " + std::to_string(g.n) + " not in 1..64");
    g.px = r.get<std::int32_t>(); g.py = r.get<std::int32_t>();
    g.origin = r.get_vec();
    g.tmax = r.get<float>();
    g.row_valid = r.get<std::uint64_t>(); g.col_valid = r.get<std::uint64_t>();
    const std::uint64_t full = g.n == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << g.n) - 1;
    if ((g.row_valid & ~full) || (g.col_valid & ~full)) throw r.fail("validity mask wider than the group");
    r.need(std::size_t(g.n) * 2 * 16);
    g.planes.resize(2 * g.n);
    for (auto& p : g.planes) { p.n = r.take_vec(); p.w = r.take<float>(); }
    r.need(std::size_t(g.n) * g.n * 12);
    g.dirs.resize(std::size_t(g.n) * g.n);
    for (auto& d : g.dirs) d = r.take_vec();
    g.counts.plane_tests = r.get<std::uint64_t>();
    g.counts.sphere_hits = r.get<std::uint64_t>();
    g.counts.rt_tests = r.get<std::uint64_t>();
    g.counts.pairless = r.get<std::uint64_t>();
    const std::uint32_t mb = mask_bytes(g.n);
    auto nh = r.get_count(4 + 2 * mb);
    g.sphere_hits.resize(nh);
    std::uint64_t rt = 0;
    std::int64_t prev = -1;
    for (auto& s : g.sphere_hits) {  // (get_count checked their bytes)
        s.sphere = r.take<std::uint32_t>();
        s.rows = r.take_mask(mb);
        s.cols = r.take_mask(mb);
        if (s.sphere >= ns || std::int64_t(s.sphere) <= prev) throw r.fail("sphere hit list out of order or range");
        if (!s.rows || !s.cols || (s.rows & ~g.row_valid) || (s.cols & ~g.col_valid)) throw r.fail("bad plane-hit mask");
        prev = s.sphere;
        rt += std::uint64_t(bit_count(s.rows)) * std::uint64_t(bit_count(s.cols)) * t.tri_count[s.sphere];
    }
    if (nh != g.counts.sphere_hits || rt != g.counts.rt_tests) throw r.fail("group counts disagree with its sphere hits");
    if (t.pairless) {
        // Runs ascending, apart, inside Sphere Memory and disjoint from the sphere hits.
        auto nr = r.get_count(2);
        const auto run_bytes = r.get<std::uint64_t>();
        if (run_bytes < 2 * nr || run_bytes > 10 * nr) throw r.fail("pair-less runs in " + std::to_string(run_bytes) + " bytes");
        const std::size_t runs_end = r.pos + run_bytes;
        g.pairless.resize(nr);
        std::uint64_t next = 0, spheres = 0;
        std::size_t hi = 0;
        for (auto& run : g.pairless) {
            const std::uint64_t first = next + r.get_varint();
            const std::uint64_t count = std::uint64_t(r.get_varint()) + 1;
            if (first + count > ns) throw r.fail("pair-less spheres out of range");
            while (hi < g.sphere_hits.size() && g.sphere_hits[hi].sphere < first) ++hi;
            if (hi < g.sphere_hits.size() && g.sphere_hits[hi].sphere < first + count)
                throw r.fail("sphere " + std::to_string(g.sphere_hits[hi].sphere) + " both hit and pair-less");
            run = {std::uint32_t(first), std::uint32_t(count)};
            spheres += count;
            next = first + count + 1;
        }
        if (r.pos != runs_end) throw r.fail("pair-less runs do not fill their " + std::to_string(run_bytes) + " bytes");
        if (spheres != g.counts.pairless) throw r.fail("group counts disagree with its pair-less spheres");
    } else if (g.counts.pairless) {
        throw r.fail("pair-less count without pair-less spheres");
    }
    r.need(std::size_t(g.n) * g.n * 12);
    g.hits.resize(std::size_t(g.n) * g.n);
    for (auto& h : g.hits) {
        h.t = r.take<double>();
        h.tri = r.take<std::int32_t>();
        if (h.tri < -1 || h.tri >= std::int64_t(nt)) throw r.fail("hit triangle out of range");
    }
}

const char* block_name(std::uint32_t kind) {
    switch (TraceBlock(kind)) {
        case TraceBlock::head: return "HEAD";
        case TraceBlock::groups: return "GROUPS";
        case TraceBlock::total: return "TOTAL";
        case TraceBlock::end: return "END";
    }
    return "unknown";
}

}  // namespace

// ---- writing ----------------------------------------------------------------

TraceWriter::TraceWriter(Sink sink) : sink_(std::move(sink)) {}

void TraceWriter::block(TraceBlock kind, const std::string& payload) {
    Writer h;
    h.put(std::uint32_t(kind));
    h.put(std::uint64_t(payload.size()));
    h.put(trace_block_checksum(kTraceVersion, payload.data(), payload.size()));
    sink_(h.out.data(), h.out.size());
    sink_(payload.data(), payload.size());
    bytes_ += h.out.size() + payload.size();
}

void TraceWriter::header(const Trace& t) {
    if (headed_) throw std::logic_error("TraceWriter: header() twice");
    Writer f;
    f.bytes(kMagic, sizeof kMagic);
    f.put(kTraceVersion);
    f.put(std::uint32_t(kHeaderBytes));
    f.put(std::uint64_t(0));
    f.put(std::uint64_t(0));
    sink_(f.out.data(), f.out.size());
    bytes_ += f.out.size();
    Writer w;
    write_header(w, t, false, t.pairless);
    block(TraceBlock::head, w.out);
    primary_ = t.primary_groups;
    pairless_ = t.pairless;
    headed_ = true;
}

void TraceWriter::group(const TraceGroup& g) {
    if (!headed_ || (groups_ == primary_ && !totalled_))
        throw std::logic_error("TraceWriter: group() before header() or, after the primary groups, before total()");
    Writer w;
    w.out.swap(pending_);
    if (pending_count_ == 0) w.put(std::uint32_t(0));  // the group count, filled in by flush()
    write_group(w, g, false, pairless_);
    w.out.swap(pending_);
    ++pending_count_;
    ++groups_;
    if (pending_count_ == kTraceBlockGroups || pending_.size() >= kTraceBlockTargetBytes || groups_ == primary_) flush();
}

void TraceWriter::flush() {
    if (!pending_count_) return;
    std::memcpy(pending_.data(), &pending_count_, sizeof pending_count_);
    block(TraceBlock::groups, pending_);
    pending_.clear();
    pending_count_ = 0;
}

void TraceWriter::total(std::uint64_t groups) {
    if (!headed_ || totalled_ || groups_ != primary_ || groups < primary_)
        throw std::logic_error("TraceWriter: total() must follow the last primary group, once");
    flush();
    Writer w;
    w.put(groups);
    block(TraceBlock::total, w.out);
    totalled_ = true;
}

void TraceWriter::finish() {
    if (!totalled_) throw std::logic_error("TraceWriter: finish() before total()");
    flush();
    Writer w;
    w.put(groups_);
    block(TraceBlock::end, w.out);
}

std::string serialize_trace(const Trace& t) {
    std::string out;
    TraceWriter w([&out](const char* p, std::size_t n) { out.append(p, n); });
    w.header(t);
    for (std::size_t i = 0; i < t.groups.size(); ++i) {
        if (i == t.primary_groups) w.total(t.groups.size());
        w.group(t.groups[i]);
    }
    if (t.groups.size() == t.primary_groups) w.total(t.groups.size());
    w.finish();
    return out;
}

void write_trace(const std::string& path, const Trace& t) { write_file_atomically(path, serialize_trace(t)); }

// ---- reading ----------------------------------------------------------------

// Where the bytes come from: read() fills up to n bytes, fewer only at the end.
struct TraceReader::Source {
    virtual ~Source() = default;
    virtual std::size_t read(char* dst, std::size_t n) = 0;
    // How many bytes are left to read, when that is known (a file, bytes in
    // memory; not a pipe).
    virtual std::optional<std::uint64_t> left() const { return std::nullopt; }
    std::uint64_t offset = 0;  // bytes read so far
};

namespace {

struct MemorySource : TraceReader::Source {
    const std::string& bytes;
    explicit MemorySource(const std::string& b) : bytes(b) {}
    std::size_t read(char* dst, std::size_t n) override {
        const std::size_t k = std::min<std::size_t>(n, bytes.size() - std::size_t(offset));
        std::memcpy(dst, bytes.data() + offset, k);
        offset += k;
        return k;
    }
    std::optional<std::uint64_t> left() const override { return bytes.size() - offset; }
};

struct FdSource : TraceReader::Source {
    int fd = -1;
    std::string path;
    std::optional<std::uint64_t> size;  // a regular file's, when opened
    ~FdSource() override {
        if (fd >= 0) ::close(fd);
    }
    std::optional<std::uint64_t> left() const override {
        if (!size || *size < offset) return std::nullopt;
        return *size - offset;
    }
    std::size_t read(char* dst, std::size_t n) override {
        std::size_t got = 0;
        while (got < n) {
            const ssize_t k = ::read(fd, dst + got, n - got);
            if (k < 0) {
                if (errno == EINTR) continue;
                throw InputError(path + ": cannot read trace: " + std::strerror(errno));
            }
            if (k == 0) break;
            got += std::size_t(k);
        }
        offset += got;
        return got;
    }
};

}  // namespace

TraceReader::TraceReader(const std::string& path) : name_(path) {
    struct stat st{};
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) throw InputError(path + ": is a directory, not a trace");
    auto src = std::make_unique<FdSource>();
    src->path = path;
    src->fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (src->fd < 0) throw InputError(path + ": cannot open trace: " + std::strerror(errno));
    if (::fstat(src->fd, &st) == 0 && S_ISREG(st.st_mode)) src->size = std::uint64_t(st.st_size);
    src_ = std::move(src);
    next_block();
}

TraceReader::TraceReader(const std::string& bytes, const std::string& name)
    : src_(std::make_unique<MemorySource>(bytes)), name_(name) {
    next_block();
}

TraceReader::~TraceReader() = default;

std::uint64_t TraceReader::bytes_read() const { return src_->offset; }

// Reads the next block (the file header first): HEAD into header_, GROUPS
// into payload_, TOTAL and END checked. False once END is read.
bool TraceReader::next_block() {
    const std::string& name = name_;
    if (blocks_ == 0) {
        char h[kHeaderBytes];
        const std::size_t n = src_->read(h, sizeof h);
        if (n < 8 + 4) {
            if (n >= 8 && std::memcmp(h, kMagic, sizeof kMagic) != 0)
                throw InputError(name + ": not a raplas trace (bad magic)");
            throw InputError(name + ": not a raplas trace (file too short)");
        }
        if (std::memcmp(h, kMagic, sizeof kMagic) != 0) throw InputError(name + ": not a raplas trace (bad magic)");
        std::uint32_t version, header;
        std::memcpy(&version, h + 8, 4);
        if (!trace_version_read(version))
            throw InputError(name + ": trace format version " + std::to_string(version) + ", this raplas reads versions " +
                             std::to_string(kTraceOldestVersion) + " to " + std::to_string(kTraceVersion) +
                             " (regenerate it with 'raplas trace')");
        version_ = version;
        if (n < sizeof h) throw InputError(name + ": not a raplas trace (file too short)");
        std::memcpy(&header, h + 12, 4);
        std::uint64_t reserved[2];
        std::memcpy(reserved, h + 16, 16);
        if (header != kHeaderBytes || reserved[0] || reserved[1]) throw InputError(name + ": corrupt trace header");
    }
    // Block header.
    const std::uint64_t at = src_->offset;
    char bh[kTraceBlockHeaderBytes];
    const std::size_t n = src_->read(bh, sizeof bh);
    if (n == 0)
        throw InputError(name + ": truncated trace (it ends after " + std::to_string(groups_read_) +
                         " groups, without its END block)");
    if (n < sizeof bh)
        throw InputError(name + ": truncated trace (it ends inside the header of block " + std::to_string(blocks_) +
                         " at byte " + std::to_string(at) + ")");
    std::uint32_t kind;
    std::uint64_t size, sum;
    std::memcpy(&kind, bh, 4);
    std::memcpy(&size, bh + 4, 8);
    std::memcpy(&sum, bh + 12, 8);
    const std::string what = std::string(block_name(kind)) + " block " + std::to_string(blocks_) + " at byte " + std::to_string(at);
    // What may come here: HEAD first; then GROUPS, TOTAL right after the
    // primary groups, END after TOTAL.
    const bool want_head = blocks_ == 0;
    const bool ok = want_head ? kind == std::uint32_t(TraceBlock::head)
                              : (kind == std::uint32_t(TraceBlock::groups) &&
                                 (total_known_ ? groups_read_ < total_ : groups_read_ < header_.primary_groups)) ||
                                    (kind == std::uint32_t(TraceBlock::total) && !total_known_ &&
                                     groups_read_ == header_.primary_groups) ||
                                    (kind == std::uint32_t(TraceBlock::end) && total_known_);
    if (!ok) {
        const std::string expected = want_head ? "HEAD"
                                     : !total_known_ ? (groups_read_ < header_.primary_groups ? "GROUPS" : "TOTAL")
                                     : groups_read_ < total_ ? "GROUPS or END" : "END";
        throw InputError(name + ": corrupt trace at byte " + std::to_string(at) + ": block kind " + std::to_string(kind) +
                         " (" + block_name(kind) + ") where the " + expected + " block belongs");
    }
    // The payload, read as it arrives (a size past the end of the stream
    // is found to be truncated, never allocated at once).
    constexpr std::size_t kChunk = std::size_t(1) << 20;
    payload_.clear();
    // (a block the source holds whole is given its room at once: the HEAD
    // block is most of a trace's header, and grown by doubling it would be
    // copied into ever larger buffers)
    if (const auto left = src_->left(); left && size <= *left) payload_.reserve(std::size_t(size));
    while (payload_.size() < size) {
        const std::size_t want = std::size_t(std::min<std::uint64_t>(kChunk, size - payload_.size()));
        const std::size_t old = payload_.size();
        payload_.resize(old + want);
        const std::size_t got = src_->read(payload_.data() + old, want);
        payload_.resize(old + got);
        if (got < want)
            throw InputError(name + ": truncated trace (" + what + ": " + std::to_string(payload_.size()) + " of " +
                             std::to_string(size) + " payload bytes)");
    }
    if (trace_block_checksum(version_, payload_.data(), payload_.size()) != sum)
        throw InputError(name + ": corrupt trace (checksum mismatch in " + what + ")");
    content_ = fnv1a64(std::string_view(bh, std::size_t(kTraceBlockHeaderBytes)), content_);
    ++blocks_;
    payload_at_ = at + kTraceBlockHeaderBytes;
    Reader r{payload_, 0, name, payload_at_};
    switch (TraceBlock(kind)) {
        case TraceBlock::head:
            parse_head(r, header_);
            spheres_ = header_.spheres.size();
            triangles_ = header_.triangles.size();
            return true;
        case TraceBlock::groups:
            left_ = r.get<std::uint32_t>();
            if (left_ == 0) throw r.fail("empty GROUPS block");
            pos_ = r.pos;
            return true;
        case TraceBlock::total: {
            total_ = r.get<std::uint64_t>();
            if (r.pos != payload_.size()) throw r.fail("TOTAL block of " + std::to_string(payload_.size()) + " bytes");
            if (total_ < header_.primary_groups || total_ > kMaxCount)
                throw r.fail("group count " + std::to_string(total_) + " with " + std::to_string(header_.primary_groups) +
                             " primary groups");
            total_known_ = true;
            return true;
        }
        case TraceBlock::end: {
            const auto g = r.get<std::uint64_t>();
            if (r.pos != payload_.size()) throw r.fail("END block of " + std::to_string(payload_.size()) + " bytes");
            if (g != groups_read_ || g != total_)
                throw r.fail("END block counts " + std::to_string(g) + " groups; the trace has " +
                             std::to_string(groups_read_) + " of the " + std::to_string(total_) + " its TOTAL block gives");
            char extra[64];
            const std::size_t more = src_->read(extra, sizeof extra);
            if (more) {
                std::uint64_t after = more;
                while (std::size_t k = src_->read(extra, sizeof extra)) after += k;
                throw InputError(name + ": corrupt trace (" + std::to_string(after) + " bytes after the END block)");
            }
            ended_ = true;
            payload_ = std::string();
            return false;
        }
    }
    return false;  // (unreachable: the kind was checked)
}

bool TraceReader::next(TraceGroup& g) {
    while (left_ == 0) {
        if (ended_ || !next_block()) return false;
    }
    Reader r{payload_, pos_, name_, payload_at_};
    parse_group(r, header_, spheres_, triangles_, groups_read_, g);
    pos_ = r.pos;
    ++groups_read_;
    if (--left_ == 0 && pos_ != payload_.size()) throw r.fail("trailing bytes in the GROUPS block");
    return true;
}

Trace TraceReader::take_header() {
    Trace t = std::exchange(header_, Trace{});
    // (what the groups' checks read stays: next_block, parse_group)
    header_.tri_count = t.tri_count;
    header_.primary_groups = t.primary_groups;
    header_.pairless = t.pairless;
    return t;
}

namespace {

// The header and every group a reader gives.
Trace read_whole(TraceReader& r) {
    Trace t = r.take_header();
    TraceGroup g;
    while (r.next(g)) t.groups.push_back(std::move(g));
    t.content_hash = r.content_hash();
    return t;
}

}  // namespace

Trace parse_trace(const std::string& bytes, const std::string& name) {
    TraceReader r(bytes, name);
    return read_whole(r);
}

Trace read_trace(const std::string& path) {
    TraceReader r(path);
    return read_whole(r);
}

}  // namespace raplas
