// The machine as a SystemC netlist (sim.mode = netlist): one clock at
// machine.clock_mhz, the Host, Sphere and Triangle Memory (TLM-2.0 targets),
// the two Stream Links and K ICCs, bound here into the top module. Every
// block is a module with ports and a process of its own; FIFOs are channels;
// what crosses blocks within a cycle are combinational signals that settle
// in delta cycles. The blocks step the same block state (Icc, StreamLink,
// the memories) as the event engine, so the statistics are
// gathered the same way (docs/MODEL.md §2).
#pragma once

#include <systemc>
#include <tlm>

#include <deque>
#include <functional>
#include <memory>
#include <vector>

#include "host_module.hpp"
#include "icc_module.hpp"
#include "memory_target.hpp"
#include "signals.hpp"
#include "stream_link_module.hpp"

namespace raplas::model {
struct SimConfig;
}

namespace raplas::model::netlist {

// Binds a Stream Link's initiator socket `link` to a memory model: called
// during elaboration (a module it creates becomes a child of the top module)
// with the default target `memory`, which holds the records (a model may
// forward its reads to it). It returns the module it made, which the netlist
// then owns (or null). Empty: `link` is bound to `memory` (docs/MODEL.md §2,
// "Binding a memory model").
using LinkSocket = tlm::tlm_initiator_socket<>;
template <class Target>
using BindMemory = std::function<std::unique_ptr<sc_core::sc_module>(LinkSocket& link, Target& memory)>;
using BindSphereMemory = BindMemory<SphereMemoryTarget>;
using BindTriangleMemory = BindMemory<TriangleMemoryTarget>;

// The state the netlist's modules step: the blocks of the event engine.
struct MachineState {
    const Host& host;
    std::deque<Icc>& iccs;
    StreamLink& sphere_link;
    StreamLink& triangle_link;
    SphereMemory& sphere_memory;
    TriangleMemory& triangle_memory;
};

class Netlist {
public:
    // Built during the elaboration of the top module, whose children its
    // modules and signals become.
    Netlist(const SimConfig& cfg, const MachineState& state, bool results_from_trace,
            const BindSphereMemory& bind_spheres = {}, const BindTriangleMemory& bind_triangles = {});

    // Every signal, port and FIFO of the netlist in the waveform, by hierarchical name.
    void trace(sc_core::sc_trace_file* tf) const;

    sc_core::sc_clock clock;
    sc_core::sc_signal<std::uint32_t> pass;
    sc_core::sc_signal<LinkRecord> sphere_record, triangle_record;
    sc_core::sc_signal<bool> sphere_valid, sphere_stall, sphere_more, sphere_done;
    sc_core::sc_signal<bool> triangle_valid, triangle_stall, triangle_more, triangle_done;
    sc_core::sc_vector<sc_core::sc_signal<bool>> sphere_ready, triangle_ready;
    sc_core::sc_vector<sc_core::sc_signal<bool>> triangle_hold;           // the stall anatomy's wires
    sc_core::sc_signal<std::uint32_t> triangle_holders, sphere_holders;  // (the sphere link's: unused)
    sc_core::sc_vector<sc_core::sc_signal<BufMask>> fetcher_busy, rti_busy;

    HostModule host;
    SphereMemoryTarget sphere_memory;
    TriangleMemoryTarget triangle_memory;
    SphereStreamLink sphere_link;
    TriangleStreamLink triangle_link;
    sc_core::sc_vector<IccModule> iccs;

private:
    std::vector<std::unique_ptr<sc_core::sc_module>> memory_models_;  // bound by the caller (destroyed first)
};

}  // namespace raplas::model::netlist
