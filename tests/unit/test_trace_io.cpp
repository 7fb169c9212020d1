// The profile trace: make_trace from a recorded frame, the binary format's
// round trip, and rejection of truncated, corrupt and foreign files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <thread>
#include <sstream>
#include <string>
#include <vector>

#include <xxhash.h>

#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/memory_estimate.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/scene/scene.hpp"
#include "raplas/util/error.hpp"
#include "temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using namespace raplas;
using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr std::size_t kHeader = 32;  // magic 8 + version 4 + header size 4 + two reserved u64

Scene small_scene() {
    SceneRequest req;
    req.overrides = {"builtin_detail=0", "image.width=20", "image.height=12", "groups.size=8", "groups.shadow_size=3",
                     "spheres.triangles_per_sphere=3"};
    return load_scene(req);
}

struct Rendered {
    Scene scene;
    Frame frame;
    Trace trace;
    std::string bytes;
};

// One render shared by every test here (it is deterministic).
const Rendered& rendered() {
    static const Rendered r = [] {
        Rendered x;
        x.scene = small_scene();
        FrameOptions fo;
        fo.format = NumFormat::parse("fp1-8-15");
        fo.threads = 2;
        fo.record = true;
        fo.pairless = true;  // a trace for both readings: every test here covers the pair-less runs too
        x.frame = render_frame(x.scene, fo);
        x.trace = make_trace(x.scene, x.frame, fo.format, true);
        x.bytes = serialize_trace(x.trace);
        return x;
    }();
    return r;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(const Vec3f& a, const Vec3f& b) { return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z); }

void expect_same_trace(const Trace& a, const Trace& b) {
    EXPECT_EQ(a.scene_name, b.scene_name);
    EXPECT_EQ(a.format, b.format);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.group_size, b.group_size);
    EXPECT_EQ(a.shadow_group_size, b.shadow_group_size);
    EXPECT_EQ(a.tris_per_sphere, b.tris_per_sphere);
    ASSERT_EQ(a.spheres.size(), b.spheres.size());
    for (std::size_t i = 0; i < a.spheres.size(); ++i) {
        ASSERT_TRUE(same(a.spheres[i].c, b.spheres[i].c) && same_bits(a.spheres[i].r, b.spheres[i].r))
            << "sphere " << i;
    }
    EXPECT_EQ(a.first_tri, b.first_tri);
    EXPECT_EQ(a.tri_count, b.tri_count);
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    for (std::size_t i = 0; i < a.triangles.size(); ++i) {
        const auto &x = a.triangles[i], &y = b.triangles[i];
        ASSERT_TRUE(same(x.v0, y.v0) && same(x.e1, y.e1) && same(x.e2, y.e2) && same(x.n, y.n) && same(x.v1, y.v1) &&
                    same(x.v2, y.v2))
            << "triangle " << i;
    }
    EXPECT_EQ(a.tri_mesh_index, b.tri_mesh_index);
    EXPECT_EQ(a.pairless, b.pairless);
    EXPECT_EQ(a.primary_groups, b.primary_groups);
    ASSERT_EQ(a.groups.size(), b.groups.size());
    for (std::size_t gi = 0; gi < a.groups.size(); ++gi) {
        const TraceGroup &g = a.groups[gi], &h = b.groups[gi];
        ASSERT_EQ(g.kind, h.kind) << gi;
        ASSERT_EQ(g.n, h.n) << gi;
        ASSERT_EQ(g.px, h.px) << gi;
        ASSERT_EQ(g.py, h.py) << gi;
        ASSERT_TRUE(same(g.origin, h.origin)) << gi;
        ASSERT_TRUE(same_bits(g.tmax, h.tmax)) << gi;
        ASSERT_EQ(g.row_valid, h.row_valid) << gi;
        ASSERT_EQ(g.col_valid, h.col_valid) << gi;
        ASSERT_EQ(g.planes.size(), h.planes.size()) << gi;
        for (std::size_t k = 0; k < g.planes.size(); ++k)
            ASSERT_TRUE(same(g.planes[k].n, h.planes[k].n) && same_bits(g.planes[k].w, h.planes[k].w)) << gi;
        for (std::uint32_t v = 0; v < g.n; ++v)
            for (std::uint32_t hh = 0; hh < g.n; ++hh) ASSERT_TRUE(same(g.dir(hh, v), h.dir(hh, v))) << gi;
        ASSERT_EQ(g.sphere_hits.size(), h.sphere_hits.size()) << gi;
        for (std::size_t k = 0; k < g.sphere_hits.size(); ++k) {
            ASSERT_EQ(g.sphere_hits[k].sphere, h.sphere_hits[k].sphere) << gi;
            ASSERT_EQ(std::uint64_t{g.sphere_hits[k].rows}, std::uint64_t{h.sphere_hits[k].rows}) << gi;
            ASSERT_EQ(std::uint64_t{g.sphere_hits[k].cols}, std::uint64_t{h.sphere_hits[k].cols}) << gi;
        }
        ASSERT_EQ(g.counts.plane_tests, h.counts.plane_tests) << gi;
        ASSERT_EQ(g.counts.sphere_hits, h.counts.sphere_hits) << gi;
        ASSERT_EQ(g.counts.rt_tests, h.counts.rt_tests) << gi;
        ASSERT_EQ(g.counts.pairless, h.counts.pairless) << gi;
        ASSERT_EQ(g.pairless, h.pairless) << gi;
        ASSERT_EQ(g.hits.size(), h.hits.size()) << gi;
        for (std::size_t k = 0; k < g.hits.size(); ++k) {
            ASSERT_EQ(g.hits[k].tri, h.hits[k].tri) << gi;
            ASSERT_TRUE(same_bits(g.hits[k].t, h.hits[k].t)) << gi;
        }
    }
}

