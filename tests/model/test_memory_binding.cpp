// The netlist's memories behind TLM-2.0 (sim.mode = netlist): a memory model
// of the user's bound to a Stream Link's initiator socket in place of the
// default target changes the cycles exactly as a closed form says. One
// simulation per process.
#include <gtest/gtest.h>

#include <tlm_utils/simple_initiator_socket.h>
#include <tlm_utils/simple_target_socket.h>

#include <functional>

#include "hand_trace.hpp"
#include "netlist/netlist.hpp"
#include "top.hpp"

using namespace raplas;
using namespace raplas::model;

namespace {

// A memory of the user's: every read goes to the records (the default
// target, through its own initiator socket) and takes `latency(index)` on
// top, annotated as b_transport's delay.
class SlowMemory : public sc_core::sc_module {
public:
    tlm_utils::simple_target_socket<SlowMemory> target;
    tlm_utils::simple_initiator_socket<SlowMemory> records;
    SlowMemory(sc_core::sc_module_name n, std::uint32_t record_bytes, std::function<sc_core::sc_time(std::uint64_t)> latency)
        : sc_core::sc_module(n), target("target"), records("records"), record_bytes_(record_bytes), latency_(std::move(latency)) {
        target.register_b_transport(this, &SlowMemory::b_transport);
    }
    std::uint64_t reads = 0;

private:
    void b_transport(tlm::tlm_generic_payload& t, sc_core::sc_time& delay) {
        records->b_transport(t, delay);
        delay += latency_(t.get_address() / record_bytes_);
        ++reads;
    }
    std::uint32_t record_bytes_;
    std::function<sc_core::sc_time(std::uint64_t)> latency_;
};

const sc_core::sc_time kPeriod(2500, sc_core::SC_PS);  // 400 MHz

// Binds a SlowMemory with `latency` in place of a default target.
template <class Target>
SimOptions::BindMemory<Target> slow(std::function<sc_core::sc_time(std::uint64_t)> latency) {
    return [latency](tlm::tlm_initiator_socket<>& link, Target& memory) {
        auto m = std::make_unique<SlowMemory>("slow_memory", memory.record_bytes(), latency);
        link.bind(m->target);
        m->records.bind(memory.socket);
        return std::unique_ptr<sc_core::sc_module>(std::move(m));
    };
}

// S one-triangle spheres that no plane hits, one ICC (tests/model/test_top.cpp:
// S + L_psi + 2 cycles with the default memories: sphere i is sent in cycle
// i and decided in cycle i + 1 + L_psi, triangle i sent one cycle later).
constexpr std::uint32_t kS = 500;
SimConfig netlist_config() {
    SimConfig c;
    c.mode = SimMode::netlist;
    c.iccs = 1;
    c.functional = FunctionalMode::trace;
    return c;
}
SimResult run(const SimOptions& opt) {
    const Trace t = test::hand_trace(kS, 16, 0, 0, std::vector<bool>(kS, false));
    return simulate(t, netlist_config(), opt);
}

}  // namespace

TEST(MemoryBinding, DefaultTargetsSendOneRecordPerCycle) {
    const SimConfig c = netlist_config();
    const SimResult r = run({});
    EXPECT_EQ(r.total_cycles, kS + c.icc.psi.stages + 2);
    EXPECT_EQ(r.triangle_link.stall_cycles, c.icc.psi.stages + 2);
    EXPECT_EQ(r.triangle_memory.reads, kS);
}

TEST(MemoryBinding, ATriangleEveryTwoCyclesDoublesTheTriangleStream) {
    // Each read takes one more cycle: record 0, asked for in cycle 0, is on
    // the link from cycle 1; the one after a record sent in cycle c from
    // cycle c + 2. The decisions come a cycle apart, so the memory sets the
    // pace: triangle i goes in cycle L_psi + 2 + 2i, the last in
    // L_psi + 2S, and the pass ends a cycle later: 2S + L_psi + 1. The link
    // stalls in cycles 1 .. L_psi + 1 (triangle 0 waiting for its decision);
    // the S cycles it waits for its memory are neither stalls nor idle.
    const SimConfig c = netlist_config();
    SimOptions opt;
    opt.bind_triangle_memory = slow<netlist::TriangleMemoryTarget>([](std::uint64_t) { return kPeriod; });
    const SimResult r = run(opt);
    const std::uint64_t L = c.icc.psi.stages;
    EXPECT_EQ(r.total_cycles, 2 * kS + L + 1);
    EXPECT_EQ(r.triangle_link.records_sent, kS);
    EXPECT_EQ(r.triangle_link.stall_cycles, L + 1);
    EXPECT_EQ(r.triangle_link.idle_cycles, 0u);
    EXPECT_EQ(r.triangle_memory.reads, kS);
    EXPECT_EQ(r.sphere_link.records_sent, kS);
}

