#include "netlist.hpp"

#include <set>

#include "config.hpp"

namespace raplas::model::netlist {

namespace {

sc_core::sc_time period_of(const SimConfig& cfg) { return sc_core::sc_time(1.0e6 / cfg.clock_mhz, sc_core::SC_PS); }

// Traces `o` when it is a signal or port of one of the types T... .
template <class... T>
struct Tracer {
    static bool trace(sc_core::sc_trace_file* tf, sc_core::sc_object* o) {
        return (try_one<T>(tf, o) || ...);
    }
    template <class U>
    static bool try_one(sc_core::sc_trace_file* tf, sc_core::sc_object* o) {
        if (auto* s = dynamic_cast<sc_core::sc_signal_in_if<U>*>(o)) {  // a signal (or the clock)
            sc_core::sc_trace(tf, *s, o->name());
            return true;
        }
        if (auto* p = dynamic_cast<sc_core::sc_in<U>*>(o)) {
            sc_core::sc_trace(tf, *p, p->name());
            return true;
        }
        if (auto* p = dynamic_cast<sc_core::sc_inout<U>*>(o)) {  // (sc_out too)
            sc_core::sc_trace(tf, *p, p->name());
            return true;
        }
        return false;
    }
};
using Traced = Tracer<bool, std::uint8_t, std::uint32_t, std::uint64_t, LinkRecord, PsiOut, RtiIssue>;

// (an sc_vector lists its elements as its children, which are its parent's too: each once)
void trace_tree(sc_core::sc_trace_file* tf, sc_core::sc_object* o, std::set<sc_core::sc_object*>& seen) {
    if (!seen.insert(o).second) return;
    if (Traced::trace(tf, o)) return;
    if (dynamic_cast<sc_core::sc_prim_channel*>(o)) o->trace(tf);  // the FIFO channels trace themselves
    for (sc_core::sc_object* c : o->get_child_objects()) trace_tree(tf, c, seen);
}

}  // namespace

Netlist::Netlist(const SimConfig& cfg, const MachineState& state, bool results_from_trace,
                 const BindSphereMemory& bind_spheres, const BindTriangleMemory& bind_triangles)
    : clock("clock", period_of(cfg), 0.5, period_of(cfg), true),  // first rising edge after one period
      pass("pass"),
      sphere_record("sphere_record"),
      triangle_record("triangle_record"),
      sphere_valid("sphere_valid"),
      sphere_stall("sphere_stall"),
      sphere_more("sphere_more"),
      sphere_done("sphere_done"),
      triangle_valid("triangle_valid"),
      triangle_stall("triangle_stall"),
      triangle_more("triangle_more"),
      triangle_done("triangle_done"),
      sphere_ready("sphere_ready", cfg.iccs),
      triangle_ready("triangle_ready", cfg.iccs),
      triangle_hold("triangle_hold", cfg.iccs),
      triangle_holders("triangle_holders"),
      sphere_holders("sphere_holders"),
      fetcher_busy("fetcher_busy", cfg.iccs),
      rti_busy("rti_busy", cfg.iccs),
      host("host", state.host),
      sphere_memory("sphere_memory", state.sphere_memory, cfg.sphere_record_bytes),
      triangle_memory("triangle_memory", state.triangle_memory, cfg.triangle_record_bytes),
      sphere_link("sphere_stream_link", state.sphere_link, cfg.iccs, state.sphere_memory.size(), 0, period_of(cfg)),
      triangle_link("triangle_stream_link", state.triangle_link, cfg.iccs, state.triangle_memory.size(),
                    cfg.triangle_lag_cycles, period_of(cfg), true),
      iccs("icc") {
    iccs.init(cfg.iccs, [&](const char* name, std::size_t k) {
        return new IccModule(name, state.iccs[k], results_from_trace, cfg.rtl,
                             cfg.fault == Fault::rtl_full_early && k == cfg.fault_icc);
    });

    host.clk(clock);
    host.pass(pass);
    host.sphere_done(sphere_done);
    host.triangle_done(triangle_done);

    if (bind_spheres) memory_models_.push_back(bind_spheres(sphere_link.memory, sphere_memory));
    else sphere_link.memory.bind(sphere_memory.socket);
    if (bind_triangles) memory_models_.push_back(bind_triangles(triangle_link.memory, triangle_memory));
    else triangle_link.memory.bind(triangle_memory.socket);

    sphere_link.clk(clock);
    sphere_link.pass(pass);
    sphere_link.record(sphere_record);
    sphere_link.valid(sphere_valid);
    sphere_link.stall(sphere_stall);
    sphere_link.more(sphere_more);
    sphere_link.done(sphere_done);
    sphere_link.holders(sphere_holders);
    triangle_link.clk(clock);
    triangle_link.pass(pass);
    triangle_link.record(triangle_record);
    triangle_link.valid(triangle_valid);
    triangle_link.stall(triangle_stall);
    triangle_link.more(triangle_more);
    triangle_link.done(triangle_done);
    triangle_link.holders(triangle_holders);

    for (std::size_t k = 0; k < iccs.size(); ++k) {
        IccModule& c = iccs[k];
        c.clk(clock);
        c.pass(pass);
        c.sphere_record(sphere_record);
        c.sphere_valid(sphere_valid);
        c.sphere_stall(sphere_stall);
        c.sphere_more(sphere_more);
        c.triangle_record(triangle_record);
        c.triangle_valid(triangle_valid);
        c.triangle_stall(triangle_stall);
        c.sphere_ready(sphere_ready[k]);
        c.triangle_ready(triangle_ready[k]);
        c.triangle_hold(triangle_hold[k]);
        c.triangle_holders(triangle_holders);
        triangle_link.holds[k](triangle_hold[k]);
        c.fetcher_busy(fetcher_busy[k]);
        c.rti_busy(rti_busy[k]);
        sphere_link.ready[k](sphere_ready[k]);
        triangle_link.ready[k](triangle_ready[k]);
        host.fetcher_busy[k](fetcher_busy[k]);
        host.rti_busy[k](rti_busy[k]);
        host.triangle_fifo[k](c.triangle_fifo_status);
        host.icc[k](c.host);
        host.output_link[k](c.results);
    }
}

void Netlist::trace(sc_core::sc_trace_file* tf) const {
    sc_core::sc_object* top = clock.get_parent_object();
    std::set<sc_core::sc_object*> seen;
    for (sc_core::sc_object* c : top->get_child_objects()) trace_tree(tf, c, seen);
}

}  // namespace raplas::model::netlist