std::string parse_error(const std::string& bytes, const std::string& name) {
    try {
        parse_trace(bytes, name);
    } catch (const InputError& e) {
        return e.what();
    } catch (const std::exception& e) {
        return std::string("not an InputError: ") + e.what();
    }
    return "";
}

// Version 4's block checksum, written out here: FNV-1a 64 from 1469598103934665603.
std::uint64_t fnv1a(const std::string& s, std::size_t from, std::size_t to = std::string::npos) {
    std::uint64_t h = 1469598103934665603ull;
    for (std::size_t i = from; i < std::min(to, s.size()); ++i) {
        h ^= static_cast<unsigned char>(s[i]);
        h *= 1099511628211ull;
    }
    return h;
}
// Version 5's: XXH3-64, seed 0, from the library itself.
std::uint64_t xxh3(const std::string& s, std::size_t from, std::size_t to) {
    return XXH3_64bits(s.data() + from, std::min(to, s.size()) - from);
}

// The blocks of a trace file as written (docs/TRACE.md): kind, offset of
// the payload, its size, whether its checksum holds, and (GROUPS) its group count.
struct BlockInfo {
    std::uint32_t kind = 0;
    std::size_t at = 0;
    std::uint64_t size = 0;
    bool sum_ok = false;
    std::uint32_t groups = 0;
};
std::vector<BlockInfo> blocks_of(const std::string& b) {
    std::vector<BlockInfo> out;
    for (std::size_t at = kHeader; at + kTraceBlockHeaderBytes <= b.size();) {
        BlockInfo x;
        std::uint64_t sum;
        std::memcpy(&x.kind, &b[at], 4);
        std::memcpy(&x.size, &b[at + 4], 8);
        std::memcpy(&sum, &b[at + 12], 8);
        x.at = at + kTraceBlockHeaderBytes;
        if (x.at + x.size > b.size()) break;
        x.sum_ok = sum == xxh3(b, x.at, x.at + x.size);
        if (x.kind == std::uint32_t(TraceBlock::groups)) std::memcpy(&x.groups, &b[x.at], 4);
        out.push_back(x);
        at = x.at + x.size;
    }
    return out;
}

// Trace bytes of version 5 made version 4: the version field, and every
// block's checksum FNV-1a.
std::string as_version4(const std::string& b) {
    std::string v4 = b;
    const std::uint32_t four = 4;
    std::memcpy(&v4[8], &four, 4);
    for (const BlockInfo& x : blocks_of(b)) {
        const std::uint64_t sum = fnv1a(b, x.at, x.at + x.size);
        std::memcpy(&v4[x.at - 8], &sum, 8);
    }
    return v4;
}

