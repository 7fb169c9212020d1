// Baseline memory systems (shared, distributed) and their area under the
// paper's PE-unit model, against closed forms on hand-made traces
// (docs/MODEL.md §6; the blocks model: test_area.cpp).
#include <gtest/gtest.h>

#include "baseline_memory.hpp"
#include "hand_trace.hpp"

using namespace raplas;
using namespace raplas::model;

namespace {

SimConfig config(MemorySystem sys, std::uint32_t iccs) {
    SimConfig c;
    c.iccs = iccs;
    c.functional = FunctionalMode::trace;
    c.memory.system = sys;
    return c;
}

// Every sphere of t holds m triangles (copies of its one triangle).
void widen_spheres(Trace& t, std::uint32_t m) {
    std::vector<TriangleRec> tris;
    std::vector<std::int32_t> idx;
    for (std::size_t s = 0; s < t.spheres.size(); ++s) {
        t.first_tri[s] = std::uint32_t(tris.size());
        t.tri_count[s] = m;
        for (std::uint32_t i = 0; i < m; ++i) {
            tris.push_back(t.triangles[s]);
            idx.push_back(std::int32_t(tris.size() - 1));
        }
    }
    t.triangles = tris;
    t.tri_mesh_index = idx;
    t.tris_per_sphere = m;
}

// Group g becomes a shadow group for g >= primaries.
void make_shadow(Trace& t, std::uint32_t primaries) {
    t.primary_groups = primaries;
    for (std::size_t g = primaries; g < t.groups.size(); ++g) t.groups[g].kind = GroupKind::shadow;
}

std::vector<bool> every_third(std::uint32_t S) {
    std::vector<bool> h(S);
    for (std::uint32_t s = 0; s < S; s += 3) h[s] = true;
    return h;
}

}  // namespace

TEST(ListSchedule, GroupsGoToTheIccFreeFirstInIssueOrder) {
    // ICC 0 takes 5; ICC 1 takes 1, 1, 1 (free at 1, 2, 3) and then 4: ends at 7.
    EXPECT_EQ(list_schedule_makespan({5, 1, 1, 1, 4}, 2), 7u);
    EXPECT_EQ(list_schedule_makespan({3, 3, 3}, 8), 3u);
    EXPECT_EQ(list_schedule_makespan({3, 3, 3}, 1), 9u);
    EXPECT_EQ(list_schedule_makespan({}, 4), 0u);
}

TEST(GroupWork, CountsNeededTrianglesAndRayTriangleTests) {
    Trace t = test::hand_trace(30, 16, 0b11, 0b111, every_third(30), 2);
    widen_spheres(t, 4);
    const std::vector<GroupWork> w = group_work(t);
    ASSERT_EQ(w.size(), 2u);
    EXPECT_EQ(w[0].triangles_needed, 10u * 4);
    EXPECT_EQ(w[0].rt_tests, 10u * 4 * 6);
    EXPECT_TRUE(w[1].primary);
}

TEST(GroupWork, TheAnyReadingAddsThePairlessSpheresTriangles) {
    // Every third sphere hit, every third (offset 1) pair-less, 4 triangles
    // each: under `any` a group needs 20 spheres' triangles, 10 of them with
    // no pair; its RTI time adds rdf_empty_cycles per pair-less triangle.
    Trace t = test::hand_trace(30, 16, 0b11, 0b111, every_third(30), 2);
    std::vector<bool> pl(30);
    for (std::uint32_t s = 1; s < 30; s += 3) pl[s] = true;
    test::add_pairless(t, pl);
    widen_spheres(t, 4);
    const std::vector<GroupWork> both = group_work(t), any = group_work(t, TriangleSelect::any);
    EXPECT_EQ(both[0].triangles_needed, 40u);
    EXPECT_EQ(both[0].pairless_triangles, 0u);
    EXPECT_EQ(any[0].triangles_needed, 80u);
    EXPECT_EQ(any[0].pairless_triangles, 40u);
    EXPECT_EQ(any[0].rt_tests, both[0].rt_tests);
    SimConfig c = config(MemorySystem::shared, 1);
    c.icc.rti.pipes = 4;
    c.icc.fetcher.empty_cycles = 3;
    EXPECT_EQ(group_rti_cycles(both[0], c), 240u / 4);
    EXPECT_EQ(group_rti_cycles(any[0], c), 240u / 4 + 40u * 3);
}

