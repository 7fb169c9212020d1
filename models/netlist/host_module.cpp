#include "host_module.hpp"

namespace raplas::model::netlist {

HostModule::HostModule(sc_core::sc_module_name n, const Host& plan)
    : sc_core::sc_module(n),
      clk("clk"),
      pass("pass"),
      sphere_done("sphere_done"),
      triangle_done("triangle_done"),
      fetcher_busy("fetcher_busy", plan.params().iccs),
      rti_busy("rti_busy", plan.params().iccs),
      triangle_fifo("triangle_fifo", plan.params().iccs),
      icc("icc", plan.params().iccs),
      output_link("output_link", plan.params().iccs),
      control("control"),
      plan_(plan) {
    control(*this);
    SC_METHOD(watch);
    sensitive << clk.pos();
    dont_initialize();
}

std::uint64_t HostModule::run_pass(const std::vector<const TraceGroup*>& groups, std::uint8_t buf, bool overlap,
                                   bool drain) {
    for (std::size_t k = 0; k < icc.size(); ++k) icc[k]->start_pass(k < groups.size() ? groups[k] : nullptr, buf, overlap);
    drain_ = drain;
    prev_ = std::uint8_t(buf ^ 1);
    cycles_ = 0;
    running_ = true;
    pass.write(++number_);
    wait(ended_);
    for (std::size_t k = 0; k < icc.size(); ++k) icc[k]->end_pass();
    return cycles_;
}

bool HostModule::drained() const {
    for (std::size_t k = 0; k < icc.size(); ++k) {
        BufMask m = BufMask(fetcher_busy[k].read() | rti_busy[k].read());
        if (!triangle_fifo[k]->empty()) m = BufMask(m | (1u << triangle_fifo[k]->front().buf));
        if (drain_ ? m != 0 : ((m >> prev_) & 1) != 0) return false;
    }
    return true;
}

void HostModule::watch() {
    if (!running_) return;
    if (!settling_) {  // the edge: look once its registers have been written
        settling_ = true;
        next_trigger(sc_core::SC_ZERO_TIME);
        return;
    }
    settling_ = false;
    ++cycles_;
    if (each_cycle) each_cycle(cycles_);
    if (sphere_done.read() && triangle_done.read() && drained()) {
        running_ = false;
        ended_.notify();
        return;
    }
    if (check && !check(cycles_)) {
        running_ = false;
        ended_.notify();
    }
}

}  // namespace raplas::model::netlist
