// Ray Data Fetcher in the netlist. What it issues to the Ray-Triangle
// Intersector in a cycle is combinational: a triangle popped in a cycle
// issues in that cycle (docs/MODEL.md §3), so `issue` is the Fetcher's next
// step (RayDataFetcher::tick, shared with the event engine) computed on a
// copy of its state from the Triangle FIFO's contents at the start of the
// cycle. At the clock edge the copy becomes its state and the triangles it
// took are popped through its port.
#pragma once

#include <systemc>

#include "fifo_channel.hpp"
#include "../ray_data_fetcher.hpp"
#include "signals.hpp"

namespace raplas::model::netlist {

class RayDataFetcherModule : public sc_core::sc_module {
public:
    using Params = RayDataFetcher::Params;
    using Stats = RayDataFetcher::Stats;

    sc_core::sc_in<bool> clk;
    sc_core::sc_in<std::uint32_t> pass;
    sc_core::sc_in<bool> rti_ready;                // the RTI takes pairs (not stopped)
    sc_core::sc_port<FifoReadIf<TriWork>> fifo;    // the Triangle FIFO
    sc_core::sc_out<RtiIssue> issue;               // the pairs entering the RTI this cycle
    sc_core::sc_out<BufMask> busy;                 // the buffers whose work it holds (registered)
    // The Triangle FIFO entries it takes at the next edge (C): bound only
    // where the FIFO is RTL (sim.rtl), whose read pointer moves on it.
    sc_core::sc_port<sc_core::sc_signal_inout_if<std::uint32_t>, 1, sc_core::SC_ZERO_OR_MORE_BOUND> pop;

    SC_HAS_PROCESS(RayDataFetcherModule);
    RayDataFetcherModule(sc_core::sc_module_name n, RayDataFetcher& core, std::uint32_t rti_pipes)
        : sc_core::sc_module(n),
          clk("clk"),
          pass("pass"),
          rti_ready("rti_ready"),
          fifo("fifo"),
          issue("issue"),
          busy("busy"),
          pop("pop"),
          core_(core),
          next_(core),
          pipes_(rti_pipes) {
        SC_METHOD(plan);
        sensitive << fifo << rti_ready << pass << replan_;
        dont_initialize();
        SC_METHOD(tick);
        sensitive << clk.pos() << pass;
        dont_initialize();
    }
    const Stats& stats() const { return core_.stats(); }

private:
    // The Triangle FIFO as the step reads it: its contents at the start of
    // the cycle, less the triangles the step has taken.
    struct Input {
        FifoReadIf<TriWork>& fifo;
        std::uint32_t taken = 0;
        bool empty() const { return taken >= fifo.size(); }
        TriWork front() const { return fifo.at(taken); }
        void pop() { ++taken; }
    };
    // The RTI as the step feeds it: one pair per pipe.
    struct Output {
        std::uint32_t pipes;
        bool ready;
        RtiIssue pairs;
        bool can_issue() const { return ready && pairs.n < pipes; }
        void issue(const RtiOp& op) { pairs.ops[pairs.n++] = op; }
    };
    BufMask holds() const { return BufMask((core_.holds(0) ? 1 : 0) | (core_.holds(1) ? 2 : 0)); }

    void plan() {
        next_ = core_;
        Input in{bound(fifo)};
        Output out{pipes_, rti_ready.read(), RtiIssue()};
        next_.tick(in, out);
        taken_ = in.taken;
        issue.write(out.pairs);
        if (pop.size()) pop->write(taken_);
    }
    void tick() {
        if (pass.event()) {  // a new pass (the ICC may have cleared it; plan runs again)
            asleep_ = false;
            busy.write(holds());
            return;
        }
        if (asleep_) {  // woken by a push into its FIFO: it steps at the next edge
            asleep_ = false;
            return;
        }
        if (!(taken_ || !core_.idle() || !next_.idle() || issue.read().n)) {
            // Idle with an empty FIFO: its step changes nothing until a triangle arrives.
            asleep_ = true;
            next_trigger(fifo->default_event() | pass.value_changed_event());
            return;
        }
        core_ = next_;
        if (taken_) fifo->pop(taken_);
        taken_ = 0;
        busy.write(holds());
        replan_.notify(sc_core::SC_ZERO_TIME);
    }

    RayDataFetcher& core_;
    RayDataFetcher next_;  // its state after this cycle
    std::uint32_t pipes_;
    std::uint32_t taken_ = 0;  // triangles the step takes this cycle
    bool asleep_ = false;
    sc_core::sc_event replan_;
};

}  // namespace raplas::model::netlist
