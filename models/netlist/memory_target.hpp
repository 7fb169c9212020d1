// Sphere Memory and Triangle Memory as TLM-2.0 targets (sim.mode = netlist):
// the Stream Links read one record per transaction through their initiator
// sockets, with b_transport and an annotated delay. The default targets
// answer with no delay: a record asked for in a cycle is on the link in that
// cycle, so a link sends one record per cycle, as the paper's Table 1 says
// and as the event engine count. A target that adds a delay d holds the
// record back ceil(d / clock period) cycles. Any target that serves the same
// payload can be bound in their place (SimOptions::bind_memory,
// docs/MODEL.md §2).
//
// Transactions: a read (TLM_READ_COMMAND) of one record; the address is the
// record's index times its size on the link (link.sphere_record_bytes,
// link.triangle_record_bytes); the data is the model's record, SphereRecord
// or TriangleRecord below (data_length = its sizeof). b_transport is called
// from a clocked SC_METHOD: a target must not wait(), it annotates the delay.
#pragma once

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_target_socket.h>

#include <cstring>

#include "../memories.hpp"

namespace raplas::model::netlist {

// What a read of Triangle Memory returns: the triangle and its sphere.
struct TriangleRecord {
    TriangleRec tri;
    std::uint32_t sphere = 0;
};

// The target of one memory. `Mem` is SphereMemory or TriangleMemory (the
// records and their read counts, shared with the event engine).
template <class Mem>
class MemoryTarget : public sc_core::sc_module {
public:
    using Params = typename Mem::Params;
    using Stats = typename Mem::Stats;

    // (optional: a memory model bound in its place need not forward to it)
    tlm_utils::simple_target_socket_optional<MemoryTarget> socket;

    MemoryTarget(sc_core::sc_module_name n, Mem& mem, std::uint32_t record_bytes)
        : sc_core::sc_module(n), socket("socket"), mem_(mem), record_bytes_(record_bytes) {
        socket.register_b_transport(this, &MemoryTarget::b_transport);
    }
    std::uint32_t record_bytes() const { return record_bytes_; }
    const Params& params() const { return mem_.params(); }
    const Stats& stats() const { return mem_.stats(); }
    std::size_t records() const { return mem_.size(); }

    void b_transport(tlm::tlm_generic_payload& t, sc_core::sc_time&) {
        const std::uint64_t i = t.get_address() / record_bytes_;
        if (t.get_command() != tlm::TLM_READ_COMMAND) {
            t.set_response_status(tlm::TLM_COMMAND_ERROR_RESPONSE);
            return;
        }
        if (t.get_address() % record_bytes_ || i >= mem_.size()) {
            t.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
            return;
        }
        if (!read(std::size_t(i), t)) {
            t.set_response_status(tlm::TLM_BURST_ERROR_RESPONSE);
            return;
        }
        t.set_response_status(tlm::TLM_OK_RESPONSE);
    }

private:
    bool read(std::size_t i, tlm::tlm_generic_payload& t);

    Mem& mem_;
    std::uint32_t record_bytes_;
};

template <>
inline bool MemoryTarget<SphereMemory>::read(std::size_t i, tlm::tlm_generic_payload& t) {
    if (t.get_data_length() != sizeof(SphereRecord)) return false;
    const SphereRecord& r = mem_.read(i);
    std::memcpy(t.get_data_ptr(), &r, sizeof r);
    return true;
}
template <>
inline bool MemoryTarget<TriangleMemory>::read(std::size_t i, tlm::tlm_generic_payload& t) {
    if (t.get_data_length() != sizeof(TriangleRecord)) return false;
    TriangleRecord r{mem_.read(i), mem_.sphere_of(i)};
    std::memcpy(t.get_data_ptr(), &r, sizeof r);
    return true;
}

using SphereMemoryTarget = MemoryTarget<SphereMemory>;
using TriangleMemoryTarget = MemoryTarget<TriangleMemory>;

}  // namespace raplas::model::netlist
