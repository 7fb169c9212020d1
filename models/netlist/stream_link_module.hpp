// Sphere Stream Link / Triangle Stream Link in the netlist: a module whose
// record, valid and stall are signals, as hardware wires them. It holds one
// record register, filled from its memory through a TLM-2.0 initiator
// socket; every ICC drives a `ready` wire (its Selector can take the record
// this cycle, judged on the state at the start of the cycle), and the record
// is broadcast (`valid`) only when every ready is high: a combinational AND
// that settles in delta cycles. At the clock edge the link counts the cycle
// (sent, stalled or idle, in the StreamLink it shares with the other
// engines) and, after a send, reads the next record.
// The Triangle Stream Link also takes every ICC's `hold` wire (its Triangle
// FIFO holds the link) and drives `holders`, their count, with which it and
// the ICCs count the stall anatomy (StreamLink::Stats::held_by).
#pragma once

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_initiator_socket.h>

#include <functional>
#include <string>

#include "memory_target.hpp"
#include "signals.hpp"
#include "../stream_link.hpp"

namespace raplas::model::netlist {

inline LinkRecord link_record(const SphereRecord& r, std::uint32_t index) {
    return {true, index, index, r.first_tri, r.tri_count};
}
inline LinkRecord link_record(const TriangleRecord& r, std::uint32_t index) { return {true, index, r.sphere, 0, 0}; }

// `Record` is what one read of its memory returns: SphereRecord or TriangleRecord.
template <class Record>
class StreamLinkModule : public sc_core::sc_module {
public:
    using Params = StreamLink::Params;
    using Stats = StreamLink::Stats;

    sc_core::sc_in<bool> clk;
    sc_core::sc_in<std::uint32_t> pass;             // the Host starts a pass
    sc_core::sc_vector<sc_core::sc_in<bool>> ready;  // per ICC: its Selector can take the record
    sc_core::sc_out<LinkRecord> record;              // offered this cycle (registered)
    sc_core::sc_out<bool> valid;                     // broadcast: offered, and every ICC ready
    sc_core::sc_out<bool> stall;                     // offered and held back
    sc_core::sc_out<bool> more;                      // records left after this cycle's
    sc_core::sc_out<bool> done;                      // every record of the pass sent (registered)
    sc_core::sc_vector<sc_core::sc_in<bool>> holds;  // per ICC (with `anatomy`): its FIFO holds the link
    sc_core::sc_out<std::uint32_t> holders;          // how many do (C)
    tlm_utils::simple_initiator_socket<StreamLinkModule> memory;

    // Called when its memory answers a read with an error response (the
    // message names the link, the record and the response); the link then
    // offers no record. (Not thrown: nothing is thrown across sc_start,
    // docs/FUZZING.md.) Unset: an SC_REPORT_ERROR.
    std::function<void(const std::string&)> on_error;

    SC_HAS_PROCESS(StreamLinkModule);
    // `core`: the link's position and statistics; `records` per pass;
    // `lag`: cycles before its first record (link.triangle_lag_cycles);
    // `anatomy`: it takes the ICCs' hold wires.
    StreamLinkModule(sc_core::sc_module_name n, StreamLink& core, std::size_t iccs, std::uint64_t records,
                     std::uint64_t lag, const sc_core::sc_time& period, bool anatomy = false)
        : sc_core::sc_module(n),
          clk("clk"),
          pass("pass"),
          ready("ready", iccs),
          record("record"),
          valid("valid"),
          stall("stall"),
          more("more"),
          done("done"),
          holds("holds", anatomy ? iccs : 0),
          holders("holders"),
          memory("memory"),
          core_(core),
          records_(records),
          lag_(lag),
          period_ps_(std::uint64_t(period.value())) {
        SC_METHOD(settle);
        sensitive << record << pass;
        for (auto& r : ready) sensitive << r;
        for (auto& h : holds) sensitive << h;
        dont_initialize();
        SC_METHOD(tick);
        sensitive << clk.pos() << pass;
        dont_initialize();
    }
    const Stats& stats() const { return core_.stats(); }
    const Params& params() const { return core_.params(); }

private:
    // Combinational: valid = offered AND every ready.
    void settle() {
        const LinkRecord& r = record.read();
        bool all = r.present;
        for (std::size_t k = 0; all && k < ready.size(); ++k) all = ready[k].read();
        valid.write(all);
        stall.write(r.present && !all);
        more.write(core_.position() + (all ? 1 : 0) < core_.end());
        std::uint32_t n = 0;
        for (auto& h : holds) n += h.read();
        holders.write(n);
    }
    void tick() {
        if (pass.event()) {  // a new pass: record 0
            core_.start_pass(records_);
            cycle_ = 0;
            ready_at_ = 0;
            if (core_.has_record()) fetch();
            drive();
            return;
        }
        const bool sent = valid.read();
        if (sent) {
            core_.sent();
        } else if (record.read().present) {
            core_.stalled();
            core_.held(holders.read());
        } else if (!core_.has_record()) {
            core_.idle();  // (before the lag, or while its memory answers, it is neither)
        }
        ++cycle_;
        if (sent && core_.has_record()) fetch();
        drive();
    }
    // Reads the record at the link's position; it is on the link from the
    // cycle the annotated delay ends in.
    void fetch() {
        const std::uint64_t i = core_.position();
        tlm::tlm_generic_payload t;
        t.set_command(tlm::TLM_READ_COMMAND);
        t.set_address(i * core_.params().record_bytes);
        t.set_data_ptr(reinterpret_cast<unsigned char*>(&buffer_));
        t.set_data_length(sizeof(Record));
        t.set_streaming_width(sizeof(Record));
        t.set_byte_enable_ptr(nullptr);
        t.set_dmi_allowed(false);
        t.set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
        sc_core::sc_time delay = sc_core::SC_ZERO_TIME;
        memory->b_transport(t, delay);
        if (t.is_response_error()) {
            failed_ = true;
            const std::string why =
                std::string(name()) + ": reading record " + std::to_string(i) + ": " + t.get_response_string();
            if (on_error) on_error(why);
            else SC_REPORT_ERROR(name(), why.c_str());
            return;
        }
        const std::uint64_t d = std::uint64_t(delay.value());
        ready_at_ = cycle_ + (d + period_ps_ - 1) / period_ps_;
        current_ = link_record(buffer_, std::uint32_t(i));
    }
    void drive() {
        LinkRecord r = current_;
        r.present = !failed_ && core_.has_record() && cycle_ >= lag_ && cycle_ >= ready_at_;
        if (!core_.has_record()) r.index = std::uint32_t(core_.position());
        record.write(r);
        done.write(!core_.has_record());
    }

    StreamLink& core_;
    std::uint64_t records_, lag_, period_ps_;
    std::uint64_t cycle_ = 0, ready_at_ = 0;  // cycles of this pass; the cycle the record is on the link
    bool failed_ = false;                     // its memory refused a read
    Record buffer_{};                         // the record register
    LinkRecord current_;
};

using SphereStreamLink = StreamLinkModule<SphereRecord>;
using TriangleStreamLink = StreamLinkModule<TriangleRecord>;

}  // namespace raplas::model::netlist