// The rendered trace with its shadow groups repeated `times` times: enough
// groups for several GROUPS blocks.
Trace longer_trace(int times) {
    Trace t = rendered().trace;
    const std::vector<TraceGroup> shadow(t.groups.begin() + t.primary_groups, t.groups.end());
    for (int i = 1; i < times; ++i) t.groups.insert(t.groups.end(), shadow.begin(), shadow.end());
    return t;
}

TEST(TraceIo, MakeTraceReflectsTheFrame) {
    const Rendered& r = rendered();
    const Trace& t = r.trace;
    const Frame& f = r.frame;
    EXPECT_EQ(t.scene_name, "builtin");
    EXPECT_EQ(t.format.name(), "fp1-8-15");
    EXPECT_EQ(t.width, 20u);
    EXPECT_EQ(t.height, 12u);
    EXPECT_EQ(t.group_size, 8u);
    EXPECT_EQ(t.shadow_group_size, 3u);
    EXPECT_EQ(t.tris_per_sphere, 3u);
    EXPECT_EQ(t.spheres.size(), f.spheres.sphere_count());
    EXPECT_EQ(t.triangles.size(), f.spheres.triangle_count());
    // 20x12 in 8x8 tiles: 3 x 2 primary groups, then one shadow group per hit pixel
    ASSERT_EQ(t.primary_groups, 6u);
    std::size_t hit_pixels = 0;
    for (const Hit& h : f.pixel_hit) hit_pixels += h.tri >= 0;
    ASSERT_GT(hit_pixels, 0u);
    ASSERT_EQ(t.groups.size(), 6u + hit_pixels);
    ASSERT_EQ(f.shadow_group_count, hit_pixels);
    for (std::size_t i = 0; i < t.groups.size(); ++i) {
        const TraceGroup& g = t.groups[i];
        const bool primary = i < t.primary_groups;
        const RayGroup& src = primary ? f.primary[i] : f.shadow[i - t.primary_groups];
        const GroupResult& res = primary ? f.primary_results[i] : f.shadow_results[i - t.primary_groups];
        ASSERT_EQ(g.kind, primary ? GroupKind::primary : GroupKind::shadow);
        ASSERT_EQ(g.n, primary ? 8u : 3u);
        ASSERT_EQ(g.planes.size(), 2u * g.n);
        for (std::uint32_t v = 0; v < g.n; ++v)
            for (std::uint32_t h = 0; h < g.n; ++h) {
                const Ray a = g.ray(h, v), b = group_ray(src, h, v);
                ASSERT_TRUE(same(a.o, b.o) && same(a.d, b.d) && same_bits(a.tmax, b.tmax));
            }
        ASSERT_EQ(g.sphere_hits.size(), g.counts.sphere_hits);
        ASSERT_EQ(g.counts.rt_tests, res.counts.rt_tests);
        ASSERT_EQ(g.hits.size(), res.hits.size());
        for (std::size_t k = 0; k < g.hits.size(); ++k) ASSERT_EQ(g.hits[k], res.hits[k]);
    }
    // primary hits in the trace are the pixels' hits
    for (std::uint32_t i = 0; i < t.primary_groups; ++i) {
        const TraceGroup& g = t.groups[i];
        for (std::uint32_t v = 0; v < g.n; ++v)
            for (std::uint32_t h = 0; h < g.n; ++h) {
                if (!g.ray_valid(h, v)) continue;
                const std::size_t px = std::size_t(g.py + int(v)) * 20 + std::size_t(g.px + int(h));
                ASSERT_EQ(g.hits[v * g.n + h], f.pixel_hit[px]);
            }
    }
    GroupCounts total = f.primary_counts;
    total += f.shadow_counts;
    const GroupCounts tc = t.total_counts();
    EXPECT_EQ(tc.plane_tests, total.plane_tests);
    EXPECT_EQ(tc.sphere_hits, total.sphere_hits);
    EXPECT_EQ(tc.rt_tests, total.rt_tests);
    // the pair-less spheres: as many as counted, disjoint from the hits
    EXPECT_TRUE(t.pairless);
    EXPECT_EQ(tc.pairless, total.pairless);
    EXPECT_GT(tc.pairless, 0u);
    for (const TraceGroup& g : t.groups) {
        std::uint64_t n = 0;
        for (const SphereRun& run : g.pairless) {
            n += run.count;
            for (const SphereHitRec& h : g.sphere_hits) ASSERT_FALSE(h.sphere >= run.first && h.sphere < run.end());
        }
        ASSERT_EQ(n, g.counts.pairless);
    }
}

