// Whole-machine tests: each runs one SystemC simulation (one per process:
// ctest runs every test in its own process).
#include <gtest/gtest.h>

#include "hand_trace.hpp"
#include "raplas/frontend/frame.hpp"
#include "top.hpp"

using namespace raplas;
using namespace raplas::model;

namespace {

SimMode g_mode = SimMode::netlist;  // (the tests not run in both modes: the reference)

SimConfig base_config(std::uint32_t iccs, std::uint32_t depth) {
    SimConfig c;
    c.mode = g_mode;
    c.iccs = iccs;
    c.icc.sphere_fifo.depth = depth;
    c.icc.triangle_fifo.depth = depth;
    c.icc.planeid_fifo.depth = 16;
    c.functional = FunctionalMode::trace;
    return c;
}

// Every sphere hit by 2 row and 3 column planes: m = 6 ray tests per
// triangle. When the RTI is the bottleneck from the first triangle on, the
// pass takes S*m + L_rti + L_psi + 3 cycles.
constexpr std::uint32_t kHitSpheres = 300, kHitTests = 6;
Trace every_sphere_hit_trace() {
    return test::hand_trace(kHitSpheres, 16, 0b11, 0b111, std::vector<bool>(kHitSpheres, true));
}
std::uint64_t rti_bound_cycles(const SimConfig& c) {
    return std::uint64_t(kHitSpheres) * kHitTests + c.icc.rti.stages + c.icc.psi.stages + 3;
}

class TopClosedForm : public ::testing::TestWithParam<SimMode> {
protected:
    void SetUp() override { g_mode = GetParam(); }
};

}  // namespace

TEST_P(TopClosedForm, AllSpheresMissed) {
    // Sphere i enters the PSI in cycle i+1 and is decided in cycle i+1+L;
    // triangle i follows one cycle later: S + L_psi + 2 cycles in all.
    const std::uint32_t S = 500;
    Trace t = test::hand_trace(S, 16, 0, 0, std::vector<bool>(S, false));
    SimConfig c = base_config(1, 1000);
    SimResult r = simulate(t, c);
    EXPECT_EQ(r.total_cycles, S + c.icc.psi.stages + 2);
    EXPECT_EQ(r.triangle_link.records_sent, S);
    EXPECT_EQ(r.triangle_link.stall_cycles, c.icc.psi.stages + 2);  // waiting for the first decision
}

TEST_P(TopClosedForm, TriangleLagBeyondTheDecisionLatencyAddsItsExcess) {
    // With the triangle stream held back lag >= L_psi + 2 cycles, the first
    // decision is always ready: S + lag cycles, and no stall is counted.
    const std::uint32_t S = 500;
    Trace t = test::hand_trace(S, 16, 0, 0, std::vector<bool>(S, false));
    SimConfig c = base_config(1, 1000);
    c.triangle_lag_cycles = 40;
    SimResult r = simulate(t, c);
    EXPECT_EQ(r.total_cycles, S + 40u);
    EXPECT_EQ(r.triangle_link.stall_cycles, 0u);
}

TEST_P(TopClosedForm, EverySphereHitDeepFifo) {
    // Every triangle needs m = 2 x 3 ray tests; the RTI is the bottleneck from
    // the first triangle on.
    Trace t = every_sphere_hit_trace();
    SimConfig c = base_config(1, 1000);
    SimResult r = simulate(t, c);
    EXPECT_EQ(r.total_cycles, rti_bound_cycles(c));
    EXPECT_EQ(r.iccs[0].rti.tests, std::uint64_t(kHitSpheres) * kHitTests);
    EXPECT_EQ(r.iccs[0].rti.busy_cycles, std::uint64_t(kHitSpheres) * kHitTests);
}

