// Decoder in the netlist. Its `hold` wire to the PSI is combinational: the
// PSI's result is to be kept and the PlaneID / First-Triangle-ID FIFOs are
// full at the start of the cycle and not popped by the Triangle Selector in
// it (`planeid_pop`, itself combinational: it depends on the triangle
// broadcast). At the clock edge it takes the result (Decoder, shared with
// the event engine): queues it through its ports, and moves its `decided`
// count, a register the Triangle Selectors read.
#pragma once

#include <systemc>

#include "../decoder.hpp"
#include "fifo_channel.hpp"
#include "signals.hpp"

namespace raplas::model::netlist {

class DecoderModule : public sc_core::sc_module {
public:
    using Params = Decoder::Params;
    using Stats = Decoder::Stats;

    sc_core::sc_in<bool> clk;
    sc_core::sc_in<std::uint32_t> pass;
    sc_core::sc_in<bool> active;
    sc_core::sc_in<PsiOut> psi;         // the PSI's output register
    sc_core::sc_in<bool> planeid_pop;   // the Triangle Selector pops the head entries this cycle
    sc_core::sc_port<FifoWriteIf<PlaneIdEntry>> planeid;
    sc_core::sc_port<FifoWriteIf<FirstTriEntry>> first_tri;
    sc_core::sc_out<bool> hold;
    sc_core::sc_out<std::uint32_t> decided;  // spheres decided this pass

    SC_HAS_PROCESS(DecoderModule);
    DecoderModule(sc_core::sc_module_name n, Decoder& core)
        : sc_core::sc_module(n),
          clk("clk"),
          pass("pass"),
          active("active"),
          psi("psi"),
          planeid_pop("planeid_pop"),
          planeid("planeid"),
          first_tri("first_tri"),
          hold("hold"),
          decided("decided"),
          core_(core),
          planeid_full_(full_event_of<PlaneIdEntry>(planeid)),
          first_tri_full_(full_event_of<FirstTriEntry>(first_tri)) {
        SC_METHOD(settle);
        sensitive << psi << planeid_pop << planeid_full_ << first_tri_full_ << active << pass;
        dont_initialize();
        SC_METHOD(tick);
        sensitive << clk.pos() << pass;
        dont_initialize();
    }
    const Stats& stats() const { return core_.stats(); }

private:
    // The PSI's output as Decoder::tick sees it (the PSI pops it itself when `hold` is low).
    struct PsiView {
        const PsiOut& o;
        bool has_output() const { return o.valid; }
        const PsiResult& output() const { return o.result; }
        void pop_output() const {}
    };
    // A FIFO as the Decoder writes it: full at the start of the cycle and not popped in it.
    template <class T>
    struct Writer {
        FifoWriteIf<T>& fifo;
        bool popped;
        bool full() const { return fifo.full() && !popped; }
        void push(const T& v) { fifo.push(v); }
        void note_full(std::uint64_t n) { fifo.note_full(n); }
    };
    // The kept sphere's First-Triangle-ID entry, from the range it carries.
    struct Range {
        const PsiOut& o;
        FirstTriEntry entry(std::uint32_t s) const { return {s, o.first_tri, o.tri_count}; }
    };

    void settle() {
        const bool pop = planeid_pop.read();
        const Writer<PlaneIdEntry> p{bound(planeid), pop};
        const Writer<FirstTriEntry> f{bound(first_tri), pop};
        hold.write(active.read() && core_.holds(PsiView{psi.read()}, p, f));
    }
    void tick() {
        if (pass.event()) {  // a new pass
            decided.write(core_.decided());
            return;
        }
        if (!active.read()) return;
        const PsiOut& o = psi.read();
        const bool pop = planeid_pop.read();
        PsiView view{o};
        Writer<PlaneIdEntry> p{bound(planeid), pop};
        Writer<FirstTriEntry> f{bound(first_tri), pop};
        const bool held = core_.tick(view, p, f, Range{o});
        if (held != hold.read())  // (the combinational wire and the step must agree)
            SC_REPORT_FATAL(name(), "the Decoder's hold wire disagrees with its step");
        decided.write(core_.decided());
    }

    Decoder& core_;
    FifoEventFinder<PlaneIdEntry> planeid_full_;
    FifoEventFinder<FirstTriEntry> first_tri_full_;
};

}  // namespace raplas::model::netlist