TEST(TraceIo, ATraceForTheRowAndColumnReadingCarriesNoPairlessSpheres) {
    // The same frame made into a `both` trace: no runs, a few bytes per group
    // fewer, and otherwise the same groups.
    const Rendered& r = rendered();
    const Trace both = make_trace(r.scene, r.frame, r.trace.format, false);
    EXPECT_FALSE(both.pairless);
    const std::string bytes = serialize_trace(both);
    const Trace back = parse_trace(bytes, "both.trace");
    EXPECT_FALSE(back.pairless);
    std::size_t runs = 0;
    for (std::size_t i = 0; i < back.groups.size(); ++i) {
        EXPECT_TRUE(back.groups[i].pairless.empty());
        EXPECT_EQ(back.groups[i].counts.pairless, 0u);
        EXPECT_EQ(back.groups[i].sphere_hits.size(), r.trace.groups[i].sphere_hits.size());
        runs += r.trace.groups[i].pairless.size();
    }
    EXPECT_LT(bytes.size(), r.bytes.size());
    EXPECT_GE(r.bytes.size() - bytes.size(), 2 * runs + 16 * back.groups.size());  // runs, run count and byte count
}

TEST(TraceIo, SerializeParseRoundTripIsExact) {
    const Rendered& r = rendered();
    ASSERT_GT(r.bytes.size(), kHeader + 100);
    EXPECT_EQ(r.bytes.substr(0, 8), std::string("RAPLTRC\n"));
    Trace back = parse_trace(r.bytes, "mem.trace");
    expect_same_trace(r.trace, back);
    // and serializing the parsed trace gives the same bytes
    EXPECT_EQ(serialize_trace(back), r.bytes);
    // serialization is deterministic (thread count does not matter)
    FrameOptions fo;
    fo.format = NumFormat::parse("fp1-8-15");
    fo.threads = 1;
    fo.record = true;
    fo.pairless = true;
    Frame f1 = render_frame(r.scene, fo);
    EXPECT_TRUE(serialize_trace(make_trace(r.scene, f1, fo.format, true)) == r.bytes);
}

TEST(TraceIo, TakenHeaderLeavesTheReaderItsGroups) {
    // The header moved out of a reader (what a streamed run keeps) has the
    // geometry; the reader keeps none of it and still reads and checks the
    // groups against the sphere and triangle counts.
    const Rendered& r = rendered();
    TraceReader rd(r.bytes, "mem.trace");
    Trace back = rd.take_header();
    EXPECT_TRUE(rd.header().triangles.empty());
    EXPECT_TRUE(rd.header().spheres.empty());
    EXPECT_EQ(rd.header().tri_count, r.trace.tri_count);
    TraceGroup g;
    while (rd.next(g)) back.groups.push_back(std::move(g));
    back.content_hash = rd.content_hash();
    expect_same_trace(r.trace, back);
    EXPECT_EQ(serialize_trace(back), r.bytes);

    Trace bad = r.trace;
    std::size_t i = 0;
    while (bad.groups[i].hits.empty()) ++i;
    bad.groups[i].hits[0].tri = std::int32_t(bad.triangles.size());
    const std::string bad_bytes = serialize_trace(bad);
    TraceReader rb(bad_bytes, "bad.trace");
    (void)rb.take_header();
    EXPECT_THROW(
        {
            while (rb.next(g)) {
            }
        },
        InputError);
}

TEST(TraceIo, HitsReplayFromTheTraceAlone) {
    // A consumer of the trace (the timing model) recomputes the same nearest
    // hits from its spheres, triangles and groups.
    const Trace t = parse_trace(rendered().bytes, "replay.trace");
    SphereSet s;
    s.spheres = t.spheres;
    s.first_tri = t.first_tri;
    s.tri_count = t.tri_count;
    s.triangles = t.triangles;
    s.tri_mesh_index = t.tri_mesh_index;
    Tracer tracer(s, t.format);
    for (std::size_t gi = 0; gi < t.groups.size(); ++gi) {
        const TraceGroup& g = t.groups[gi];
        for (std::uint32_t v = 0; v < g.n; ++v)
            for (std::uint32_t h = 0; h < g.n; ++h) {
                if (!g.ray_valid(h, v)) continue;
                ASSERT_EQ(tracer.brute_force(g.ray(h, v)), g.hits[v * g.n + h]) << "group " << gi;
            }
    }
}