TEST_P(TopClosedForm, HeldDecoderStopsTheSphereStreamWithoutStarvingTheRti) {
    // As above with 10-deep Sphere and Triangle FIFOs: the Triangle FIFO
    // fills, the 16-deep PlaneID FIFO behind it, the Decoder holds, the
    // Sphere FIFO fills and stops the sphere stream (the event mode lets
    // such an ICC doze and settles its counts when a selection frees it).
    // The RTI still never waits.
    Trace t = every_sphere_hit_trace();
    SimConfig c = base_config(1, 10);
    SimResult r = simulate(t, c);
    EXPECT_EQ(r.total_cycles, rti_bound_cycles(c));
    const IccSnapshot& i = r.iccs[0];
    EXPECT_EQ(i.rti.busy_cycles, std::uint64_t(kHitSpheres) * kHitTests);
    EXPECT_EQ(i.planeid_fifo.pushes, kHitSpheres);
    EXPECT_EQ(i.planeid_fifo.max_occupancy, 16u);
    EXPECT_EQ(i.sphere_fifo.pushes, kHitSpheres);
    EXPECT_EQ(i.sphere_fifo.max_occupancy, 10u);
    EXPECT_GT(i.decoder.full_cycles, 0u);
    // The PSI holds exactly when the Decoder does, and both FIFOs are full then.
    EXPECT_EQ(i.psi.stall_cycles, i.decoder.full_cycles);
    EXPECT_EQ(i.planeid_fifo.full_cycles, i.decoder.full_cycles);
    EXPECT_EQ(i.first_tri_fifo.full_cycles, i.decoder.full_cycles);
    // The only ICC's full Sphere FIFO is the only reason the sphere link stalls.
    EXPECT_GT(i.sphere_selector.blocked_link_cycles, 0u);
    EXPECT_EQ(i.sphere_selector.blocked_link_cycles, r.sphere_link.stall_cycles);
    EXPECT_EQ(i.sphere_fifo.full_cycles, r.sphere_link.stall_cycles);
}

TEST_P(TopClosedForm, DepthOneFifoHalvesTheRateOfOneRayTriangles) {
    // A full FIFO refuses a push even when its reader pops in the same cycle:
    // with depth 1 and one test per triangle the link delivers every other
    // cycle: 2S + L_rti + L_psi + 2 cycles.
    const std::uint32_t S = 200;
    Trace t = test::hand_trace(S, 16, 0b1, 0b1, std::vector<bool>(S, true));
    SimConfig c = base_config(1, 1);
    c.icc.sphere_fifo.depth = 1000;
    SimResult r = simulate(t, c);
    EXPECT_EQ(r.total_cycles, 2ull * S + c.icc.rti.stages + c.icc.psi.stages + 2);
}

TEST_P(TopClosedForm, PassesAddUp) {
    // 5 groups on 2 ICCs: 3 passes of S + L_psi + 2 cycles (+ overhead).
    const std::uint32_t S = 100;
    Trace t = test::hand_trace(S, 8, 0, 0, std::vector<bool>(S, false), 5);
    SimConfig c = base_config(2, 1000);
    c.pass_overhead_cycles = 7;
    SimResult r = simulate(t, c);
    EXPECT_EQ(r.host.passes, 3u);
    EXPECT_EQ(r.total_cycles, 3ull * (S + c.icc.psi.stages + 2 + 7));
    EXPECT_EQ(r.iccs[1].icc.groups, 2u);
    EXPECT_EQ(r.iccs[1].icc.idle_cycles, S + c.icc.psi.stages + 2u);
}

// Every sphere cut by row planes only (one simulation per process: one
// configuration per test). Under `both` nothing is kept: S + L_psi + 2
// cycles. Under `any` every triangle is kept: triangle i is selected in
// cycle L_psi + 2 + i and the Fetcher, free from cycle L_psi + 3 on, spends e
// cycles on each (the cycle it pops it included): the last is done in cycle
// L_psi + 2 + e S, the pass ends one later. With e <= 1 the link is the
// bottleneck: S + L_psi + 3. Sphere i's PlaneID entry is queued in cycle
// L_psi + 1 + i and taken with its triangle a cycle later: the PlaneID FIFO
// never holds more than one; with e <= 1 neither does the Triangle FIFO.
namespace {
constexpr std::uint32_t kPairlessS = 300;
Trace all_pairless() {
    Trace t = test::hand_trace(kPairlessS, 16, 0, 0, std::vector<bool>(kPairlessS, false));
    test::add_pairless(t, std::vector<bool>(kPairlessS, true));
    return t;
}
void expect_all_pairless(std::uint32_t e) {
    SimConfig c = base_config(1, 1000);
    c.icc.decoder.select = TriangleSelect::any;
    c.icc.fetcher.empty_cycles = e;
    const std::uint64_t S = kPairlessS, L = c.icc.psi.stages;
    SimResult r = simulate(all_pairless(), c);
    EXPECT_EQ(r.total_cycles, L + 3 + std::uint64_t(std::max(e, 1u)) * S) << "e = " << e;
    EXPECT_EQ(r.iccs[0].decoder.sphere_hits, S);
    EXPECT_EQ(r.iccs[0].decoder.pairless, S);
    EXPECT_EQ(r.iccs[0].triangle_selector.selected, S);
    EXPECT_EQ(r.iccs[0].ray_data_fetcher.empty_triangles, S);
    EXPECT_EQ(r.iccs[0].rti.tests, 0u);
    EXPECT_EQ(r.iccs[0].rti.busy_cycles, 0u);
    EXPECT_EQ(r.iccs[0].planeid_fifo.pushes, S);
    EXPECT_EQ(r.iccs[0].planeid_fifo.max_occupancy, 1u);
    EXPECT_EQ(r.iccs[0].triangle_fifo.pushes, S);
    if (e <= 1) {
        EXPECT_EQ(r.iccs[0].triangle_fifo.max_occupancy, 1u);
    }
}
}  // namespace

