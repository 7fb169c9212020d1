#include "raplas/frontend/trace_io.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "raplas/util/atomic_file.hpp"
#include "raplas/util/input_file.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"

namespace raplas {

namespace {

constexpr char kMagic[8] = {'R', 'A', 'P', 'L', 'T', 'R', 'C', '\n'};
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8 + 8;
// Sanity limits that keep a corrupt header from asking for absurd memory.
constexpr std::uint64_t kMaxCount = std::uint64_t(1) << 32;

// The trace format's checksum: FNV-1a over 64 bits from the start value
// 1469598103934665603 (not FNV's usual 14695981039346656037); part of the
// format, so every trace ever written keeps verifying.
std::uint64_t fnv1a(const char* p, std::size_t n) { return fnv1a64(std::string_view(p, n), 1469598103934665603ull); }

// Appends to `out`; with `count_only` it only adds up the bytes (`size`), so
// that the whole file can be written into one buffer of the exact size; with
// `hashing` it feeds the bytes to an FNV-1a hash instead (workload_hash).
struct Writer {
    std::string out;
    bool count_only = false;
    bool hashing = false;
    std::uint64_t hash = 0xcbf29ce484222325ull;
    std::size_t size = 0;
    void bytes(const char* p, std::size_t n) {
        size += n;
        if (hashing) hash = fnv1a64(std::string_view(p, n), hash);
        else if (!count_only) out.append(p, n);
    }
    template <class T> void put(const T& v) { bytes(reinterpret_cast<const char*>(&v), sizeof(T)); }
    void put_vec(const Vec3f& v) { put(v.x); put(v.y); put(v.z); }
    void put_str(const std::string& s) {
        put(std::uint32_t(s.size()));
        bytes(s.data(), s.size());
    }
    void put_varint(std::uint32_t v) {  // LEB128: 7 bits a byte, low bits first
        do {
            const std::uint8_t b = std::uint8_t(v & 0x7f) | std::uint8_t(v >= 0x80 ? 0x80 : 0);
            put(b);
            v >>= 7;
        } while (v);
    }
    void put_mask(std::uint64_t m, std::uint32_t bytes_) {
        char b[8];
        for (std::uint32_t i = 0; i < bytes_; ++i) b[i] = char((m >> (8 * i)) & 0xff);
        bytes(b, bytes_);
    }
};

struct Reader {
    const std::string& in;
    std::size_t pos;
    const std::string& name;
    InputError fail(const std::string& why) const {
        return InputError(name + ": corrupt trace at byte " + std::to_string(pos) + ": " + why);
    }
    void need(std::size_t n) const {
        if (in.size() - pos < n) throw fail("truncated");
    }
    template <class T> T get() {
        need(sizeof(T));
        T v;
        std::memcpy(&v, in.data() + pos, sizeof(T));
        pos += sizeof(T);
        return v;
    }
    Vec3f get_vec() { float x = get<float>(), y = get<float>(), z = get<float>(); return {x, y, z}; }
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
    std::uint64_t get_mask(std::uint32_t bytes) {
        need(bytes);
        std::uint64_t m = 0;
        for (std::uint32_t i = 0; i < bytes; ++i) m |= std::uint64_t(static_cast<unsigned char>(in[pos + i])) << (8 * i);
        pos += bytes;
        return m;
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

void write_group(Writer& w, const TraceGroup& g, bool as_workload, bool pairless) {
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
        // previous run's end) and its length - 1, as LEB128 varints,
        // after the run count and their byte count.
        w.put(std::uint64_t(g.pairless.size()));
        Writer runs;
        std::uint32_t next = 0;
        for (const SphereRun& r : g.pairless) {
            runs.put_varint(r.first - next);
            runs.put_varint(r.count - 1);
            next = r.end() + 1;
        }
        w.put(std::uint64_t(runs.out.size()));
        w.bytes(runs.out.data(), runs.out.size());
    }
    for (const auto& h : g.hits) { w.put(h.t); w.put(h.tri); }
}

void write_payload(Writer& w, const Trace& t) {
    write_header(w, t, false, t.pairless);
    w.put(std::uint64_t(t.groups.size()));
    for (const auto& g : t.groups) write_group(w, g, false, t.pairless);
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

std::string serialize_trace(const Trace& t) {
    Writer count;
    count.count_only = true;
    write_payload(count, t);
    // One buffer: the header's place first, filled in once the payload is there.
    Writer w;
    w.out.reserve(kHeaderBytes + count.size);
    w.out.append(kMagic, sizeof kMagic);
    w.out.append(kHeaderBytes - sizeof kMagic, '\0');
    write_payload(w, t);
    Writer hdr;
    hdr.put(kTraceVersion);
    hdr.put(std::uint32_t(kHeaderBytes));
    hdr.put(std::uint64_t(w.out.size() - kHeaderBytes));
    hdr.put(fnv1a(w.out.data() + kHeaderBytes, w.out.size() - kHeaderBytes));
    w.out.replace(sizeof kMagic, hdr.out.size(), hdr.out);
    return std::move(w.out);
}

Trace parse_trace(const std::string& bytes, const std::string& name) {
    if (bytes.size() < kHeaderBytes) throw InputError(name + ": not a raplas trace (file too short)");
    if (std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) throw InputError(name + ": not a raplas trace (bad magic)");
    Reader r{bytes, sizeof kMagic, name};
    auto version = r.get<std::uint32_t>();
    if (version != kTraceVersion)
        throw InputError(name + ": trace format version " + std::to_string(version) + ", this raplas reads version " +
                         std::to_string(kTraceVersion) + " (regenerate it with 'raplas trace')");
    auto header = r.get<std::uint32_t>();
    auto payload = r.get<std::uint64_t>();
    auto sum = r.get<std::uint64_t>();
    if (header != kHeaderBytes) throw InputError(name + ": corrupt trace header");
    if (bytes.size() - kHeaderBytes < payload)
        throw InputError(name + ": truncated trace (" + std::to_string(bytes.size() - kHeaderBytes) + " of " +
                         std::to_string(payload) + " payload bytes)");
    if (bytes.size() - kHeaderBytes > payload)
        throw InputError(name + ": corrupt trace (" + std::to_string(bytes.size() - kHeaderBytes - payload) +
                         " bytes after the " + std::to_string(payload) + "-byte payload)");
    if (fnv1a(bytes.data() + kHeaderBytes, payload) != sum) throw InputError(name + ": corrupt trace (checksum mismatch)");

    Trace t;
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
    auto ng = r.get_count(32);
    if (t.primary_groups > ng) throw r.fail("more primary groups than groups");
    t.groups.resize(ng);
    for (std::size_t gi = 0; gi < ng; ++gi) {
        TraceGroup& g = t.groups[gi];
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
        for (auto& p : g.planes) { p.n = r.get_vec(); p.w = r.get<float>(); }
        r.need(std::size_t(g.n) * g.n * 12);
        g.dirs.resize(std::size_t(g.n) * g.n);
        for (auto& d : g.dirs) d = r.get_vec();
        g.counts.plane_tests = r.get<std::uint64_t>();
        g.counts.sphere_hits = r.get<std::uint64_t>();
        g.counts.rt_tests = r.get<std::uint64_t>();
        g.counts.pairless = r.get<std::uint64_t>();
        const std::uint32_t mb = mask_bytes(g.n);
        auto nh = r.get_count(4 + 2 * mb);
        g.sphere_hits.resize(nh);
        std::uint64_t rt = 0;
        std::int64_t prev = -1;
        for (auto& s : g.sphere_hits) {
            s.sphere = r.get<std::uint32_t>();
            s.rows = r.get_mask(mb);
            s.cols = r.get_mask(mb);
            if (s.sphere >= ns || std::int64_t(s.sphere) <= prev) throw r.fail("sphere hit list out of order or range");
            if (!s.rows || !s.cols || (s.rows & ~g.row_valid) || (s.cols & ~g.col_valid)) throw r.fail("bad plane-hit mask");
            prev = s.sphere;
            rt += std::uint64_t(__builtin_popcountll(s.rows)) * std::uint64_t(__builtin_popcountll(s.cols)) * t.tri_count[s.sphere];
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
            h.t = r.get<double>();
            h.tri = r.get<std::int32_t>();
            if (h.tri < -1 || h.tri >= std::int64_t(nt)) throw r.fail("hit triangle out of range");
        }
    }
    if (r.pos != bytes.size()) throw r.fail("trailing bytes");
    return t;
}

void write_trace(const std::string& path, const Trace& t) { write_file_atomically(path, serialize_trace(t)); }

Trace read_trace(const std::string& path) {
    // A regular file is read straight into one buffer of its size; a pipe
    // (`--trace <(...)`, /dev/stdin) to its end, the memory budget checked
    // each time the buffer has doubled.
    TextInput kind{"trace", "a", "trace file", 1.0};
    kind.text = false;
    return parse_trace(read_text_input(path, kind), path);
}

}  // namespace raplas