TEST(BaselineShared, IdealPesTakeOneCyclePerNeededTriangleWhateverTheIccCount) {
    // 5 groups, each needing 100 of 300 triangles: 500 fetches through one port.
    const std::uint32_t S = 300;
    Trace t = test::hand_trace(S, 16, 0b1, 0b1, every_third(S), 5);
    for (std::uint32_t k : {1u, 2u, 4u, 16u}) {
        MemoryStats st;
        SimConfig c = config(MemorySystem::shared, k);
        c.area.model = AreaModel::pe_units;
        SimResult r = simulate_system(t, c, st);
        EXPECT_EQ(r.total_cycles, 500u) << k;
        EXPECT_EQ(st.triangle_records_read, 500u);
        EXPECT_EQ(st.sphere_records_read, 0u);
        EXPECT_EQ(st.memory_bound_cycles, 500u);
        EXPECT_DOUBLE_EQ(st.area.total, k * 1.0 + 2.0);  // K PEs and one memory
    }
}

TEST(BaselineShared, FetchedSpheresGoThroughTheSamePortAtItsRate) {
    const std::uint32_t S = 300;
    Trace t = test::hand_trace(S, 16, 0b1, 0b1, every_third(S), 5);
    SimConfig c = config(MemorySystem::shared, 2);
    c.memory.shared_fetch_spheres = true;
    MemoryStats st;
    EXPECT_EQ(simulate_system(t, c, st).total_cycles, 5u * (S + 100));
    EXPECT_EQ(st.sphere_records_read, 5u * S);
    c.memory.records_per_cycle = 3;
    EXPECT_EQ(simulate_system(t, c, st).total_cycles, (5u * (S + 100) + 2) / 3);
}

TEST(BaselineShared, RtiBoundPesAreLimitedByTheBusiestIcc) {
    // 2 x 3 ray tests per triangle: 600 RTI cycles per group; 5 groups on 2
    // ICCs take 3 x 600 on the RTIs against 500 cycles on the port.
    const std::uint32_t S = 300;
    Trace t = test::hand_trace(S, 16, 0b11, 0b111, every_third(S), 5);
    SimConfig c = config(MemorySystem::shared, 2);
    MemoryStats st;
    EXPECT_EQ(simulate_system(t, c, st).total_cycles, 500u);
    EXPECT_EQ(st.pe_bound_cycles, 1800u);
    c.memory.pe_rti_bound = true;
    EXPECT_EQ(simulate_system(t, c, st).total_cycles, 1800u);
    c.icc.rti.pipes = 4;  // 150 cycles per group: the port bounds again
    EXPECT_EQ(simulate_system(t, c, st).total_cycles, 500u);
    EXPECT_EQ(st.pe_bound_cycles, 450u);
}

TEST(BaselineDistributed, IdealPesReadEverySphereOfTheirOwnCopyPerGroup) {
    // Needed triangles (100) < spheres (300): a group takes S cycles; 5 groups
    // on 2 ICCs: 3 S; on 5 or more: S.
    const std::uint32_t S = 300;
    Trace t = test::hand_trace(S, 16, 0b1, 0b1, every_third(S), 5);
    MemoryStats st;
    SimConfig c = config(MemorySystem::distributed, 2);
    c.area.model = AreaModel::pe_units;
    EXPECT_EQ(simulate_system(t, c, st).total_cycles, 3u * S);
    EXPECT_EQ(st.sphere_records_read, 5u * S);
    EXPECT_EQ(st.triangle_records_read, 5u * 100);
    EXPECT_DOUBLE_EQ(st.area.total, 2 * (1.0 + 2.0));  // a PE and a memory per ICC
    EXPECT_EQ(simulate_system(t, config(MemorySystem::distributed, 5), st).total_cycles, std::uint64_t(S));
    EXPECT_EQ(simulate_system(t, config(MemorySystem::distributed, 9), st).total_cycles, std::uint64_t(S));
}

TEST(BaselineDistributed, TrianglePortBoundsWhenAGroupNeedsMoreTrianglesThanThereAreSpheres) {
    // 100 spheres of 4 triangles, every sphere hit: 400 triangle fetches per
    // group on the Triangle Memory port against 100 sphere reads.
    Trace t = test::hand_trace(100, 16, 0b1, 0b1, std::vector<bool>(100, true), 3);
    widen_spheres(t, 4);
    MemoryStats st;
    EXPECT_EQ(simulate_system(t, config(MemorySystem::distributed, 3), st).total_cycles, 400u);
    EXPECT_EQ(simulate_system(t, config(MemorySystem::distributed, 1), st).total_cycles, 1200u);
    SimConfig c = config(MemorySystem::distributed, 1);
    c.memory.records_per_cycle = 2;
    EXPECT_EQ(simulate_system(t, c, st).total_cycles, 600u);
}

