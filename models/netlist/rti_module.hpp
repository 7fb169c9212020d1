// Ray-Triangle Intersector in the netlist. Clocked: at each edge the pairs
// that entered L cycles ago leave (each tested against the Ray Memory
// through its port, a hit written to the Min-distance Memory through its
// port), and the pairs the Ray Data Fetcher issues this cycle enter
// (RayTriangleIntersector, shared with the event engine).
#pragma once

#include <systemc>

#include "memories_module.hpp"
#include "../ray_triangle_intersector.hpp"
#include "signals.hpp"

namespace raplas::model::netlist {

class RtiModule : public sc_core::sc_module {
public:
    using Params = RayTriangleIntersector::Params;
    using Stats = RayTriangleIntersector::Stats;

    sc_core::sc_in<bool> clk;
    sc_core::sc_in<std::uint32_t> pass;
    sc_core::sc_in<RtiIssue> issue;                 // from the Ray Data Fetcher
    sc_core::sc_port<RayMemoryIf> rays;
    sc_core::sc_port<MinDistanceWriteIf> results;   // the Min-distance Memory
    sc_core::sc_out<bool> ready;                    // takes pairs (sim.fault = stuck_rti: it does not)
    sc_core::sc_out<BufMask> busy;                  // the buffers with pairs in flight (registered)

    SC_HAS_PROCESS(RtiModule);
    RtiModule(sc_core::sc_module_name n, RayTriangleIntersector& core)
        : sc_core::sc_module(n),
          clk("clk"),
          pass("pass"),
          issue("issue"),
          rays("rays"),
          results("results"),
          ready("ready"),
          busy("busy"),
          core_(core) {
        SC_METHOD(tick);
        sensitive << clk.pos() << pass;
        dont_initialize();
    }
    const Stats& stats() const { return core_.stats(); }

private:
    BufMask holds() const { return BufMask((core_.inflight(0) ? 1 : 0) | (core_.inflight(1) ? 2 : 0)); }
    void tick() {
        if (pass.event()) {  // a new pass
            asleep_ = false;
            ready.write(!core_.stuck());
            busy.write(holds());
            return;
        }
        if (asleep_) {  // woken by pairs issued this cycle: they enter at the next edge
            asleep_ = false;
            return;
        }
        const RtiIssue& in = issue.read();
        if (core_.empty() && in.n == 0) {  // nothing in flight: nothing to step until pairs come
            asleep_ = true;
            next_trigger(issue.value_changed_event() | pass.value_changed_event());
            return;
        }
        core_.retire_with([this](const RtiOp& op, double& t) { return rays->group(op.buf).rti(op.ray, op.tri, t); },
                          [this](const RtiOp& op, double t) { results->update(op.buf, op.ray, t, op.tri); });
        for (std::uint32_t i = 0; i < in.n; ++i) core_.issue(in.ops[i]);
        core_.advance();
        busy.write(holds());
    }

    RayTriangleIntersector& core_;
    bool asleep_ = false;
};

}  // namespace raplas::model::netlist