TEST(TraceIo, TruncatedAnywhereIsRejected) {
    const std::string& b = rendered().bytes;
    const std::size_t cuts[] = {0, 1, 7, 8, 11, 12, 20, kHeader - 1, kHeader, kHeader + 1, kHeader + 40,
                                b.size() / 3, b.size() / 2, b.size() - 13, b.size() - 1};
    for (std::size_t n : cuts) {
        const std::string msg = parse_error(b.substr(0, n), "cut.trace");
        EXPECT_THAT(msg, HasSubstr("cut.trace")) << "cut at " << n;
        EXPECT_THAT(msg, ::testing::Not(HasSubstr("not an InputError"))) << "cut at " << n;
    }
    // extra bytes at the end too
    EXPECT_THAT(parse_error(b + "x", "long.trace"), HasSubstr("long.trace"));
}

TEST(TraceIo, FlippedByteAnywhereIsRejected) {
    const std::string& b = rendered().bytes;
    std::size_t tried = 0;
    // every header byte, then payload bytes across the file (first and last included)
    std::vector<std::size_t> positions;
    for (std::size_t i = 0; i < kHeader; ++i) positions.push_back(i);
    const std::size_t step = std::max<std::size_t>(1, (b.size() - kHeader) / 400);
    for (std::size_t i = kHeader; i < b.size(); i += step) positions.push_back(i);
    positions.push_back(b.size() - 1);
    for (std::size_t pos : positions) {
        for (unsigned char mask : {0x01, 0x80, 0xff}) {
            std::string c = b;
            c[pos] = char(static_cast<unsigned char>(c[pos]) ^ mask);
            const std::string msg = parse_error(c, "flip.trace");
            ASSERT_THAT(msg, HasSubstr("flip.trace")) << "byte " << pos << " ^ " << int(mask);
            ASSERT_THAT(msg, ::testing::Not(HasSubstr("not an InputError"))) << "byte " << pos;
            ++tried;
        }
    }
    EXPECT_GT(tried, 1000u);
}

TEST(TraceIo, WrongMagicAndOtherVersions) {
    const std::string& b = rendered().bytes;
    std::string m = b;
    m[0] = 'X';
    EXPECT_THAT(parse_error(m, "magic.trace"), AllOf(HasSubstr("magic.trace"), HasSubstr("not a raplas trace")));
    EXPECT_THAT(parse_error("PNG\x89 this is something else entirely, long enough", "other.png"),
                HasSubstr("other.png"));
    for (std::uint32_t version : {0u, kTraceVersion + 1, 0xffffffffu}) {
        std::string v = b;
        std::memcpy(&v[8], &version, 4);
        const std::string msg = parse_error(v, "ver.trace");
        EXPECT_THAT(msg, AllOf(HasSubstr("ver.trace"), HasSubstr("version " + std::to_string(version)))) << version;
    }
}

TEST(TraceIo, ReadsVersion4TracesByTheirOwnChecksum) {
    // A version 5 trace made version 4: the version field, and every block's
    // checksum FNV-1a. It reads as the same trace; with version 5's
    // checksums left in place, it does not.
    const std::string& b = rendered().bytes;
    std::uint32_t version;
    std::memcpy(&version, &b[8], 4);
    ASSERT_EQ(version, kTraceVersion);
    ASSERT_EQ(kTraceVersion, 5u);
    const std::string v4 = as_version4(b);
    std::string stale = b;  // version 4, version 5's checksums
    const std::uint32_t four = 4;
    std::memcpy(&stale[8], &four, 4);
    const std::vector<BlockInfo> blocks = blocks_of(b);
    ASSERT_GE(blocks.size(), 4u);
    for (const BlockInfo& x : blocks) {
        ASSERT_TRUE(x.sum_ok);
        ASSERT_NE(fnv1a(b, x.at, x.at + x.size), xxh3(b, x.at, x.at + x.size));
    }
    ASSERT_NE(v4, stale);
    EXPECT_EQ(serialize_trace(parse_trace(v4, "v4.trace")), b);
    EXPECT_THAT(parse_error(stale, "stale.trace"), AllOf(HasSubstr("stale.trace"), HasSubstr("checksum mismatch")));
    std::string three = b;
    const std::uint32_t v3 = 3;
    std::memcpy(&three[8], &v3, 4);
    EXPECT_THAT(parse_error(three, "v3.trace"), AllOf(HasSubstr("version 3"), HasSubstr("versions 4 to 5")));
}