TEST(BaselineDistributed, RtiBoundPesTakeTheLongerOfMemoryAndRtiPerGroup) {
    const std::uint32_t S = 300;
    Trace t = test::hand_trace(S, 16, 0b11, 0b111, std::vector<bool>(S, true), 4);
    SimConfig c = config(MemorySystem::distributed, 2);
    c.memory.pe_rti_bound = true;
    MemoryStats st;
    EXPECT_EQ(simulate_system(t, c, st).total_cycles, 2u * 6 * S);
    c.memory.pe_rti_bound = false;
    EXPECT_EQ(simulate_system(t, c, st).total_cycles, 2u * S);
}

TEST(BaselineDistributed, ShadowGroupsStartWhenEveryPrimaryGroupIsDone) {
    // Group 0 (primary) takes 6 S on the RTI; groups 1 and 2 (shadow) hit
    // nothing and take S each. On 2 ICCs: 6 S, then both shadow groups at once.
    const std::uint32_t S = 300;
    Trace t = test::hand_trace(S, 16, 0b11, 0b111, std::vector<bool>(S, true), 3);
    for (std::size_t g : {1, 2}) t.groups[g].sphere_hits.clear();
    make_shadow(t, 1);
    SimConfig c = config(MemorySystem::distributed, 2);
    c.memory.pe_rti_bound = true;
    MemoryStats st;
    EXPECT_EQ(simulate_system(t, c, st).total_cycles, 6u * S + S);
    c.memory.system = MemorySystem::shared;  // port: 300 then 0 fetches; RTI: 1800 then 0
    EXPECT_EQ(simulate_system(t, c, st).total_cycles, 6u * S);
}

TEST(BaselineDistributed, StreamFetchTakesEachGroupsOneIccStreamingPass) {
    // Runs the SystemC model once (one ICC): a pass with no hit lasts
    // S + L_psi + 2 cycles (test_top.cpp, AllSpheresMissed); 5 such groups on
    // 2 ICCs with their own copies: 3 passes' time.
    const std::uint32_t S = 200;
    Trace t = test::hand_trace(S, 16, 0, 0, std::vector<bool>(S, false), 5);
    SimConfig c = config(MemorySystem::distributed, 2);
    c.memory.distributed_stream = true;
    MemoryStats st;
    SimResult r = simulate_system(t, c, st);
    EXPECT_EQ(r.total_cycles, 3u * (S + c.icc.psi.stages + 2));
    EXPECT_EQ(st.triangle_records_read, 5u * S);
    EXPECT_EQ(st.memory_bound_cycles, 3u * S);
}

TEST(StreamingSystem, AreaCountsEachIccsFifosAndOneMemoryAndBoundsFollowThePasses) {
    // 5 groups on 2 ICCs: 3 passes, each streaming all S spheres and triangles.
    const std::uint32_t S = 200;
    Trace t = test::hand_trace(S, 16, 0, 0, std::vector<bool>(S, false), 5);
    SimConfig c = config(MemorySystem::streaming, 2);
    c.area.model = AreaModel::pe_units;
    c.area.icc_fifos = 0.5;
    MemoryStats st;
    SimResult r = simulate_system(t, c, st);
    EXPECT_EQ(r.total_cycles, 3u * (S + c.icc.psi.stages + 2));
    EXPECT_DOUBLE_EQ(st.area.total, 2 * (1.0 + 0.5) + 2.0);
    EXPECT_EQ(st.sphere_records_read, 3u * S);
    EXPECT_EQ(st.triangle_records_read, 3u * S);
    EXPECT_EQ(st.memory_bound_cycles, 3u * S);
    EXPECT_EQ(st.pe_bound_cycles, 0u);
}

TEST(StreamingSystem, PeBoundIsTheSlowestIccsRtiWorkPerPass) {
    // Group 0 of each pass hits every sphere (6 tests per triangle), group 1
    // none: each of the 2 passes is bounded below by 6 S RTI cycles.
    const std::uint32_t S = 100;
    Trace t = test::hand_trace(S, 16, 0b11, 0b111, std::vector<bool>(S, true), 4);
    t.groups[1].sphere_hits.clear();
    t.groups[3].sphere_hits.clear();
    MemoryStats st;
    SimResult r = simulate_system(t, config(MemorySystem::streaming, 2), st);
    EXPECT_EQ(st.pe_bound_cycles, 2u * 6 * S);
    EXPECT_GE(r.total_cycles, st.pe_bound_cycles);
}
