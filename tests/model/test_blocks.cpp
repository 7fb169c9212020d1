// Exact-cycle tests of single blocks, stepped by hand (no SystemC kernel run).
#include <gtest/gtest.h>

#include <random>

#include "bucket_queue.hpp"
#include "ring_queue.hpp"
#include "icc.hpp"

using namespace raplas;
using namespace raplas::model;

namespace {

// A GroupUnit whose plane tests hit spheres 0..99 with fixed masks and whose
// ray-triangle tests hit at t = ray + 1.
class FixedUnit : public GroupUnit {
public:
    std::vector<SphereHitRec> hits;
    std::vector<SphereRun> runs;
    FixedUnit() {
        for (std::uint32_t s = 0; s < 100; ++s) hits.push_back({s, 1, 1});
    }
    void load(const TraceGroup&) override {}
    const std::vector<SphereHitRec>& sphere_hits() const override { return hits; }
    const std::vector<SphereRun>& pairless() const override { return runs; }
    bool rti(std::uint32_t ray, std::uint32_t, double& t) override {
        t = ray + 1.0;
        return true;
    }
    std::uint32_t n = 16;  // group size, for rti_row's ray numbers
    std::uint64_t rti_row(std::uint32_t v, std::uint64_t cols, std::uint32_t tri, double* t) override {
        for (std::uint64_t cm = cols; cm; cm &= cm - 1) rti(v * n + std::uint32_t(__builtin_ctzll(cm)), tri, t[__builtin_ctzll(cm)]);
        return cols;
    }
    bool rti_certain_miss(std::uint64_t, std::uint64_t, std::uint32_t) const override { return false; }  // every test hits
};

}  // namespace

TEST(PlaneSphereIntersector, FirstResultExactlyTenCyclesAfterItsInput) {
    PlaneSphereIntersector psi({32, 10});
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
    PlaneSphereIntersector psi({8, 10});
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
    PlaneSphereIntersector psi({32, 10});
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
    RayTriangleIntersector rti({1, 25});
    MinDistanceMemory mem({});
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
    RayDataFetcher rdf({1});
    RayTriangleIntersector rti({1, 25});
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

TEST(RayDataFetcher, ATriangleWithNoPairHoldsItForItsEmptyCycles) {
    // Triangles: 2 pairs, no pair, 1 pair. With e = 3 the empty one is popped
    // in cycle 2 and holds the Fetcher through cycle 4: the last pair enters
    // in cycle 5. With e = 0 it is dropped in the cycle it is reached (2),
    // and the next triangle issues in that same cycle.
    for (std::uint32_t e : {0u, 1u, 3u}) {
        RayDataFetcher rdf({e});
        RayTriangleIntersector rti({1, 25});
        Fifo<TriWork> in(("tri_fifo_e" + std::to_string(e)).c_str(), {4});
        rdf.start_group(4);
        rti.start_group();
        in.push({1, 0b1, 0b11});  // 2 pairs
        in.push({2, 0b1, 0});     // no pair
        in.push({3, 0b10, 0b1});  // 1 pair
        std::vector<int> issue_cycles;
        int idle_from = -1;
        for (int c = 0; c < 12; ++c) {
            const auto before = rti.stats().tests;
            rdf.tick(in, rti);
            if (rti.stats().tests > before) issue_cycles.push_back(c);
            if (idle_from < 0 && rdf.idle() && in.empty()) idle_from = c;
            rti.advance();
        }
        const int last = 2 + int(std::max(e, 1u));  // e = 0: same cycle as the drop; else after e cycles
        EXPECT_EQ(issue_cycles, (std::vector<int>{0, 1, e == 0 ? 2 : last})) << "e = " << e;
        EXPECT_EQ(idle_from, e == 0 ? 2 : last) << "e = " << e;
        EXPECT_EQ(rdf.stats().triangles, 3u);
        EXPECT_EQ(rdf.stats().empty_triangles, 1u);
        EXPECT_EQ(rti.stats().tests, 3u);
    }
}

TEST(Decoder, QueuesPairlessSpheresOnlyUnderTheAnyReading) {
    for (TriangleSelect sel : {TriangleSelect::both, TriangleSelect::any}) {
        const std::string tag = sel == TriangleSelect::any ? "any" : "both";
        PlaneSphereIntersector psi({32, 1});
        SphereFifo in(("sfifo_" + tag).c_str(), {8});
        Decoder dec({sel});
        Fifo<PlaneIdEntry> pid(("pid_" + tag).c_str(), {8});
        Fifo<FirstTriEntry> ftid(("ftid_" + tag).c_str(), {8});
        SphereMemory mem({});
        std::vector<SphereRecord> recs(4);
        for (std::uint32_t s = 0; s < 4; ++s) recs[s] = {Sphere{}, s, 1};
        mem.load(recs);
        const std::vector<SphereHitRec> hits{{1, 0b1, 0b1}};
        const std::vector<SphereRun> pairless{{2, 2}};  // spheres 2 and 3
        psi.start_group(32, &hits, &pairless);
        dec.start_group();
        for (std::uint32_t s = 0; s < 4; ++s) in.push(s);
        for (int c = 0; c < 10; ++c) {
            const bool hold = dec.tick(psi, pid, ftid, SphereInfo{&mem});
            psi.tick(in, hold, false);
        }
        EXPECT_EQ(dec.decided(), 4u);
        std::vector<std::uint32_t> queued;
        for (; !ftid.empty(); ftid.pop()) queued.push_back(ftid.front().sphere);
        if (sel == TriangleSelect::any) {
            EXPECT_EQ(queued, (std::vector<std::uint32_t>{1, 2, 3}));
            EXPECT_EQ(dec.stats().pairless, 2u);
        } else {
            EXPECT_EQ(queued, (std::vector<std::uint32_t>{1}));
            EXPECT_EQ(dec.stats().pairless, 0u);
        }
    }
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
    TriangleSelector sel({StallPolicy::any_full});
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
    TriangleSelector lenient({StallPolicy::needed_full});
    EXPECT_TRUE(lenient.ready(true, 4, 5, ftid, tf));
}

// The event mode's queue of ICCs by stream position, against a plain search
// of every ICC's key: ICCs pushed at or after the stream position (the last
// key taken), those taken sometimes pushed again at larger keys, and the
// smallest key always the one the search finds. Pushes below the smallest
// key followed by a take (an ICC queued just ahead of the stream, far below
// the others) are among the cases drawn.
// A cursor set at sphere s gives the kept spheres from s on, as one walked from the start does.
TEST(KeptSpheres, SeekGivesTheKeptSpheresFromThereOn) {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<SphereHitRec> hits;
        std::vector<SphereRun> runs;
        std::uint32_t s = 0;
        while (s < 200) {  // hit spheres, pair-less runs and gaps, in sphere order
            const std::uint32_t r = std::uint32_t(rng() % 4), n = 1 + std::uint32_t(rng() % 5);
            if (r == 0) hits.push_back({s, 0b1, 0b10});
            if (r == 1) add_to_runs(runs, s, n);
            s += r == 1 ? n : 1 + std::uint32_t(rng() % 3);
        }
        const std::vector<SphereRun>* const readings[] = {&runs, nullptr};  // any, both
        for (const std::vector<SphereRun>* rp : readings) {
            std::vector<std::uint32_t> all;
            KeptSpheres walk(hits, rp);
            while (walk.next()) all.push_back(walk.sphere);
            for (std::uint32_t from = 0; from <= s; from += 1 + std::uint32_t(rng() % 7)) {
                KeptSpheres e(hits, rp);
                e.seek(from);
                std::vector<std::uint32_t> got;
                while (e.next()) got.push_back(e.sphere);
                std::vector<std::uint32_t> want;
                for (std::uint32_t x : all)
                    if (x >= from) want.push_back(x);
                ASSERT_EQ(got, want) << "trial " << trial << ", from " << from << (rp ? ", any" : ", both");
            }
        }
    }
}

