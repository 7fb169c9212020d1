// Plane-Sphere Intersector in the netlist. Clocked: at each edge it hands
// its result to the Decoder unless the Decoder's combinational `hold` is
// high, and steps the pipe (PlaneSphereIntersector, shared with the other
// engines), taking the next sphere from the Sphere FIFO through its port.
// Its output register `out` carries the result leaving the last stage with
// the sphere's triangle range, which travels with the sphere from the FIFO.
#pragma once

#include <systemc>

#include <vector>

#include "fifo_channel.hpp"
#include "../plane_sphere_intersector.hpp"
#include "signals.hpp"

namespace raplas::model::netlist {

class PsiModule : public sc_core::sc_module {
public:
    using Params = PlaneSphereIntersector::Params;
    using Stats = PlaneSphereIntersector::Stats;

    sc_core::sc_in<bool> clk;
    sc_core::sc_in<std::uint32_t> pass;
    sc_core::sc_in<bool> active;
    sc_core::sc_in<bool> hold;  // the Decoder cannot queue the result: the whole pipe holds
    sc_core::sc_in<bool> more;  // the Sphere Stream Link has spheres left after this cycle's
    sc_core::sc_port<FifoReadIf<SphereEntry>> fifo;  // the Sphere FIFO
    sc_core::sc_out<PsiOut> out;

    SC_HAS_PROCESS(PsiModule);
    PsiModule(sc_core::sc_module_name n, PlaneSphereIntersector& core)
        : sc_core::sc_module(n),
          clk("clk"),
          pass("pass"),
          active("active"),
          hold("hold"),
          more("more"),
          fifo("fifo"),
          out("out"),
          core_(core),
          range_(core.params().stages + 2) {  // (the spheres in flight are consecutive: no two share a slot)
        SC_METHOD(tick);
        sensitive << clk.pos() << pass;
        dont_initialize();
    }
    const Stats& stats() const { return core_.stats(); }

private:
    // The Sphere FIFO as PlaneSphereIntersector::tick reads it; a sphere
    // taken leaves its triangle range here.
    struct Input {
        FifoReadIf<SphereEntry>& fifo;
        std::vector<SphereEntry>& range;
        bool empty() const { return fifo.empty(); }
        std::uint32_t front() const { return fifo.front().sphere; }
        void pop() {
            const SphereEntry e = fifo.front();
            range[e.sphere % range.size()] = e;
            fifo.pop();
        }
    };
    void tick() {
        if (pass.event()) {  // a new pass
            drive();
            return;
        }
        if (!active.read()) return;
        const bool held = hold.read();
        if (out.read().valid && !held) core_.pop_output();  // the Decoder took it
        Input in{bound(fifo), range_};
        core_.tick(in, held, more.read() || !fifo->empty());
        drive();
    }
    void drive() {
        PsiOut o;
        o.valid = core_.has_output();
        if (o.valid) {
            o.result = core_.output();
            const SphereEntry& e = range_[o.result.sphere % range_.size()];
            o.first_tri = e.first_tri;
            o.tri_count = e.tri_count;
        }
        out.write(o);
    }

    PlaneSphereIntersector& core_;
    std::vector<SphereEntry> range_;
};

}  // namespace raplas::model::netlist