TEST_P(TopClosedForm, PairlessSpheresAreDiscardedUnderBoth) {
    SimConfig c = base_config(1, 1000);
    SimResult r = simulate(all_pairless(), c);
    EXPECT_EQ(r.total_cycles, kPairlessS + c.icc.psi.stages + 2);
    EXPECT_EQ(r.iccs[0].triangle_selector.selected, 0u);
}
TEST_P(TopClosedForm, PairlessSpheresUnderAnyFetcherDropsThemAtNoCost) { expect_all_pairless(0); }
TEST_P(TopClosedForm, PairlessSpheresUnderAnyOneFetcherCycleEach) { expect_all_pairless(1); }
TEST_P(TopClosedForm, PairlessSpheresUnderAnyThreeFetcherCyclesEach) { expect_all_pairless(3); }

// The same behind a triangle stream held back lag >= L_psi + 2 cycles, with
// a deep PlaneID FIFO: sphere i is queued in cycle L_psi + 1 + i and its
// triangle taken in cycle lag + i, so the FIFO holds up to lag - L_psi - 1
// entries while the Fetcher takes each triangle the cycle after it came (the
// event mode takes such runs as a whole and must still count every push).
TEST_P(TopClosedForm, PairlessSpheresBehindALaggingTriangleStream) {
    SimConfig c = base_config(1, 1000);
    c.icc.decoder.select = TriangleSelect::any;
    c.icc.planeid_fifo.depth = 1000;
    c.triangle_lag_cycles = 40;
    const std::uint64_t S = kPairlessS, L = c.icc.psi.stages, lag = c.triangle_lag_cycles;
    SimResult r = simulate(all_pairless(), c);
    EXPECT_EQ(r.total_cycles, lag + S + 1);
    EXPECT_EQ(r.iccs[0].triangle_selector.selected, S);
    EXPECT_EQ(r.iccs[0].ray_data_fetcher.empty_triangles, S);
    EXPECT_EQ(r.iccs[0].planeid_fifo.pushes, S);
    EXPECT_EQ(r.iccs[0].planeid_fifo.max_occupancy, lag - L - 1);
    EXPECT_EQ(r.iccs[0].triangle_fifo.pushes, S);
    EXPECT_EQ(r.iccs[0].triangle_fifo.max_occupancy, 1u);
    EXPECT_EQ(r.triangle_link.stall_cycles, 0u);
}

// Spheres alternate: a hit (m = 2 x 2 pairs) and a pair-less sphere (e = 2
// Fetcher cycles). With a deep FIFO the Fetcher works without a gap from
// cycle L_psi + 3 on, S/2 (ceil(4/R) + 2) cycles, the last a pair-less
// triangle; the last pair leaves the RTI L_rti cycles after it entered.
namespace {
void expect_alternating(std::uint32_t rti_pipes) {
    const std::uint32_t S = 200, e = 2;
    std::vector<bool> hit(S), pairless(S);
    for (std::uint32_t s = 0; s < S; ++s) (s % 2 ? pairless : hit)[s] = true;
    Trace t = test::hand_trace(S, 16, 0b11, 0b11, hit);
    test::add_pairless(t, pairless);
    SimConfig c = base_config(1, 1000);
    c.icc.decoder.select = TriangleSelect::any;
    c.icc.fetcher.empty_cycles = e;
    c.icc.rti.pipes = rti_pipes;
    const std::uint64_t L = c.icc.psi.stages, Lr = c.icc.rti.stages, hit_cycles = (4 + rti_pipes - 1) / rti_pipes;
    const std::uint64_t fetcher_end = L + 2 + (S / 2) * (hit_cycles + e);  // last cycle the Fetcher is busy
    const std::uint64_t last_pair = fetcher_end - e;
    SimResult r = simulate(t, c);
    EXPECT_EQ(r.total_cycles, std::max(fetcher_end, last_pair + Lr) + 1);
    EXPECT_EQ(r.iccs[0].rti.tests, (S / 2) * 4u);
    EXPECT_EQ(r.iccs[0].rti.busy_cycles, (S / 2) * hit_cycles);
    EXPECT_EQ(r.iccs[0].ray_data_fetcher.empty_triangles, S / 2);
}
}  // namespace

