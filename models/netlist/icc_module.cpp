#define SC_INCLUDE_DYNAMIC_PROCESSES  // (sc_spawn, for the optional ports)
#include "icc_module.hpp"

namespace raplas::model::netlist {

namespace {

std::unique_ptr<TriangleSelectorRtl> make_triangle_selector_rtl(Icc& icc, RtlBlock rtl, bool full_early) {
    if (rtl != RtlBlock::triangle_selector) return nullptr;
#ifdef RAPLAS_HAVE_RTL
    return std::make_unique<TriangleSelectorRtl>("triangle_selector", icc.triangle_selector, icc.triangle_fifo,
                                                 full_early);
#else
    (void)icc;
    (void)full_early;
    SC_REPORT_FATAL("raplas", "sim.rtl: this build has no RTL (config_from_params refuses it)");
    return nullptr;
#endif
}

}  // namespace

IccModule::IccModule(sc_core::sc_module_name n, Icc& icc, bool results_from_trace, RtlBlock rtl, bool rtl_full_early)
    : IccModule(n, nullptr, &icc, results_from_trace, rtl, rtl_full_early) {}

IccModule::IccModule(sc_core::sc_module_name n, const Icc::Params& params, const Functional& f, RtlBlock rtl)
    : IccModule(n, std::make_unique<Icc>(params, f), nullptr, f.mode() == FunctionalMode::trace, rtl, false) {}

IccModule::IccModule(sc_core::sc_module_name n, std::unique_ptr<Icc> owned, Icc* shared, bool results_from_trace,
                     RtlBlock rtl, bool rtl_full_early)
    : sc_core::sc_module(n),
      owned_(std::move(owned)),
      icc_(shared ? *shared : *owned_),
      clk("clk"),
      pass("pass"),
      sphere_record("sphere_record"),
      sphere_valid("sphere_valid"),
      sphere_stall("sphere_stall"),
      sphere_more("sphere_more"),
      triangle_record("triangle_record"),
      triangle_valid("triangle_valid"),
      triangle_stall("triangle_stall"),
      sphere_ready("sphere_ready"),
      triangle_ready("triangle_ready"),
      fetcher_busy("fetcher_busy"),
      rti_busy("rti_busy"),
      triangle_fifo_status("triangle_fifo_status"),
      host("host"),
      results("results"),
      triangle_hold("triangle_hold"),
      triangle_holders("triangle_holders"),
      active("active"),
      buf("buf"),
      psi_out("psi_out"),
      hold("hold"),
      decided("decided"),
      planeid_pop("planeid_pop"),
      rti_issue("rti_issue"),
      rti_ready("rti_ready"),
      triangle_pop(rtl != RtlBlock::none ? std::make_unique<sc_core::sc_signal<std::uint32_t>>("triangle_pop")
                                         : nullptr),
      fifo_hold("fifo_hold"),
      holders("holders"),
      sphere_fifo("sphere_fifo", icc_.sphere_fifo),
      planeid_fifo("planeid_fifo", icc_.planeid_fifo),
      first_tri_fifo("first_tri_fifo", icc_.first_tri_fifo),
      triangle_fifo(rtl == RtlBlock::none ? std::make_unique<FifoChannelOf<TriWork>>("triangle_fifo", icc_.triangle_fifo)
                                          : nullptr),
      sphere_selector("sphere_selector", icc_.sphere_selector),
      psi("psi", icc_.psi),
      decoder("decoder", icc_.decoder),
      triangle_selector(rtl == RtlBlock::none
                            ? std::make_unique<TriangleSelectorModule>("triangle_selector", icc_.triangle_selector,
                                                                     icc_.triangle_fifo.depth())
                            : nullptr),
      triangle_selector_rtl(make_triangle_selector_rtl(icc_, rtl, rtl_full_early)),
      ray_data_fetcher("ray_data_fetcher", icc_.ray_data_fetcher, icc_.params().rti.pipes),
      ray_memory("ray_memory", icc_),
      rti("rti", icc_.rti),
      min_distance_memory("min_distance_memory", icc_),
      output_link("output_link", icc_.output, results_from_trace) {
    host(*this);
    results(output_link.host);

    sphere_selector.clk(clk);
    sphere_selector.pass(pass);
    sphere_selector.active(active);
    sphere_selector.record(sphere_record);
    sphere_selector.valid(sphere_valid);
    sphere_selector.stall(sphere_stall);
    sphere_selector.fifo(sphere_fifo);
    sphere_selector.ready(sphere_ready);

    psi.clk(clk);
    psi.pass(pass);
    psi.active(active);
    psi.hold(hold);
    psi.more(sphere_more);
    psi.fifo(sphere_fifo);
    psi.out(psi_out);

    decoder.clk(clk);
    decoder.pass(pass);
    decoder.active(active);
    decoder.psi(psi_out);
    decoder.planeid_pop(planeid_pop);
    decoder.planeid(planeid_fifo);
    decoder.first_tri(first_tri_fifo);
    decoder.hold(hold);
    decoder.decided(decided);

    auto bind_selector = [&](auto& ts) {
        ts.clk(clk);
        ts.active(active);
        ts.buf(buf);
        ts.decided(decided);
        ts.record(triangle_record);
        ts.valid(triangle_valid);
        ts.stall(triangle_stall);
        ts.planeid(planeid_fifo);
        ts.first_tri(first_tri_fifo);
        ts.ready(triangle_ready);
        ts.planeid_pop(planeid_pop);
        ts.fifo_hold(fifo_hold);
        ts.holders(holders);
    };
    if (triangle_selector) {
        bind_selector(*triangle_selector);
        triangle_selector->pass(pass);
        triangle_selector->fifo(*triangle_fifo);
        triangle_fifo_status(*triangle_fifo);
        ray_data_fetcher.fifo(*triangle_fifo);
    } else {
        bind_selector(*triangle_selector_rtl);
        triangle_selector_rtl->fetcher_pop(*triangle_pop);
        ray_data_fetcher.pop(*triangle_pop);
        triangle_fifo_status(*triangle_selector_rtl);
        ray_data_fetcher.fifo(*triangle_selector_rtl);
    }

    ray_data_fetcher.clk(clk);
    ray_data_fetcher.pass(pass);
    ray_data_fetcher.rti_ready(rti_ready);
    ray_data_fetcher.issue(rti_issue);
    ray_data_fetcher.busy(fetcher_busy);

    rti.clk(clk);
    rti.pass(pass);
    rti.issue(rti_issue);
    rti.rays(ray_memory.rays);
    rti.results(min_distance_memory.write);
    rti.ready(rti_ready);
    rti.busy(rti_busy);

    output_link.memory(min_distance_memory.read);
}

void IccModule::end_of_elaboration() {
    if (triangle_hold.size()) {
        sc_core::sc_spawn_options o;
        o.spawn_method();
        o.set_sensitivity(&fifo_hold.value_changed_event());
        sc_core::sc_spawn([this] { triangle_hold->write(fifo_hold.read()); }, sc_core::sc_gen_unique_name("hold_out"), &o);
    }
    if (triangle_holders.size()) {
        sc_core::sc_spawn_options o;
        o.spawn_method();
        o.set_sensitivity(&triangle_holders->value_changed_event());
        sc_core::sc_spawn([this] { holders.write(triangle_holders->read()); }, sc_core::sc_gen_unique_name("holders_in"),
                          &o);
    }
}

void IccModule::start_pass(const TraceGroup* g, std::uint8_t b, bool overlap) {
    end_pass();  // (Icc::start_pass reads the Triangle Selector's count)
    icc_.start_pass(g, b, overlap);
    active.write(g != nullptr);
    if (g) buf.write(b);
    sphere_fifo.refresh();
    planeid_fifo.refresh();
    first_tri_fifo.refresh();
    if (triangle_fifo) triangle_fifo->refresh();
    else triangle_selector_rtl->start_pass(overlap);
}

void IccModule::end_pass() {
    if (triangle_selector_rtl) triangle_selector_rtl->read_counters();
}

}  // namespace raplas::model::netlist
