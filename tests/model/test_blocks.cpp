// Exact-cycle tests of single blocks, stepped by hand (no SystemC kernel run).
#include <gtest/gtest.h>

#include "icc.hpp"

using namespace raplas;
using namespace raplas::model;

namespace {

// A GroupUnit whose plane tests hit spheres 0..99 with fixed masks and whose
// ray-triangle tests hit at t = ray + 1.
class FixedUnit : public GroupUnit {
public:
    std::vector<SphereHitRec> hits;
    FixedUnit() {
        for (std::uint32_t s = 0; s < 100; ++s) hits.push_back({s, 1, 1});
    }
    void load(const TraceGroup&) override {}
    const std::vector<SphereHitRec>& sphere_hits() const override { return hits; }
    bool rti(std::uint32_t ray, std::uint32_t, double& t) override {
        t = ray + 1.0;
        return true;
    }
};

}  // namespace

TEST(PlaneSphereIntersector, FirstResultExactlyTenCyclesAfterItsInput) {
    PlaneSphereIntersector psi("psi_a", {32, 10});
    SphereFifo in("fifo_a", {8});
    FixedUnit unit;
    psi.start_group(32, &unit.sphere_hits());
    in.push(7);
    std::int64_t out_cycle = -1;
    for (std::uint64_t c = 0; c < 30 && out_cycle < 0; ++c) {
        if (psi.has_output()) {
            out_cycle = std::int64_t(c);
            EXPECT_EQ(psi.output().sphere, 7u);
            break;
        }
        psi.tick(in, false, false);  // input enters in cycle 0
    }
    EXPECT_EQ(out_cycle, 10);
}

TEST(PlaneSphereIntersector, PlanesBeyondThePipesTakeExtraCycles) {
    // 32 planes on 8 pipes: 4 batches, result 3 + 10 cycles after the first batch;
    // the next sphere enters 4 cycles after the first.
    PlaneSphereIntersector psi("psi_b", {8, 10});
    SphereFifo in("fifo_b", {8});
    FixedUnit unit;
    psi.start_group(32, &unit.sphere_hits());
    in.push(1);
    in.push(2);
    std::vector<std::uint64_t> outs;
    for (std::uint64_t c = 0; c < 40; ++c) {
        if (psi.has_output()) {
            outs.push_back(c);
            psi.pop_output();
        }
        psi.tick(in, false, false);
    }
    ASSERT_EQ(outs.size(), 2u);
    EXPECT_EQ(outs[0], 13u);
    EXPECT_EQ(outs[1], 17u);
}

TEST(PlaneSphereIntersector, HoldsWholePipeWhileTheDecoderIsFull) {
    PlaneSphereIntersector psi("psi_c", {32, 10});
    SphereFifo in("fifo_c", {8});
    FixedUnit unit;
    psi.start_group(32, &unit.sphere_hits());
    in.push(1);
    in.push(2);
    std::vector<std::uint64_t> outs;
    for (std::uint64_t c = 0; c < 30; ++c) {
        bool hold = false;
        if (psi.has_output()) {
            if (c < 15) hold = true;  // decoder full until cycle 15
            else {
                outs.push_back(c);
                psi.pop_output();
            }
        }
        psi.tick(in, hold, false);
    }
    // sphere 1 ready at 10 but held until 15; sphere 2 entered at 1, one stage
    // behind, so it leaves the cycle after
    ASSERT_EQ(outs.size(), 2u);
    EXPECT_EQ(outs[0], 15u);
    EXPECT_EQ(outs[1], 16u);
    EXPECT_EQ(psi.stats().stall_cycles, 5u);
}

