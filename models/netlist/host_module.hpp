// Host / pass control in the netlist. The Host starts each pass: it loads
// every ICC's group and resets it through the ICC's host interface, then
// raises `pass` (a pass number), on which every block re-drives its outputs
// and the links start from record 0. After each clock edge, once the edge's
// registers have settled (one delta cycle later), it looks at the links'
// `done` and at every ICC's busy masks (Triangle FIFO, Ray Data Fetcher,
// RTI): the pass ends in the first cycle after which both links are done and
// every ICC has drained (with overlapped passes: the previous pass's work
// has). The next pass then starts at that same edge, so passes follow each
// other without a gap, as in the event engine.
#pragma once

#include <systemc>

#include <functional>
#include <vector>

#include "fifo_channel.hpp"
#include "../host.hpp"
#include "icc_module.hpp"
#include "signals.hpp"

namespace raplas::model::netlist {

// What the simulation's driver (Top) asks of the Host.
struct PassControlIf : virtual sc_core::sc_interface {
    // Runs one pass (must be called from a thread): ICC k gets groups[k]
    // (null: none) in buffer `buf`. `drain`: the pass ends only when every
    // ICC has finished all of its work; else once the streams are done and
    // the other buffer's work has drained. Returns the pass's cycles (when
    // stopped, the cycles until then).
    virtual std::uint64_t run_pass(const std::vector<const TraceGroup*>& groups, std::uint8_t buf, bool overlap,
                                   bool drain) = 0;
    // ICC k's results for group g in buffer `buf` (through its Output Link).
    virtual const std::vector<Hit>& results(std::size_t k, const TraceGroup& g, std::uint8_t buf) = 0;
};

class HostModule : public sc_core::sc_module, public PassControlIf {
public:
    using Params = Host::Params;
    using Stats = Host::Stats;

    sc_core::sc_in<bool> clk;
    sc_core::sc_out<std::uint32_t> pass;
    sc_core::sc_in<bool> sphere_done, triangle_done;
    sc_core::sc_vector<sc_core::sc_in<BufMask>> fetcher_busy, rti_busy;
    sc_core::sc_vector<sc_core::sc_port<FifoStatusIf<TriWork>>> triangle_fifo;
    sc_core::sc_vector<sc_core::sc_port<IccHostIf>> icc;
    sc_core::sc_vector<sc_core::sc_port<OutputLinkIf>> output_link;  // each ICC's
    sc_core::sc_export<PassControlIf> control;

    // Called after every cycle of a pass, with the cycles so far: `each_cycle`
    // before the end of the pass is looked for, `check` after, when it has
    // not ended (the watchdog; false stops the pass).
    std::function<void(std::uint64_t)> each_cycle;
    std::function<bool(std::uint64_t)> check;

    SC_HAS_PROCESS(HostModule);
    // `plan`: the Host's plan and statistics (Top plans the passes with it).
    HostModule(sc_core::sc_module_name n, const Host& plan);
    const Params& params() const { return plan_.params(); }
    const Stats& stats() const { return plan_.stats(); }

    std::uint64_t run_pass(const std::vector<const TraceGroup*>& groups, std::uint8_t buf, bool overlap,
                           bool drain) override;
    const std::vector<Hit>& results(std::size_t k, const TraceGroup& g, std::uint8_t buf) override {
        return output_link[k]->results(g, buf);
    }
    // Ends the pass that runs now (the machine cannot go on: an error).
    void stop() {
        if (!running_) return;
        running_ = false;
        ended_.notify();
    }

private:
    void watch();
    bool drained() const;

    const Host& plan_;
    bool settling_ = false, running_ = false, drain_ = true;
    std::uint8_t prev_ = 0;
    std::uint32_t number_ = 0;
    std::uint64_t cycles_ = 0;
    sc_core::sc_event ended_;
};

}  // namespace raplas::model::netlist
