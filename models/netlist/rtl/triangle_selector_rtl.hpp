// The Triangle Selector and its Triangle FIFO as Verilog RTL in the netlist
// (sim.rtl = triangle_selector): rtl/triangle_selector.v, made a SystemC
// module by `verilator --sc` at build time, in a thin wrapper that stands in
// for TriangleSelectorModule and the Triangle FIFO's channel at their ports.
//
// What the wrapper adds to the RTL, and nothing else:
// - glue: the link's record and the heads of the First-Triangle-ID and
//   PlaneID FIFOs split into the RTL's input wires (combinational), and the
//   PlaneID and First-Triangle-ID FIFOs popped through their ports at the
//   clock edge when the RTL's `planeid_pop` was high;
// - the Triangle FIFO's RAM (the C++ FIFO's storage, Fifo::ram), which the
//   RTL writes through its write port at the edge and whose entries from the
//   RTL's read pointer on the Ray Data Fetcher reads through the FIFO's read
//   interface (it may take several in one cycle); occupancy and flags are
//   the RTL's;
// - the statistics: the RTL's counters, added to the C++ block's Stats at the
//   end of every pass (read_counters), so that reports count them as before.
// The Ray Data Fetcher tells the RTL how many entries it takes at the next
// edge on `fetcher_pop` (combinational), as a FIFO's reader drives its read
// enable.
#pragma once

#include <systemc>

#include <cstdint>
#include <memory>

#include "../../fifo.hpp"
#include "../fifo_channel.hpp"
#include "../signals.hpp"
#include "../triangle_selector_ports.hpp"
#include "../../triangle_selector.hpp"

namespace raplas::model::netlist {

class TriangleSelectorRtl : public sc_core::sc_module, public TriangleSelectorPorts, public FifoReadIf<TriWork> {
public:
    using Params = TriangleSelector::Params;
    using Stats = TriangleSelector::Stats;

    // TriangleSelectorModule's ports (TriangleSelectorPorts; but the
    // Triangle FIFO's, which it holds), and:
    // From the Ray Data Fetcher: the Triangle FIFO entries it takes at the next edge (C).
    sc_core::sc_in<std::uint32_t> fetcher_pop;

    SC_HAS_PROCESS(TriangleSelectorRtl);
    // `core` and `fifo`: the C++ block's Stats (and the FIFO's RAM);
    // `full_early`: the deliberately broken variant (sim.fault = rtl_full_early).
    TriangleSelectorRtl(sc_core::sc_module_name n, TriangleSelector& core, Fifo<TriWork>& fifo, bool full_early);
    ~TriangleSelectorRtl() override;

    // A new pass (Icc::start_pass has run): without overlap the Host has
    // drained the FIFO (checked), as the C++ FIFO's clear() assumes.
    void start_pass(bool overlap);
    // Adds what the RTL's counters counted since the last call to the C++
    // block's Stats (and its FIFO's).
    void read_counters();

    // The Triangle FIFO's read side (the Ray Data Fetcher's port, the Host's status port).
    bool empty() const override { return empty_.read(); }
    bool full() const override { return full_.read(); }
    std::uint32_t size() const override { return count_.read(); }
    TriWork at(std::uint32_t i) const override;
    void pop(std::uint32_t n) override;
    const sc_core::sc_event& default_event() const override { return changed_; }
    const sc_core::sc_event& front_event() const override { return changed_; }
    const sc_core::sc_event& full_event() const override { return changed_; }

private:
    void drive();    // glue: the RTL's input wires
    void hold();     // its FIFO holds the link: not ready, the sphere decided
    void changed();  // the FIFO's read pointer or occupancy moved: tells its readers
    void tick();     // the clock edge: the RAM's write port, the PlaneID and First-Triangle-ID pops

    TriangleSelector& core_;
    Fifo<TriWork>& fifo_;
    const std::uint32_t depth_value_;

    // The RTL's wires (named as its ports).
    sc_core::sc_signal<std::uint32_t> depth_;
    sc_core::sc_signal<bool> needed_full_;
    sc_core::sc_signal<bool> buf_sel_, rec_present_, ft_valid_;
    sc_core::sc_signal<std::uint32_t> rec_index_, rec_sphere_, ft_sphere_, ft_first_, ft_count_;
    sc_core::sc_signal<std::uint64_t> pid_rows_, pid_cols_;
    sc_core::sc_signal<bool> ram_we_, ram_wbuf_;
    sc_core::sc_signal<std::uint32_t> ram_waddr_, ram_wtri_;
    sc_core::sc_signal<std::uint64_t> ram_wrows_, ram_wcols_;
    sc_core::sc_signal<std::uint32_t> rd_ptr_, count_;
    sc_core::sc_signal<bool> full_, empty_;
    sc_core::sc_signal<std::uint64_t> selected_, blocked_full_, blocked_undecided_;
    sc_core::sc_signal<std::uint32_t> max_count_;
    std::unique_ptr<sc_core::sc_module> rtl_;  // the Verilated module (raplas.icc_K.triangle_selector.rtl)

    sc_core::sc_event changed_;
    FifoEventFinder<FirstTriEntry> first_tri_front_;
    FifoEventFinder<PlaneIdEntry> planeid_front_;
    struct Counters {
        std::uint64_t selected = 0, blocked_full = 0, blocked_undecided = 0;
    } read_;  // as read_counters last read them
    std::uint64_t alone_ = 0;  // cycles its FIFO alone held the link, since read_counters
};

}  // namespace raplas::model::netlist
