// Sphere Selector (with the Sphere FIFO it writes) in the netlist. Its
// `ready` wire to the Sphere Stream Link is combinational: high when the ICC
// has no group this pass or its Sphere FIFO is not full at the start of the
// cycle. At the clock edge it pushes the sphere broadcast, or counts a cycle
// in which its full FIFO stopped the link (SphereSelector, shared with the
// event engine).
#pragma once

#include <systemc>

#include "fifo_channel.hpp"
#include "signals.hpp"
#include "../sphere_selector.hpp"

namespace raplas::model::netlist {

class SphereSelectorModule : public sc_core::sc_module {
public:
    using Params = SphereSelector::Params;
    using Stats = SphereSelector::Stats;

    sc_core::sc_in<bool> clk;
    sc_core::sc_in<std::uint32_t> pass;
    sc_core::sc_in<bool> active;        // the ICC has a group this pass
    sc_core::sc_in<LinkRecord> record;  // the Sphere Stream Link
    sc_core::sc_in<bool> valid, stall;
    sc_core::sc_port<FifoWriteIf<SphereEntry>> fifo;  // the Sphere FIFO
    sc_core::sc_out<bool> ready;

    SC_HAS_PROCESS(SphereSelectorModule);
    SphereSelectorModule(sc_core::sc_module_name n, SphereSelector& core)
        : sc_core::sc_module(n),
          clk("clk"),
          pass("pass"),
          active("active"),
          record("record"),
          valid("valid"),
          stall("stall"),
          fifo("fifo"),
          ready("ready"),
          core_(core),
          fifo_full_(full_event_of<SphereEntry>(fifo)) {
        SC_METHOD(settle);
        sensitive << fifo_full_ << active << pass;
        dont_initialize();
        SC_METHOD(tick);
        sensitive << clk.pos();
        dont_initialize();
    }
    const Stats& stats() const { return core_.stats(); }

private:
    void settle() { ready.write(core_.ready(active.read(), bound(fifo))); }
    void tick() {
        if (valid.read()) {
            if (active.read()) {
                const LinkRecord& r = record.read();
                fifo->push({r.index, r.first_tri, r.tri_count});
            }
        } else if (stall.read() && !ready.read()) {
            core_.note_blocked(bound(fifo));
        }
    }

    SphereSelector& core_;
    FifoEventFinder<SphereEntry> fifo_full_;
};

}  // namespace raplas::model::netlist
