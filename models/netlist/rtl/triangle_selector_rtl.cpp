#include "triangle_selector_rtl.hpp"

#include <string>

// The Verilated modules (verilator --sc, models/CMakeLists.txt): the block,
// and its broken variant built with FULL_EARLY = 1. (Their headers include
// systemc.h, which opens SystemC's namespaces: only here.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include "Vtriangle_selector.h"
#include "Vtriangle_selector_full_early.h"
#pragma GCC diagnostic pop

namespace raplas::model::netlist {

namespace {

// A Verilated module of type V, named "rtl", owned by `slot`.
template <class V>
V& make_rtl(std::unique_ptr<sc_core::sc_module>& slot) {
    auto m = std::make_unique<V>("rtl");
    V& v = *m;
    slot = std::move(m);
    return v;
}

}  // namespace

TriangleSelectorRtl::TriangleSelectorRtl(sc_core::sc_module_name n, TriangleSelector& core, Fifo<TriWork>& fifo,
                                         bool full_early)
    : sc_core::sc_module(n),
      fetcher_pop("fetcher_pop"),
      core_(core),
      fifo_(fifo),
      depth_value_(fifo.depth()),
      depth_("depth", fifo.depth()),
      needed_full_("needed_full", core.params().policy == StallPolicy::needed_full),
      buf_sel_("buf_sel"),
      rec_present_("rec_present"),
      ft_valid_("ft_valid"),
      rec_index_("rec_index"),
      rec_sphere_("rec_sphere"),
      ft_sphere_("ft_sphere"),
      ft_first_("ft_first"),
      ft_count_("ft_count"),
      pid_rows_("pid_rows"),
      pid_cols_("pid_cols"),
      ram_we_("ram_we"),
      ram_wbuf_("ram_wbuf"),
      ram_waddr_("ram_waddr"),
      ram_wtri_("ram_wtri"),
      ram_wrows_("ram_wrows"),
      ram_wcols_("ram_wcols"),
      rd_ptr_("rd_ptr"),
      count_("count"),
      full_("full"),
      empty_("empty", true),
      selected_("selected"),
      blocked_full_("blocked_full"),
      blocked_undecided_("blocked_undecided"),
      max_count_("max_count"),
      first_tri_front_(front_event_of<FirstTriEntry>(first_tri)),
      planeid_front_(front_event_of<PlaneIdEntry>(planeid)) {
    auto bind = [&](auto& m) {
        m.clk(clk);
        m.depth(depth_);
        m.needed_full(needed_full_);
        m.active(active);
        m.buf_sel(buf_sel_);
        m.decided(decided);
        m.rec_present(rec_present_);
        m.rec_index(rec_index_);
        m.rec_sphere(rec_sphere_);
        m.valid(valid);
        m.stall(stall);
        m.ft_valid(ft_valid_);
        m.ft_sphere(ft_sphere_);
        m.ft_first(ft_first_);
        m.ft_count(ft_count_);
        m.pid_rows(pid_rows_);
        m.pid_cols(pid_cols_);
        m.ready(ready);
        m.planeid_pop(planeid_pop);
        m.ram_we(ram_we_);
        m.ram_waddr(ram_waddr_);
        m.ram_wtri(ram_wtri_);
        m.ram_wbuf(ram_wbuf_);
        m.ram_wrows(ram_wrows_);
        m.ram_wcols(ram_wcols_);
        m.pop(fetcher_pop);
        m.rd_ptr(rd_ptr_);
        m.count(count_);
        m.full(full_);
        m.empty(empty_);
        m.selected(selected_);
        m.max_count(max_count_);
        m.blocked_full(blocked_full_);
        m.blocked_undecided(blocked_undecided_);
    };
    if (full_early) bind(make_rtl<Vtriangle_selector_full_early>(rtl_));
    else bind(make_rtl<Vtriangle_selector>(rtl_));

    SC_METHOD(drive);
    sensitive << record << buf << first_tri_front_ << planeid_front_;
    SC_METHOD(hold);
    sensitive << ready << decided << record;
    SC_METHOD(changed);
    sensitive << rd_ptr_ << count_;
    dont_initialize();
    SC_METHOD(tick);
    sensitive << clk.pos();
    dont_initialize();
}

TriangleSelectorRtl::~TriangleSelectorRtl() = default;

void TriangleSelectorRtl::drive() {
    const LinkRecord& r = record.read();
    rec_present_.write(r.present);
    rec_index_.write(r.index);
    rec_sphere_.write(r.sphere);
    buf_sel_.write(buf.read() != 0);
    const bool ft = !first_tri->empty();
    const FirstTriEntry f = ft ? first_tri->front() : FirstTriEntry{};
    const PlaneIdEntry p = ft ? planeid->front() : PlaneIdEntry{};
    ft_valid_.write(ft);
    ft_sphere_.write(f.sphere);
    ft_first_.write(f.first);
    ft_count_.write(f.count);
    pid_rows_.write(p.rows);
    pid_cols_.write(p.cols);
}

void TriangleSelectorRtl::hold() {
    const LinkRecord& r = record.read();
    fifo_hold.write(TriangleSelector::fifo_holds(ready.read(), decided.read(), r.present ? r.sphere : 0));
}

void TriangleSelectorRtl::changed() { changed_.notify(); }

void TriangleSelectorRtl::tick() {
    // (the values the RTL settled on in the cycle that ends)
    if (ram_we_.read()) {
        const std::uint32_t a = ram_waddr_.read();
        if (a >= depth_value_) SC_REPORT_FATAL(name(), "the RTL writes past the Triangle FIFO's RAM");
        fifo_.ram(a) = TriWork(ram_wtri_.read(), ram_wrows_.read(), ram_wcols_.read(), ram_wbuf_.read() ? 1 : 0);
    }
    if (planeid_pop.read()) {
        planeid->pop();
        first_tri->pop();
    }
    if (stall.read() && fifo_hold.read() && holders.read() == 1) ++alone_;
}

TriWork TriangleSelectorRtl::at(std::uint32_t i) const {
    std::uint32_t a = rd_ptr_.read() + i;  // (i < size() <= depth: one wrap at most)
    if (a >= depth_value_) a -= depth_value_;
    return fifo_.ram(a);
}

void TriangleSelectorRtl::pop(std::uint32_t n) {
    // Called by the Ray Data Fetcher at the clock edge: the RTL takes its
    // pops from the Fetcher's `fetcher_pop` wire as it stood in the cycle that ends.
    if (n != fetcher_pop.read())
        SC_REPORT_FATAL(name(), ("the Ray Data Fetcher pops " + std::to_string(n) + " entries but announced " +
                                 std::to_string(fetcher_pop.read()))
                                    .c_str());
}

void TriangleSelectorRtl::start_pass(bool overlap) {
    if (!overlap && count_.read() != 0)
        SC_REPORT_FATAL(name(), "a pass without overlap starts before the Triangle FIFO has drained");
    changed_.notify(sc_core::SC_ZERO_TIME);
}

void TriangleSelectorRtl::read_counters() {
    const Counters now{selected_.read(), blocked_full_.read(), blocked_undecided_.read()};
    const std::uint64_t pushes = now.selected - read_.selected;
    core_.add_selected(pushes);
    fifo_.record_push(max_count_.read(), pushes);
    core_.note_blocked_full(fifo_, now.blocked_full - read_.blocked_full);
    core_.add_blocked_undecided(now.blocked_undecided - read_.blocked_undecided);
    core_.note_alone(alone_);
    alone_ = 0;
    read_ = now;
}

}  // namespace raplas::model::netlist
