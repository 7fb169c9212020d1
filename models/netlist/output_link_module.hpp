// Output Link in the netlist: at the end of a pass the Host reads the
// group's nearest hits from the Min-distance Memory through it (one entry
// per ray, counted by OutputLink, shared with the event engine).
#pragma once

#include <systemc>

#include "memories_module.hpp"
#include "../output_link.hpp"

namespace raplas::model::netlist {

struct OutputLinkIf : virtual sc_core::sc_interface {
    // Group g's results, from buffer `buf` (in sim.functional = trace, the trace's).
    virtual const std::vector<Hit>& results(const TraceGroup& g, std::uint8_t buf) = 0;
};

class OutputLinkModule : public sc_core::sc_module, public OutputLinkIf {
public:
    using Params = OutputLink::Params;
    using Stats = OutputLink::Stats;

    sc_core::sc_port<MinDistanceReadIf> memory;  // the Min-distance Memory
    sc_core::sc_export<OutputLinkIf> host;

    OutputLinkModule(sc_core::sc_module_name n, OutputLink& core, bool from_trace)
        : sc_core::sc_module(n), memory("memory"), host("host"), core_(core), from_trace_(from_trace) {
        host(*this);
    }
    const std::vector<Hit>& results(const TraceGroup& g, std::uint8_t buf) override {
        if (from_trace_) memory->set(buf, g.hits);
        core_.send(std::uint64_t(g.n) * g.n);
        return memory->hits(buf);
    }
    const Stats& stats() const { return core_.stats(); }

private:
    OutputLink& core_;
    bool from_trace_;
};

}  // namespace raplas::model::netlist
