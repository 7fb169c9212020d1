#include "icc_module.hpp"

namespace raplas::model::netlist {

IccModule::IccModule(sc_core::sc_module_name n, Icc& icc, bool results_from_trace)
    : IccModule(n, nullptr, &icc, results_from_trace) {}

IccModule::IccModule(sc_core::sc_module_name n, const Icc::Params& params, const Functional& f)
    : IccModule(n, std::make_unique<Icc>(params, f), nullptr, f.mode() == FunctionalMode::trace) {}

IccModule::IccModule(sc_core::sc_module_name n, std::unique_ptr<Icc> owned, Icc* shared, bool results_from_trace)
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
      active("active"),
      buf("buf"),
      psi_out("psi_out"),
      hold("hold"),
      decided("decided"),
      planeid_pop("planeid_pop"),
      rti_issue("rti_issue"),
      rti_ready("rti_ready"),
      sphere_fifo("sphere_fifo", icc_.sphere_fifo),
      planeid_fifo("planeid_fifo", icc_.planeid_fifo),
      first_tri_fifo("first_tri_fifo", icc_.first_tri_fifo),
      triangle_fifo("triangle_fifo", icc_.triangle_fifo),
      sphere_selector("sphere_selector", icc_.sphere_selector),
      psi("psi", icc_.psi),
      decoder("decoder", icc_.decoder),
      triangle_selector("triangle_selector", icc_.triangle_selector),
      ray_data_fetcher("ray_data_fetcher", icc_.ray_data_fetcher, icc_.params().rti.pipes),
      ray_memory("ray_memory", icc_),
      rti("rti", icc_.rti),
      min_distance_memory("min_distance_memory", icc_),
      output_link("output_link", icc_.output, results_from_trace) {
    host(*this);
    results(output_link.host);
    triangle_fifo_status(triangle_fifo);

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

    triangle_selector.clk(clk);
    triangle_selector.pass(pass);
    triangle_selector.active(active);
    triangle_selector.buf(buf);
    triangle_selector.decided(decided);
    triangle_selector.record(triangle_record);
    triangle_selector.valid(triangle_valid);
    triangle_selector.stall(triangle_stall);
    triangle_selector.planeid(planeid_fifo);
    triangle_selector.first_tri(first_tri_fifo);
    triangle_selector.fifo(triangle_fifo);
    triangle_selector.ready(triangle_ready);
    triangle_selector.planeid_pop(planeid_pop);

    ray_data_fetcher.clk(clk);
    ray_data_fetcher.pass(pass);
    ray_data_fetcher.rti_ready(rti_ready);
    ray_data_fetcher.fifo(triangle_fifo);
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

void IccModule::start_pass(const TraceGroup* g, std::uint8_t b, bool overlap) {
    icc_.start_pass(g, b, overlap);
    active.write(g != nullptr);
    if (g) buf.write(b);
    sphere_fifo.refresh();
    planeid_fifo.refresh();
    first_tri_fifo.refresh();
    triangle_fifo.refresh();
}

}  // namespace raplas::model::netlist
