// The watchdog: a machine in which one block stops (fault injection,
// sim.fault) ends with an error naming the stuck block, the blocks held behind
// it and the FIFO states, in every timing mode. One simulation per process.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>

#include "hand_trace.hpp"
#include "top.hpp"

using namespace raplas;
using namespace raplas::model;
using ::testing::HasSubstr;
using ::testing::Not;

namespace {

// 200 one-triangle spheres, every one hit by 4 x 4 rays of both groups; two
// ICCs with 4-deep Sphere and Triangle FIFOs.
constexpr std::uint32_t kSpheres = 200;

SimConfig faulty(SimMode mode, Fault fault, std::uint32_t icc) {
    SimConfig c;
    c.mode = mode;
    c.iccs = 2;
    c.icc.sphere_fifo.depth = 4;
    c.icc.triangle_fifo.depth = 4;
    c.icc.planeid_fifo.depth = 16;
    c.functional = FunctionalMode::trace;
    c.watchdog_cycles = 5000;
    c.sync_cycles = 512;
    c.fault = fault;
    c.fault_icc = icc;
    return c;
}

Trace two_groups() { return test::hand_trace(kSpheres, 4, 0b1111, 0b1111, std::vector<bool>(kSpheres, true), 2); }

// The watchdog's message, or "" when the simulation finished.
std::string watchdog_message(const Trace& t, const SimConfig& c) {
    const SimResult r = simulate(t, c);
    EXPECT_EQ(r.error.empty(), r.total_cycles > 0);
    return r.error;
}

// The cycle the watchdog fired at ("... at cycle N; ...").
std::uint64_t cycle_of(const std::string& msg) {
    const std::size_t at = msg.find(" at cycle ");
    return at == std::string::npos ? 0 : std::strtoull(msg.c_str() + at + 10, nullptr, 10);
}

class Watchdog : public ::testing::TestWithParam<SimMode> {};

}  // namespace

TEST_P(Watchdog, StuckRayTriangleIntersectorIsNamedWithItsFullTriangleFifo) {
    const SimConfig c = faulty(GetParam(), Fault::stuck_rti, 1);
    const std::string msg = watchdog_message(two_groups(), c);
    ASSERT_THAT(msg, HasSubstr("watchdog: no progress for 5000 cycles (sim.watchdog_cycles)"));
    EXPECT_EQ(msg.find('\n'), std::string::npos);
    // the stuck block, and only it
    EXPECT_THAT(msg, HasSubstr("stuck: icc_1.rti (takes no ray-triangle pair; triangle_fifo 4/4 full); held:"));
    EXPECT_THAT(msg, Not(HasSubstr("icc_0.rti")));
    // ICC 1 took 4 triangles and the broadcast stopped at the fifth. Both ICCs
    // then decided 4 + 16 spheres (16 hits wait in each PlaneID FIFO), which
    // holds both PSIs with 10 spheres in their stages and 4 in their Sphere
    // FIFOs: the sphere stream stopped at 20 + 10 + 4 = 34.
    EXPECT_THAT(msg, HasSubstr("held: icc_0.psi (planeid_fifo 16/16 full), icc_1.psi (planeid_fifo 16/16 full), "
                               "sphere_stream_link at record 34/200 (icc_0.sphere_fifo full, icc_1.sphere_fifo full), "
                               "triangle_stream_link at record 4/200 (icc_1.triangle_fifo full);"));
    EXPECT_THAT(msg, HasSubstr("FIFOs: icc_0 sphere_fifo 4/4 full, planeid_fifo 16/16 full, triangle_fifo 0/4, decided 20; "
                               "icc_1 sphere_fifo 4/4 full, planeid_fifo 16/16 full, triangle_fifo 4/4 full, decided 20"));
    EXPECT_THAT(msg, HasSubstr("[fault injected: sim.fault = stuck_rti, sim.fault_icc = 1]"));
    // found within one sync interval of the watchdog period after the stall
    // (the stall starts within the first few hundred cycles)
    EXPECT_GE(cycle_of(msg), c.watchdog_cycles);
    EXPECT_LE(cycle_of(msg), c.watchdog_cycles + c.sync_cycles + 1000);
}

TEST_P(Watchdog, StuckPlaneSphereIntersectorIsNamedWithItsFullSphereFifo) {
    const SimConfig c = faulty(GetParam(), Fault::stuck_psi, 0);
    const std::string msg = watchdog_message(two_groups(), c);
    ASSERT_THAT(msg, HasSubstr("watchdog: no progress for 5000 cycles"));
    EXPECT_THAT(msg, HasSubstr("stuck: icc_0.psi (takes no sphere; sphere_fifo 4/4 full); held:"));
    EXPECT_THAT(msg, Not(HasSubstr("icc_1.psi")));
    // ICC 0 took 4 spheres and decided none: both links wait for it
    EXPECT_THAT(msg, HasSubstr("sphere_stream_link at record 4/200 (icc_0.sphere_fifo full)"));
    EXPECT_THAT(msg, HasSubstr("triangle_stream_link at record 0/200 (icc_0 has not decided sphere 0)"));
    EXPECT_THAT(msg, HasSubstr("icc_0 sphere_fifo 4/4 full, planeid_fifo 0/16, triangle_fifo 0/4, decided 0"));
    // ICC 1 decided the 4 spheres it got: all hits, queued for the triangle stream
    EXPECT_THAT(msg, HasSubstr("icc_1 sphere_fifo 0/4, planeid_fifo 4/16, triangle_fifo 0/4, decided 4"));
    EXPECT_GE(cycle_of(msg), c.watchdog_cycles);
    EXPECT_LE(cycle_of(msg), c.watchdog_cycles + c.sync_cycles + 1000);
}

TEST_P(Watchdog, FaultOnAnIccWithoutAGroupChangesNothing) {
    // One group on two ICCs: ICC 1 is idle, its stuck RTI is never used.
    Trace t = test::hand_trace(kSpheres, 4, 0b1111, 0b1111, std::vector<bool>(kSpheres, true), 1);
    const SimResult r = simulate(t, faulty(GetParam(), Fault::stuck_rti, 1));
    EXPECT_EQ(r.error, "");
    // the closed form of an RTI-bound pass (tests/model/test_top.cpp):
    // S*m + L_rti + L_psi + 3 cycles, m = 16 tests per triangle
    const SimConfig c;
    EXPECT_EQ(r.total_cycles, std::uint64_t(kSpheres) * 16 + c.icc.rti.stages + c.icc.psi.stages + 3);
}

INSTANTIATE_TEST_SUITE_P(Modes, Watchdog, ::testing::Values(SimMode::event, SimMode::netlist),
                         [](const ::testing::TestParamInfo<SimMode>& i) {
                             return std::string(i.param == SimMode::event ? "event" : "netlist");
                         });