TEST(TraceIo, BlocksInTheirOrder) {
    // HEAD, GROUPS blocks of the primary groups, TOTAL, GROUPS blocks of the
    // shadow groups (at most kTraceBlockGroups each), END; nothing after it.
    const Trace t = longer_trace(5);
    const std::string b = serialize_trace(t);
    const std::vector<BlockInfo> blocks = blocks_of(b);
    ASSERT_GE(blocks.size(), 6u);
    EXPECT_EQ(blocks.front().kind, std::uint32_t(TraceBlock::head));
    EXPECT_EQ(blocks.back().kind, std::uint32_t(TraceBlock::end));
    EXPECT_EQ(blocks.back().at + blocks.back().size, b.size());
    std::uint64_t groups = 0, at_total = ~std::uint64_t(0), shadow_blocks = 0;
    for (std::size_t i = 1; i + 1 < blocks.size(); ++i) {
        EXPECT_TRUE(blocks[i].sum_ok);
        if (blocks[i].kind == std::uint32_t(TraceBlock::total)) {
            at_total = groups;
            std::uint64_t g;
            std::memcpy(&g, &b[blocks[i].at], 8);
            EXPECT_EQ(g, t.groups.size());
            continue;
        }
        ASSERT_EQ(blocks[i].kind, std::uint32_t(TraceBlock::groups)) << i;
        EXPECT_GE(blocks[i].groups, 1u);
        EXPECT_LE(blocks[i].groups, kTraceBlockGroups);
        groups += blocks[i].groups;
        shadow_blocks += at_total != ~std::uint64_t(0);
    }
    EXPECT_EQ(at_total, t.primary_groups);
    EXPECT_EQ(groups, t.groups.size());
    EXPECT_GE(shadow_blocks, (t.groups.size() - t.primary_groups + kTraceBlockGroups - 1) / kTraceBlockGroups);
    expect_same_trace(t, parse_trace(b, "long.trace"));
}

TEST(TraceIo, WriterGroupByGroupGivesTheSameBytes) {
    const Trace t = longer_trace(3);
    std::string out;
    TraceWriter w([&out](const char* p, std::size_t n) { out.append(p, n); });
    Trace header = t;
    header.groups.clear();
    w.header(header);
    for (std::size_t i = 0; i < t.groups.size(); ++i) {
        if (i == t.primary_groups) w.total(t.groups.size());
        w.group(t.groups[i]);
        EXPECT_EQ(w.bytes(), out.size());
    }
    w.finish();
    EXPECT_EQ(out, serialize_trace(t));
    // misuse is a programming error, not bad input
    TraceWriter x([](const char*, std::size_t) {});
    EXPECT_THROW(x.group(t.groups[0]), std::logic_error);
    x.header(header);
    for (std::uint32_t i = 0; i < t.primary_groups; ++i) x.group(t.groups[i]);
    EXPECT_THROW(x.group(t.groups[t.primary_groups]), std::logic_error);  // TOTAL first
    EXPECT_THROW(x.finish(), std::logic_error);
}

TEST(TraceIo, MorePrimaryGroupsThanGroupsIsRejected) {
    // The HEAD block's primary group count (its last 4 bytes) raised past the
    // group count, its checksum made right again.
    const Trace& t = rendered().trace;
    std::string b = serialize_trace(t);
    const BlockInfo head = blocks_of(b).front();
    const std::uint32_t p = std::uint32_t(t.groups.size() + 1);
    std::memcpy(&b[head.at + head.size - 4], &p, 4);
    const std::uint64_t sum = xxh3(b, head.at, head.at + head.size);
    std::memcpy(&b[head.at - 8], &sum, 8);
    const std::string msg = parse_error(b, "bad.trace");
    EXPECT_THAT(msg, AllOf(HasSubstr("bad.trace"), ::testing::Not(HasSubstr("not an InputError")))) << msg;
}

