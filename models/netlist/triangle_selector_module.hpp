// Triangle Selector (with the Triangle FIFO it writes) in the netlist. Two
// combinational wires: `ready` to the Triangle Stream Link (its sphere is
// decided and, under the stall policy, its Triangle FIFO can take it,
// judged at the start of the cycle), and `planeid_pop` to the Decoder (it
// takes the last triangle of the sphere at the head of its First-Triangle-ID
// FIFO this cycle, so that FIFO and the PlaneID FIFO free an entry). At the
// clock edge it keeps or discards the triangle broadcast (TriangleSelector,
// shared with the event engine).
#pragma once

#include <systemc>

#include "fifo_channel.hpp"
#include "signals.hpp"
#include "../triangle_selector.hpp"

namespace raplas::model::netlist {

class TriangleSelectorModule : public sc_core::sc_module {
public:
    using Params = TriangleSelector::Params;
    using Stats = TriangleSelector::Stats;

    sc_core::sc_in<bool> clk;
    sc_core::sc_in<std::uint32_t> pass;
    sc_core::sc_in<bool> active;
    sc_core::sc_in<std::uint8_t> buf;        // the group's Ray / Min-distance Memory buffer
    sc_core::sc_in<std::uint32_t> decided;   // the Decoder's count
    sc_core::sc_in<LinkRecord> record;       // the Triangle Stream Link
    sc_core::sc_in<bool> valid, stall;
    sc_core::sc_port<FifoReadIf<PlaneIdEntry>> planeid;
    sc_core::sc_port<FifoReadIf<FirstTriEntry>> first_tri;
    sc_core::sc_port<FifoWriteIf<TriWork>> fifo;  // the Triangle FIFO
    sc_core::sc_out<bool> ready;
    sc_core::sc_out<bool> planeid_pop;

    SC_HAS_PROCESS(TriangleSelectorModule);
    TriangleSelectorModule(sc_core::sc_module_name n, TriangleSelector& core)
        : sc_core::sc_module(n),
          clk("clk"),
          pass("pass"),
          active("active"),
          buf("buf"),
          decided("decided"),
          record("record"),
          valid("valid"),
          stall("stall"),
          planeid("planeid"),
          first_tri("first_tri"),
          fifo("fifo"),
          ready("ready"),
          planeid_pop("planeid_pop"),
          core_(core),
          first_tri_front_(front_event_of<FirstTriEntry>(first_tri)),
          fifo_full_(full_event_of<TriWork>(fifo)) {
        SC_METHOD(settle);
        sensitive << record << valid << decided << first_tri_front_ << fifo_full_ << active << pass;
        dont_initialize();
        SC_METHOD(tick);
        sensitive << clk.pos();
        dont_initialize();
    }
    const Stats& stats() const { return core_.stats(); }

private:
    // The sphere of the triangle offered (0 when none is, as the event engine take it).
    std::uint32_t sphere() const {
        const LinkRecord& r = record.read();
        return r.present ? r.sphere : 0;
    }
    void settle() {
        const std::uint32_t s = sphere();
        const bool act = active.read();
        ready.write(core_.ready(act, s, decided.read(), bound(first_tri), bound(fifo)));
        bool pop = false;
        if (valid.read() && act && TriangleSelector::wants(s, bound(first_tri))) {
            const FirstTriEntry f = first_tri->front();
            pop = record.read().index + 1 == f.first + f.count;
        }
        planeid_pop.write(pop);
    }
    void tick() {
        if (valid.read()) {
            core_.receive(active.read(), record.read().index, sphere(), bound(planeid), bound(first_tri), bound(fifo),
                          buf.read());
        } else if (stall.read() && !ready.read()) {
            core_.note_blocked(sphere(), decided.read(), bound(fifo));
        }
    }

    TriangleSelector& core_;
    FifoEventFinder<FirstTriEntry> first_tri_front_;
    FifoEventFinder<TriWork> fifo_full_;
};

}  // namespace raplas::model::netlist