TEST(RayTriangleIntersector, FirstResultExactlyTwentyFiveCyclesAfterItsInput) {
    RayTriangleIntersector rti("rti_a", {1, 25});
    MinDistanceMemory mem("mem_a", {});
    FixedUnit unit;
    rti.start_group();
    mem.reset(4);
    std::int64_t seen = -1;
    for (std::uint64_t c = 0; c < 40; ++c) {
        rti.retire(unit, mem);
        if (seen < 0 && mem.hits()[2].tri >= 0) seen = std::int64_t(c);
        if (c == 0) {
            ASSERT_TRUE(rti.can_issue());
            rti.issue({2, 9});
            EXPECT_FALSE(rti.can_issue());  // one pipe: one pair per cycle
        }
        rti.advance();
    }
    EXPECT_EQ(seen, 25);
    EXPECT_EQ(mem.hits()[2].tri, 9);
    EXPECT_TRUE(rti.empty());
}

TEST(RayDataFetcher, IssuesOnePairPerCycleForRowsTimesColumns) {
    RayDataFetcher rdf("rdf_a");
    RayTriangleIntersector rti("rti_b", {1, 25});
    Fifo<TriWork> in("tri_fifo_a", {4});
    rdf.start_group(4);
    rti.start_group();
    in.push({5, 0b0101, 0b0110});  // rows {0,2} x cols {1,2}: 4 pairs
    in.push({6, 0b1000, 0b0001});  // 1 pair
    std::uint64_t issued_cycles = 0;
    for (int c = 0; c < 10; ++c) {
        const auto before = rti.stats().tests;
        rdf.tick(in, rti);
        issued_cycles += rti.stats().tests - before;
        rti.advance();
    }
    EXPECT_EQ(rti.stats().tests, 5u);
    EXPECT_EQ(rti.stats().busy_cycles, 5u);
    EXPECT_EQ(rdf.stats().triangles, 2u);
    EXPECT_TRUE(rdf.idle());
}

TEST(Fifo, RefusesWhenFullAndTracksOccupancy) {
    Fifo<int> f("fifo_d", {3});
    EXPECT_TRUE(f.empty());
    f.push(1);
    f.push(2);
    f.push(3);
    EXPECT_TRUE(f.full());
    EXPECT_EQ(f.front(), 1);
    f.pop();
    f.push(4);
    EXPECT_EQ(f.front(), 2);
    EXPECT_EQ(f.stats().max_occupancy, 3u);
    EXPECT_EQ(f.stats().pushes, 4u);
    EXPECT_THROW(Fifo<int>("fifo_e", {0}), std::invalid_argument);
}

TEST(TriangleSelector, WaitsForTheDecisionThenSelectsOrDiscards) {
    TriangleSelector sel("sel_a", {StallPolicy::any_full});
    Fifo<PlaneIdEntry> pid("pid_a", {4});
    Fifo<FirstTriEntry> ftid("ftid_a", {4});
    Fifo<TriWork> tf("tf_a", {2});
    // sphere 3 undecided: not ready
    EXPECT_FALSE(sel.ready(true, 3, 3, ftid, tf));
    EXPECT_TRUE(sel.ready(false, 3, 0, ftid, tf));  // an idle ICC never holds the link
    pid.push({0b11, 0b1});
    ftid.push({3, 10, 2});
    EXPECT_TRUE(sel.ready(true, 3, 4, ftid, tf));
    sel.receive(true, 9, 2, pid, ftid, tf);   // sphere 2: not hit, discarded
    sel.receive(true, 10, 3, pid, ftid, tf);  // first of sphere 3
    sel.receive(true, 11, 3, pid, ftid, tf);  // last of sphere 3: entry popped
    sel.end_group(3, 0);                      // 3 triangles passed, 2 selected
    EXPECT_EQ(sel.stats().discarded, 1u);
    EXPECT_EQ(sel.stats().selected, 2u);
    EXPECT_TRUE(ftid.empty());
    EXPECT_TRUE(pid.empty());
    EXPECT_TRUE(tf.full());
    // full Triangle FIFO: any_full holds the link even for an unwanted triangle,
    // needed_full does not
    EXPECT_FALSE(sel.ready(true, 4, 5, ftid, tf));
    TriangleSelector lenient("sel_b", {StallPolicy::needed_full});
    EXPECT_TRUE(lenient.ready(true, 4, 5, ftid, tf));
}
