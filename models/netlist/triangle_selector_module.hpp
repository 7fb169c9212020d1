// Triangle Selector (with the Triangle FIFO it writes) in the netlist. Two
// combinational wires: `ready` to the Triangle Stream Link (its sphere is
// decided and, under the stall policy, its Triangle FIFO can take it,
// judged at the start of the cycle), and `planeid_pop` to the Decoder (it
// takes the last triangle of the sphere at the head of its First-Triangle-ID
// FIFO this cycle, so that FIFO and the PlaneID FIFO free an entry). At the
// clock edge it keeps or discards the triangle broadcast (TriangleSelector,
// shared with the event engine).
// Its FIFO's hold on the link (TriangleSelector::hold) is "full" in the same
// cycle by default. With link.stall_latency L it is the hold of cycle c - L,
// from a pipeline of L registers (the hold of the pass's first cycle for the
// first L cycles), and with link.resume_occupancy a register keeps it up
// until the FIFO has drained that far.
#pragma once

#include <systemc>

#include <vector>

#include "fifo_channel.hpp"
#include "signals.hpp"
#include "triangle_selector_ports.hpp"
#include "../triangle_selector.hpp"

namespace raplas::model::netlist {

class TriangleSelectorModule : public sc_core::sc_module, public TriangleSelectorPorts {
public:
    using Params = TriangleSelector::Params;
    using Stats = TriangleSelector::Stats;

    // (and TriangleSelectorPorts')
    sc_core::sc_in<std::uint32_t> pass;
    sc_core::sc_port<FifoWriteIf<TriWork>> fifo;  // the Triangle FIFO

    SC_HAS_PROCESS(TriangleSelectorModule);
    // `depth`: its Triangle FIFO's.
    TriangleSelectorModule(sc_core::sc_module_name n, TriangleSelector& core, std::uint32_t depth)
        : sc_core::sc_module(n),
          pass("pass"),
          fifo("fifo"),
          core_(core),
          first_tri_front_(front_event_of<FirstTriEntry>(first_tri)),
          fifo_full_(full_event_of<TriWork>(fifo)),
          fifo_changed_(sc_core::sc_event_finder_t<FifoStatusIf<TriWork>>(fifo, &FifoStatusIf<TriWork>::default_event)),
          depth_(depth),
          latency_(core.params().stall_latency),
          plain_(core.params().plain()),
          line_(std::size_t(latency_) + 1, 0),
          held_("held", false) {
        SC_METHOD(settle);
        sensitive << record << valid << decided << first_tri_front_ << fifo_full_ << active << pass;
        if (!plain_) sensitive << fifo_changed_ << held_;
        dont_initialize();
        SC_METHOD(tick);
        sensitive << clk.pos();
        dont_initialize();
    }
    const Stats& stats() const { return core_.stats(); }

private:
    // The sphere of the triangle offered (0 when none is, as the event engine take it).
    std::uint32_t sphere() const {
        const LinkRecord& r = record.read();
        return r.present ? r.sphere : 0;
    }
    // The cycle of the pass this is (a new pass, read from its number so
    // that the order of processes in a delta cycle does not matter, starts
    // at 0 and refills the pipeline from its first cycle's hold).
    std::uint64_t cycle() const { return pass.read() == pass_ ? cycle_ : 0; }
    // Its FIFO's hold at the start of this cycle (not delayed).
    bool hold_now() const { return core_.hold(fifo->size(), depth_, cycle() > 0 && before_); }
    // The hold the link sees this cycle.
    bool held() const {
        if (plain_) return fifo->full();
        if (latency_ == 0 || cycle() == 0) return hold_now();
        return held_.read();
    }
    void settle() {
        const std::uint32_t s = sphere();
        const bool act = active.read();
        const bool r = core_.ready_held(act, s, decided.read(), bound(first_tri), held());
        ready.write(r);
        fifo_hold.write(TriangleSelector::fifo_holds(r, decided.read(), s));
        bool pop = false;
        if (valid.read() && act && TriangleSelector::wants(s, bound(first_tri))) {
            const FirstTriEntry f = first_tri->front();
            pop = record.read().index + 1 == f.first + f.count;
        }
        planeid_pop.write(pop);
    }
    void tick() {
        if (!plain_) {  // the hold of this cycle into the pipeline; the link's of the next
            if (pass.read() != pass_) {
                pass_ = pass.read();
                cycle_ = 0;
            }
            const bool h = hold_now();
            line_[cycle_ % line_.size()] = h;
            before_ = h;
            ++cycle_;
            if (latency_) held_.write(line_[(cycle_ < latency_ ? 0 : cycle_ - latency_) % line_.size()] != 0);
        }
        if (valid.read()) {
            core_.receive(active.read(), record.read().index, sphere(), bound(planeid), bound(first_tri), bound(fifo),
                          buf.read());
        } else if (stall.read() && !ready.read()) {
            core_.note_blocked(sphere(), decided.read(), bound(fifo));
            if (fifo_hold.read() && holders.read() == 1) core_.note_alone();
        }
    }

    TriangleSelector& core_;
    FifoEventFinder<FirstTriEntry> first_tri_front_;
    FifoEventFinder<TriWork> fifo_full_, fifo_changed_;
    std::uint32_t depth_, latency_;
    bool plain_;
    std::vector<std::uint8_t> line_;  // the holds of the last latency + 1 cycles, by cycle modulo its size
    std::uint64_t cycle_ = 0;         // cycles of pass `pass_`
    std::uint32_t pass_ = 0;
    bool before_ = false;             // the hold of the cycle before
    sc_core::sc_signal<bool> held_;   // the hold the link sees in this cycle (with a latency)
};

}  // namespace raplas::model::netlist