TEST(MemoryBinding, ASphereEveryTwoCyclesHalvesTheRateOfDecisions) {
    // Sphere i is on the link from cycle 1 + 2i (sent then: the ICC always
    // has room), enters the PSI in cycle 2 + 2i and is decided in cycle
    // 2 + 2i + L_psi; triangle i follows a cycle later. The last, S - 1,
    // goes in cycle 2S + 1 + L_psi: 2S + L_psi + 2 cycles.
    const SimConfig c = netlist_config();
    SimOptions opt;
    opt.bind_sphere_memory = slow<netlist::SphereMemoryTarget>([](std::uint64_t) { return kPeriod; });
    const SimResult r = run(opt);
    const std::uint64_t L = c.icc.psi.stages;
    EXPECT_EQ(r.total_cycles, 2 * kS + L + 2);
    EXPECT_EQ(r.sphere_link.records_sent, kS);
    EXPECT_EQ(r.sphere_link.stall_cycles, 0u);
    EXPECT_EQ(r.sphere_memory.reads, kS);
    // (the PSI waits for every other sphere: its input is free and the stream not done)
    EXPECT_EQ(r.iccs[0].psi.starved_cycles, kS);
}

TEST(MemoryBinding, AFixedLatencyPerBurstAddsItOncePerBurst) {
    // Bursts of B records: the first of each costs `lat` cycles, the rest
    // none. Record 0 is on the link long before its sphere is decided; every
    // later burst start, asked for the cycle after the record before it was
    // sent, comes `lat` cycles late. Triangle i thus goes in cycle
    // L_psi + 2 + i + lat * floor(i / B): S + L_psi + 2 + lat * floor((S - 1) / B) cycles.
    constexpr std::uint64_t B = 16, lat = 5;
    const SimConfig c = netlist_config();
    SimOptions opt;
    opt.bind_triangle_memory = slow<netlist::TriangleMemoryTarget>(
        [](std::uint64_t i) { return i % B == 0 ? kPeriod * double(lat) : sc_core::SC_ZERO_TIME; });
    const SimResult r = run(opt);
    const std::uint64_t L = c.icc.psi.stages;
    EXPECT_EQ(r.total_cycles, kS + L + 2 + lat * ((kS - 1) / B));
    EXPECT_EQ(r.triangle_link.records_sent, kS);
    EXPECT_EQ(r.triangle_memory.reads, kS);
}

TEST(MemoryBinding, AReadTheMemoryRefusesStopsTheRunWithItsReason) {
    // A model that answers with an error response: the run stops, and says
    // why in SimResult::error (as the watchdog does).
    SimOptions opt;
    opt.bind_sphere_memory = [](tlm::tlm_initiator_socket<>& link, netlist::SphereMemoryTarget&) {
        struct Broken : sc_core::sc_module {
            tlm_utils::simple_target_socket<Broken> target{"target"};
            explicit Broken(sc_core::sc_module_name n) : sc_core::sc_module(n) {
                target.register_b_transport(this, &Broken::b_transport);
            }
            void b_transport(tlm::tlm_generic_payload& t, sc_core::sc_time&) {
                t.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
            }
        };
        auto m = std::make_unique<Broken>("broken_memory");
        link.bind(m->target);
        return std::unique_ptr<sc_core::sc_module>(std::move(m));
    };
    const SimResult r = run(opt);
    EXPECT_EQ(r.error, "raplas.sphere_stream_link: reading record 0: TLM_ADDRESS_ERROR_RESPONSE");
    EXPECT_EQ(r.total_cycles, 0u);
}
