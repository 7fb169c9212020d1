// One Intersection Calculation Core in the netlist (paper Figure 7): its
// blocks, the FIFOs between them as channels and the wires between them as
// signals, bound here. Its state is the Icc of the event engine: each
// module steps that ICC's block, so the statistics are the same objects.
//
// Wires inside the ICC (C: combinational, settled within the cycle; R: a
// register, changed at the clock edge):
//   sphere_selector --push--> sphere_fifo --pop--> psi --out (R)--> decoder
//   decoder --hold (C)--> psi;  decoder --push--> planeid_fifo, first_tri_fifo
//   decoder --decided (R)--> triangle_selector --pop--> planeid_fifo, first_tri_fifo
//   triangle_selector --planeid_pop (C)--> decoder
//   triangle_selector --push--> triangle_fifo --pop--> ray_data_fetcher
//   (sim.rtl = triangle_selector: both are the RTL block triangle_selector,
//   and ray_data_fetcher --triangle_pop (C)--> it)
//   ray_data_fetcher --issue (C)--> rti --update--> min_distance_memory --read--> output_link
//   rti --ready (R)--> ray_data_fetcher;  rti --test--> ray_memory
// and to the rest of the machine: the two links' record, valid and stall
// in, sphere_ready and triangle_ready (C) out, and the busy masks the Host
// reads to end a pass.
#pragma once

#include <systemc>

#include <memory>

#include "decoder_module.hpp"
#include "fetcher_module.hpp"
#include "fifo_channel.hpp"
#include "../config.hpp"
#include "../icc.hpp"
#include "memories_module.hpp"
#include "output_link_module.hpp"
#include "psi_module.hpp"
#include "rti_module.hpp"
#include "rtl/triangle_selector_rtl.hpp"
#include "signals.hpp"
#include "sphere_selector_module.hpp"
#include "triangle_selector_module.hpp"

namespace raplas::model::netlist {

// What the Host asks of an ICC before a pass (its results it reads through
// the Output Link, OutputLinkIf).
struct IccHostIf : virtual sc_core::sc_interface {
    // A new pass: group g (or none) in buffer `buf`; with `overlap` the other
    // buffer's work stays in flight. Loads the group into the Plane and Ray
    // Memories and resets the blocks for it (Icc::start_pass).
    virtual void start_pass(const TraceGroup* g, std::uint8_t buf, bool overlap) = 0;
    // The pass has ended: the ICC's statistics are brought up to date (an
    // RTL block's counters read into its Stats).
    virtual void end_pass() = 0;
};

class IccModule : public sc_core::sc_module, public IccHostIf {
    std::unique_ptr<Icc> owned_;  // (first: the blocks below are built on it)
    Icc& icc_;

public:
    sc_core::sc_in<bool> clk;
    sc_core::sc_in<std::uint32_t> pass;
    sc_core::sc_in<LinkRecord> sphere_record;
    sc_core::sc_in<bool> sphere_valid, sphere_stall, sphere_more;
    sc_core::sc_in<LinkRecord> triangle_record;
    sc_core::sc_in<bool> triangle_valid, triangle_stall;
    sc_core::sc_out<bool> sphere_ready, triangle_ready;
    sc_core::sc_out<BufMask> fetcher_busy, rti_busy;
    sc_core::sc_export<FifoStatusIf<TriWork>> triangle_fifo_status;
    sc_core::sc_export<IccHostIf> host;
    sc_core::sc_export<OutputLinkIf> results;  // the Output Link's
    // The stall anatomy, optional (an ICC whose testbench leaves them unbound
    // counts no cycles in which its FIFO alone held the link): its Triangle
    // FIFO holds the Triangle Stream Link this cycle (C, out), and how many
    // ICCs' FIFOs do (C, in, from the link).
    sc_core::sc_port<sc_core::sc_signal_inout_if<bool>, 1, sc_core::SC_ZERO_OR_MORE_BOUND> triangle_hold;
    sc_core::sc_port<sc_core::sc_signal_in_if<std::uint32_t>, 1, sc_core::SC_ZERO_OR_MORE_BOUND> triangle_holders;

    // The netlist's: the blocks step `icc`, which the caller owns (Top: the
    // event engine steps the same objects); with `results_from_trace` the
    // Output Link returns a group's hits from the trace (sim.functional = trace).
    // `rtl`: the block co-simulated as RTL (sim.rtl); `rtl_full_early`: its
    // broken variant (sim.fault = rtl_full_early).
    IccModule(sc_core::sc_module_name n, Icc& icc, bool results_from_trace, RtlBlock rtl = RtlBlock::none,
              bool rtl_full_early = false);
    // An ICC of its own, in a testbench or platform of the caller's
    // (examples/embed_icc, docs/MODEL.md §2, "Embedding an ICC"): its state
    // made from `params` and the functional model `f` of the scene (the
    // spheres and triangles the links will broadcast), which must outlive it.
    IccModule(sc_core::sc_module_name n, const Icc::Params& params, const Functional& f,
              RtlBlock rtl = RtlBlock::none);

    // Its blocks' state and statistics.
    const Icc& state() const { return icc_; }

    void start_pass(const TraceGroup* g, std::uint8_t buf, bool overlap) override;
    void end_pass() override;
    // Wires inside the ICC.
    sc_core::sc_signal<bool> active;           // R: the ICC has a group this pass (set by the Host)
    sc_core::sc_signal<std::uint8_t> buf;      // R: its buffer
    sc_core::sc_signal<PsiOut> psi_out;        // R
    sc_core::sc_signal<bool> hold;             // C
    sc_core::sc_signal<std::uint32_t> decided; // R
    sc_core::sc_signal<bool> planeid_pop;      // C
    sc_core::sc_signal<RtiIssue> rti_issue;    // C
    sc_core::sc_signal<bool> rti_ready;        // R
    std::unique_ptr<sc_core::sc_signal<std::uint32_t>> triangle_pop;  // C (sim.rtl = triangle_selector)
    sc_core::sc_signal<bool> fifo_hold;        // C: triangle_hold, inside
    sc_core::sc_signal<std::uint32_t> holders; // C: triangle_holders, inside

    // FIFOs (the Triangle FIFO's channel only with the C++ Triangle Selector).
    SphereFifoChannel sphere_fifo;
    FifoChannelOf<PlaneIdEntry> planeid_fifo;
    FifoChannelOf<FirstTriEntry> first_tri_fifo;
    std::unique_ptr<FifoChannelOf<TriWork>> triangle_fifo;

    // Blocks: the Triangle Selector (with the Triangle FIFO) is C++ or RTL.
    SphereSelectorModule sphere_selector;
    PsiModule psi;
    DecoderModule decoder;
    std::unique_ptr<TriangleSelectorModule> triangle_selector;
    std::unique_ptr<TriangleSelectorRtl> triangle_selector_rtl;
    RayDataFetcherModule ray_data_fetcher;
    RayMemoryModule ray_memory;
    RtiModule rti;
    MinDistanceMemoryModule min_distance_memory;
    OutputLinkModule output_link;

private:
    // Joins the optional anatomy ports to the wires inside, when bound.
    void end_of_elaboration() override;
    IccModule(sc_core::sc_module_name n, std::unique_ptr<Icc> owned, Icc* shared, bool results_from_trace,
              RtlBlock rtl, bool rtl_full_early);
};

}  // namespace raplas::model::netlist