TEST(TraceIo, ReaderHandsOutGroupsBeforeLateDamage) {
    // A stream is checked block by block: the groups before a damaged block
    // come out first, then one line names the block.
    const Trace t = longer_trace(5);
    const std::string b = serialize_trace(t);
    const std::vector<BlockInfo> blocks = blocks_of(b);
    const BlockInfo& last = blocks[blocks.size() - 2];  // the last GROUPS block
    ASSERT_EQ(last.kind, std::uint32_t(TraceBlock::groups));
    std::string c = b;
    c[last.at + last.size / 2] ^= 1;
    TraceReader r(c, "late.trace");
    TraceGroup g;
    std::uint64_t n = 0;
    try {
        while (r.next(g)) ++n;
        ADD_FAILURE() << "damaged block accepted";
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), AllOf(HasSubstr("late.trace"), HasSubstr("checksum mismatch in GROUPS block " +
                                                                        std::to_string(blocks.size() - 2))));
    }
    EXPECT_EQ(n, t.groups.size() - last.groups);
    EXPECT_TRUE(r.total_known());
    // cut at a block boundary: no END block
    const std::string cut = b.substr(0, last.at - kTraceBlockHeaderBytes);
    EXPECT_THAT(parse_error(cut, "cut.trace"),
                HasSubstr("truncated trace (it ends after " + std::to_string(t.groups.size() - last.groups) + " groups"));
    // a block out of place: END where TOTAL belongs
    std::string swapped = b;
    const std::uint32_t end = std::uint32_t(TraceBlock::end);
    for (const BlockInfo& x : blocks)
        if (x.kind == std::uint32_t(TraceBlock::total)) std::memcpy(&swapped[x.at - kTraceBlockHeaderBytes], &end, 4);
    EXPECT_THAT(parse_error(swapped, "order.trace"), HasSubstr("where the TOTAL block belongs"));
}