TEST_P(TopClosedForm, PairlessTrianglesQueueBehindRayTriangleWorkOneRtiPipe) { expect_alternating(1); }
TEST_P(TopClosedForm, PairlessTrianglesQueueBehindRayTriangleWorkTwoRtiPipes) { expect_alternating(2); }

// Overlapped passes (host.overlap_passes): G groups on one ICC, every sphere
// hit with m = 6 pairs, a FIFO deep enough for two groups. A pass's streams
// take S + L_psi + 2 cycles, far less than its RTI work, and the next pass
// starts as soon as the streams are done and the pass before has drained:
// the RTI works without a gap from cycle L_psi + 3 on, through every group
// of a phase. Without overlap each pass drains: S m + L_rti + L_psi + 3.
namespace {
constexpr std::uint32_t kOvS = 100, kOvM = 6;
SimResult overlapped(std::uint32_t groups, std::uint32_t primaries, bool overlap, Estimate est = Estimate::exact) {
    Trace t = test::hand_trace(kOvS, 16, 0b11, 0b111, std::vector<bool>(kOvS, true), groups);
    t.primary_groups = primaries;
    for (std::uint32_t g = primaries; g < groups; ++g) t.groups[g].kind = GroupKind::shadow;
    SimConfig c = base_config(1, 1000);
    c.icc.planeid_fifo.depth = 1000;
    c.overlap_passes = overlap;
    c.estimate = est;
    return simulate(t, c);
}
}  // namespace

TEST_P(TopClosedForm, PassesWithoutOverlapEachDrain) {
    const SimConfig c = base_config(1, 1000);
    const std::uint64_t L = c.icc.psi.stages, Lr = c.icc.rti.stages, Sm = std::uint64_t(kOvS) * kOvM;
    SimResult r = overlapped(3, 3, false);
    EXPECT_EQ(r.total_cycles, 3 * (Sm + Lr + L + 3));
}

TEST_P(TopClosedForm, OverlappedPassesKeepTheRtiBusyAcrossPasses) {
    const SimConfig c = base_config(1, 1000);
    const std::uint64_t L = c.icc.psi.stages, Lr = c.icc.rti.stages, S = kOvS, Sm = std::uint64_t(kOvS) * kOvM;
    SimResult r = overlapped(3, 3, true);
    EXPECT_EQ(r.total_cycles, L + 3 + 3 * Sm + Lr);
    // pass 0 ends with its streams; pass 1 when pass 0 has drained; pass 2 drains
    ASSERT_EQ(r.pass_cycles.size(), 3u);
    EXPECT_EQ(r.pass_cycles[0], S + L + 2);
    EXPECT_EQ(r.pass_cycles[0] + r.pass_cycles[1], L + 3 + Sm + Lr);
    EXPECT_EQ(r.iccs[0].rti.busy_cycles, 3 * Sm);
    EXPECT_EQ(r.iccs[0].rti.tests, 3 * Sm);
}

TEST_P(TopClosedForm, OverlappedPassesDrainAtThePrimaryToShadowBoundary) {
    // Two primary groups, then one shadow group: the shadow pass waits for the
    // primary phase to drain (its origins are primary hits).
    const SimConfig c = base_config(1, 1000);
    const std::uint64_t L = c.icc.psi.stages, Lr = c.icc.rti.stages, Sm = std::uint64_t(kOvS) * kOvM;
    SimResult r = overlapped(3, 2, true);
    EXPECT_EQ(r.total_cycles, (L + 3 + 2 * Sm + Lr) + (Sm + Lr + L + 3));
}

TEST(TopBound, OverlappedPassesInClosedFormEqualTheExactCountWhenNoFifoFills) {
    const SimConfig c = base_config(1, 1000);
    const std::uint64_t L = c.icc.psi.stages, Lr = c.icc.rti.stages, Sm = std::uint64_t(kOvS) * kOvM;
    SimResult r = overlapped(3, 2, true, Estimate::fifo_bound);
    EXPECT_TRUE(r.lower_bound);
    EXPECT_EQ(r.total_cycles, (L + 3 + 2 * Sm + Lr) + (Sm + Lr + L + 3));
}

INSTANTIATE_TEST_SUITE_P(Modes, TopClosedForm, ::testing::Values(SimMode::event, SimMode::netlist),
                         [](const ::testing::TestParamInfo<SimMode>& i) {
                             return std::string(i.param == SimMode::event ? "event" : "netlist");
                         });