TEST(BucketQueue, SmallestKeyIsAlwaysTheSmallestUsedOne) {
    std::mt19937 rng(7);
    BucketQueue q;  // (reset for every trial, as for every pass: with the same keys, emptied or not, or others)
    for (int trial = 0; trial < 2000; ++trial) {
        const std::uint32_t keys = 16 + 3 * std::uint32_t(trial / 4 % 200), iccs = 1 + std::uint32_t(trial % 9);
        q.reset(keys, iccs);
        std::vector<std::int64_t> key_of(iccs, -1);
        std::uint32_t pos = 0;
        std::size_t taken = 0;
        for (int step = 0; step < 300; ++step) {
            if (rng() % 3 < 2) {
                const std::uint32_t k = std::uint32_t(rng() % iccs);
                if (key_of[k] >= 0) continue;
                const std::uint32_t key = pos + std::uint32_t(rng() % (keys - pos));
                q.push(key, k);
                key_of[k] = key;
            } else if (!q.empty()) {
                std::int64_t smallest = -1;
                for (std::int64_t x : key_of)
                    if (x >= 0 && (smallest < 0 || x < smallest)) smallest = x;
                const std::uint32_t m = q.min_key();
                ASSERT_EQ(std::int64_t(m), smallest) << "trial " << trial << ", step " << step;
                pos = m;
                q.pop_min([&](std::uint32_t k) {
                    ASSERT_EQ(key_of[k], std::int64_t(m));
                    key_of[k] = -1;
                    ++taken;
                    if (rng() % 2 && m + 1 < keys) {
                        const std::uint32_t key = m + 1 + std::uint32_t(rng() % (keys - m - 1));
                        q.push(key, k);
                        key_of[k] = key;
                    }
                });
            }
            std::size_t queued = 0;
            for (std::int64_t x : key_of) queued += x >= 0;
            ASSERT_EQ(q.empty(), queued == 0);
        }
        ASSERT_GT(taken, 0u);
    }
}

// The Triangle FIFO's record of pop cycles counts the entries that pop in the
// same cycle as the one before them (the event mode's coasts rely on it):
// against a recount, through pushes, pops, growth and a shift of every entry.
TEST(RingQueue, TiesAreTheEntriesEqualToTheOneBefore) {
    std::mt19937 rng(11);
    RingQueue q;
    std::uint64_t last = 100;
    std::size_t seen_ties = 0;
    for (int step = 0; step < 20000; ++step) {
        if (q.empty() || rng() % 5 < 3) {
            last += rng() % 3 == 0 ? 0 : 1 + rng() % 4;  // (a third pop in the same cycle as the one before)
            q.push_back(last);
        } else {
            q.pop_front();
        }
        if (step % 997 == 0) {  // the event mode moves every entry to the next pass's cycles
            for (std::size_t i = 0; i < q.size(); ++i) q[i] -= 50;
            last -= 50;
        }
        std::uint32_t ties = 0;
        for (std::size_t i = 1; i < q.size(); ++i) ties += q[i] == q[i - 1];
        ASSERT_EQ(q.ties(), ties) << "step " << step;
        seen_ties += ties;
    }
    EXPECT_GT(seen_ties, 0u);
}