// The structural checks behind the checksum: files whose checksum is right
// but whose content is inconsistent.
TEST(TraceIo, InconsistentContentWithAValidChecksumIsRejected) {
    const Trace& good = rendered().trace;
    ASSERT_GE(good.spheres.size(), 2u);
    std::size_t with_hits = 0;
    while (with_hits < good.groups.size() && good.groups[with_hits].sphere_hits.empty()) ++with_hits;
    ASSERT_LT(with_hits, good.groups.size());
    std::size_t with_pairless = 0;
    while (with_pairless < good.groups.size() && good.groups[with_pairless].pairless.empty()) ++with_pairless;
    ASSERT_LT(with_pairless, good.groups.size());
    struct Case {
        const char* what;
        std::function<void(Trace&)> edit;
    };
    const std::vector<Case> cases = {
        {"sphere triangles not contiguous", [](Trace& t) { t.first_tri[1] += 1; }},
        {"empty sphere", [](Trace& t) { t.tri_count[0] = 0; }},
        {"hit triangle out of range", [](Trace& t) { t.groups[0].hits[0].tri = std::int32_t(t.triangles.size()); }},
        {"hit triangle below -1", [](Trace& t) { t.groups[0].hits[0].tri = -2; }},
        {"counts disagree", [&](Trace& t) { t.groups[with_hits].counts.rt_tests += 1; }},
        {"sphere hit out of range",
         [&](Trace& t) { t.groups[with_hits].sphere_hits[0].sphere = std::uint32_t(t.spheres.size()); }},
        {"empty plane mask", [&](Trace& t) { t.groups[with_hits].sphere_hits[0].rows = 0; }},
        {"group kinds out of order", [](Trace& t) { t.primary_groups += 1; }},
        {"bad format", [](Trace& t) { t.format.exp_bits = 1; }},
        {"pair-less sphere that is also a hit",
         [&](Trace& t) {
             auto& g = t.groups[with_hits];
             g.pairless = {SphereRun{g.sphere_hits[0].sphere, 1}};
             g.counts.pairless = 1;
         }},
        {"pair-less spheres out of range",
         [&](Trace& t) {
             t.groups[0].pairless.push_back({std::uint32_t(t.spheres.size() + 5), 1});
             t.groups[0].counts.pairless += 1;
         }},
        {"pair-less count disagrees", [&](Trace& t) { t.groups[with_pairless].counts.pairless += 1; }},
        {"pair-less count without a list",
         [&](Trace& t) {
             t.pairless = false;
             t.groups[with_pairless].counts.pairless = 3;
         }},
    };
    for (const Case& c : cases) {
        Trace t = good;
        c.edit(t);
        const std::string bytes = serialize_trace(t);
        // every block's checksum is valid: only the content can be wrong
        for (const BlockInfo& b : blocks_of(bytes)) ASSERT_TRUE(b.sum_ok) << c.what;
        const std::string msg = parse_error(bytes, "bad.trace");
        EXPECT_THAT(msg, AllOf(HasSubstr("bad.trace"), ::testing::Not(HasSubstr("not an InputError")))) << c.what;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

class TraceFiles : public raplas_test::TempDirFixture {
protected:
    TraceFiles() : TempDirFixture("raplas_trace") {}
};

TEST_F(TraceFiles, Version4FileReadsAndIsSizedAsItsVersion5Twin) {
    // From a file, and in the memory check's reading of its header and blocks.
    const Trace t = longer_trace(3);
    const std::string b = serialize_trace(t);
    const std::string p5 = (dir / "v5.trace").string(), p4 = (dir / "v4.trace").string();
    std::ofstream(p5, std::ios::binary) << b;
    std::ofstream(p4, std::ios::binary) << as_version4(b);
    EXPECT_EQ(serialize_trace(read_trace(p4)), b);
    const TraceShape s4 = trace_file_shape(p4), s5 = trace_file_shape(p5);
    EXPECT_EQ(s5.groups(), t.groups.size());
    EXPECT_EQ(s4.groups(), s5.groups());
    EXPECT_EQ(s4.spheres, s5.spheres);
    EXPECT_EQ(s4.triangles, s5.triangles);
    EXPECT_EQ(trace_file_memory(s4).bytes, trace_file_memory(s5).bytes);
}

TEST_F(TraceFiles, WriteAndReadThroughTheFilesystem) {
    const Rendered& r = rendered();
    const std::string p = (dir / "frame.trace").string();
    write_trace(p, r.trace);
    ASSERT_TRUE(fs::exists(p));
    EXPECT_EQ(fs::file_size(p), r.bytes.size());
    // no temporary files left behind
    std::size_t entries = 0;
    for (const auto& e : fs::directory_iterator(dir)) entries += e.is_regular_file();
    EXPECT_EQ(entries, 1u);
    Trace back = read_trace(p);
    expect_same_trace(r.trace, back);
    // the reader on the file, group by group, and on a pipe
    {
        TraceReader rd(p);
        TraceGroup g;
        std::size_t n = 0;
        while (rd.next(g)) ++n;
        EXPECT_EQ(n, r.trace.groups.size());
        EXPECT_EQ(rd.bytes_read(), r.bytes.size());
    }
    {
        const std::string fifo = (dir / "pipe.trace").string();
        ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
        std::thread writer([&] { std::ofstream(fifo, std::ios::binary) << r.bytes; });
        const Trace piped = read_trace(fifo);
        writer.join();
        expect_same_trace(r.trace, piped);
    }
    // the memory check reads the shape from the file's header and sizes the
    // read buffer from it: the record sizes of this version
    const TraceShape shape = trace_file_shape(p);
    EXPECT_EQ(shape.spheres, r.trace.spheres.size());
    EXPECT_EQ(shape.triangles, r.trace.triangles.size());
    EXPECT_EQ(shape.groups(), r.trace.groups.size());
    const double buffer = trace_file_memory(shape).bytes;
    EXPECT_GE(buffer, 0.9 * double(r.bytes.size()));
    EXPECT_LE(buffer, 1.2 * double(r.bytes.size()));
    // overwrite in place
    write_trace(p, back);
    expect_same_trace(r.trace, read_trace(p));
    // a truncated file on disk names its path
    const std::string cut = (dir / "cut.trace").string();
    std::ofstream(cut, std::ios::binary) << r.bytes.substr(0, r.bytes.size() / 2);
    try {
        read_trace(cut);
        ADD_FAILURE() << "truncated trace accepted";
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr(cut));
    }
    // a missing file names its path
    const std::string missing = (dir / "missing.trace").string();
    try {
        read_trace(missing);
        ADD_FAILURE() << "missing trace accepted";
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr(missing));
    }
}

}  // namespace