TEST(TopStall, AFullTriangleFifoStopsTheBroadcastForEveryIccInTheSameCycle) {
    // ICC 0's group hits every sphere with 16 rays per triangle; ICC 1's group
    // hits none. ICC 0's Triangle FIFO fills, and in every cycle that starts
    // with it full, no ICC receives a triangle.
    const std::uint32_t S = 200;
    Trace t = test::hand_trace(S, 4, 0b1111, 0b1111, std::vector<bool>(S, true), 2);
    t.groups[1].sphere_hits.clear();
    t.groups[1].counts.sphere_hits = 0;
    SimConfig c = base_config(2, 4);
    bool full_at_start = false, pending_at_start = true;
    std::uint64_t stalled_cycles_seen = 0, full_cycles = 0, full_and_pending = 0;
    SimOptions opt;
    opt.on_cycle = [&](const Top& top, std::uint64_t, std::int64_t, std::int64_t tri) {
        if (full_at_start) {
            ++full_cycles;
            full_and_pending += pending_at_start;
            EXPECT_EQ(tri, -1);
            if (tri == -1) ++stalled_cycles_seen;
        }
        // ICC 0 wants every triangle: it took each one the link delivered, in that cycle
        EXPECT_EQ(top.iccs[0].triangle_selector.stats().selected, top.triangle_link.position());
        full_at_start = top.iccs[0].triangle_fifo.full() || top.iccs[1].triangle_fifo.full();
        pending_at_start = top.triangle_link.has_record();
    };
    SimResult r = simulate(t, c, opt);
    EXPECT_GT(full_cycles, 100u);
    EXPECT_EQ(stalled_cycles_seen, full_cycles);
    EXPECT_EQ(r.iccs[1].triangle_selector.discarded, S);
    EXPECT_EQ(r.iccs[0].triangle_selector.selected, S);
    EXPECT_EQ(r.iccs[0].triangle_selector.blocked_fifo_full, full_and_pending);
    EXPECT_EQ(r.iccs[1].triangle_selector.blocked_fifo_full, 0u);
}

namespace {
void expect_functional_match(const SimConfig& c, int image, int group) {
    ParamSet p = scene_params();
    p.set("image.width=" + std::to_string(image));
    p.set("image.height=" + std::to_string(image));
    p.set("groups.size=" + std::to_string(group));
    p.set("groups.shadow_size=" + std::to_string(group));
    p.set("builtin_detail=2");
    Scene scene = scene_from_params(p, "");
    FrameOptions fo;
    fo.record = true;
    fo.format = c.format;
    fo.pairless = c.icc.decoder.select == TriangleSelect::any;
    Frame f = render_frame(scene, fo);
    Trace t = make_trace(scene, f, c.format, fo.pairless);
    SimResult r = simulate(t, c);
    EXPECT_TRUE(r.functional_checked);
    EXPECT_GT(r.rays_checked, 0u);
    EXPECT_EQ(r.rays_mismatched, 0u);
    EXPECT_TRUE(r.functional_match);
}
}  // namespace

TEST(TopFunctional, MatchesTheFrontEndOneIccDeepFifo) {
    SimConfig c = base_config(1, 1000);
    c.functional = FunctionalMode::compute;
    expect_functional_match(c, 24, 8);
}

TEST(TopFunctional, MatchesTheFrontEndFourIccsShallowFifo) {
    SimConfig c = base_config(4, 3);
    c.functional = FunctionalMode::compute;
    c.icc.planeid_fifo.depth = 2;
    expect_functional_match(c, 24, 8);
}

TEST(TopFunctional, MatchesTheFrontEndInFloat64WithFewPsiPipes) {
    SimConfig c = base_config(3, 10);
    c.functional = FunctionalMode::compute;
    c.format = NumFormat::float64();
    c.icc.psi.pipes = 4;
    expect_functional_match(c, 16, 4);
}

TEST(TopFunctional, MatchesTheFrontEndUnderTheAnyPlaneReading) {
    SimConfig c = base_config(3, 5);
    c.functional = FunctionalMode::compute;
    c.icc.decoder.select = TriangleSelect::any;
    c.icc.rti.pipes = 2;
    expect_functional_match(c, 24, 8);
}

TEST(TopFunctional, MatchesTheFrontEndWithOverlappedPasses) {
    SimConfig c = base_config(3, 4);
    c.functional = FunctionalMode::compute;
    c.overlap_passes = true;
    c.icc.decoder.select = TriangleSelect::any;
    expect_functional_match(c, 24, 8);
}

TEST(TopFunctional, MatchesTheFrontEndInAnEmulatedFormat) {
    SimConfig c = base_config(2, 100);
    c.functional = FunctionalMode::compute;
    c.format = NumFormat::parse("fp1-8-15");
    expect_functional_match(c, 16, 8);
}
