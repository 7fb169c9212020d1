// Intersection Calculation Core (paper Figure 7): Selector + Sphere FIFO,
// Plane-Sphere Intersectors, Decoder, PlaneID FIFO, First-Triangle-ID FIFO,
// Triangle Selector + Triangle FIFO, Ray Data Fetcher, Ray-Triangle
// Intersector, Min-distance Memory, Output Link. Each block is a C++ state
// machine of its own; the ICC holds them, with its group state. The netlist
// (models/netlist/) wraps each block in a SystemC module with ports that
// steps it once per clock cycle; the event engine (event_engine.cpp) steps
// them only when something can change, an ICC's front end (tick_front) in
// the order of the netlist's cycle: Decoder, PSI, Sphere Selector.
#pragma once

#include <memory>

#include "decoder.hpp"
#include "fifo.hpp"
#include "functional.hpp"
#include "memories.hpp"
#include "min_distance_memory.hpp"
#include "output_link.hpp"
#include "plane_sphere_intersector.hpp"
#include "ray_data_fetcher.hpp"
#include "ray_triangle_intersector.hpp"
#include "sphere_selector.hpp"
#include "triangle_selector.hpp"

namespace raplas::model {

// What the Decoder needs to know of a sphere: its triangle range.
struct SphereInfo {
    const SphereMemory* mem;
    std::uint32_t first_tri(std::uint32_t s) const { return mem->peek(s).first_tri; }
    std::uint32_t tri_count(std::uint32_t s) const { return mem->peek(s).tri_count; }
    // Sphere s's First-Triangle-ID FIFO entry.
    FirstTriEntry entry(std::uint32_t s) const {
        const auto& r = mem->peek(s);
        return {s, r.first_tri, r.tri_count};
    }
};

class Icc {
public:
    struct Params {
        FifoParams sphere_fifo{1000};
        FifoParams triangle_fifo{1000};
        FifoParams planeid_fifo{1000};
        PlaneSphereIntersector::Params psi;
        Decoder::Params decoder;
        RayTriangleIntersector::Params rti;
        RayDataFetcher::Params fetcher;
        TriangleSelector::Params selector;
        MinDistanceMemory::Params min_distance;
        OutputLink::Params output;
    };
    struct Stats {
        std::uint64_t pass_cycles = 0;   // cycles of passes in which this ICC had a group
        std::uint64_t idle_cycles = 0;   // cycles of passes in which it had none
        std::uint64_t groups = 0;
    };

    Icc(const Params& p, const Functional& f)
        : sphere_fifo("sphere_fifo", p.sphere_fifo),
          psi(p.psi),
          decoder(p.decoder),
          planeid_fifo("planeid_fifo", p.planeid_fifo),
          first_tri_fifo("first_tri_fifo", p.planeid_fifo),
          triangle_selector(p.selector),
          triangle_fifo("triangle_fifo", p.triangle_fifo),
          ray_data_fetcher(p.fetcher),
          rti(p.rti),
          min_distance_0(p.min_distance),
          min_distance_1(p.min_distance),
          output(p.output),
          params_(p),
          units_{f.make_unit(), f.make_unit()},
          functional_(f) {}

    // A pass gives this ICC group g (or none) in Ray Memory / Min-distance
    // Memory buffer `buf`. With `overlap` the other buffer's group may still
    // be draining behind the Triangle Selector, and its work is kept.
    void start_pass(const TraceGroup* g, std::uint8_t buf = 0, bool overlap = false) {
        group_ = g;
        sphere_fifo.clear();
        planeid_fifo.clear();
        first_tri_fifo.clear();
        decoder.start_group();
        if (!overlap) {
            triangle_fifo.clear();
            rti.start_group();
        }
        if (!g) return;
        buf_ = buf;
        ++stats_.groups;
        selected_before_ = triangle_selector.stats().selected;
        sphere_pushes_before_ = sphere_fifo.stats().pushes;
        GroupUnit& u = *units_[buf];
        if (loaded_[buf] != g) load(*g, buf);
        loaded_[buf] = nullptr;
        psi.start_group(2 * g->n, &u.sphere_hits(), params_.decoder.select == TriangleSelect::any ? &u.pairless() : nullptr);
        ray_data_fetcher.start_group(g->n, buf, overlap);
        min_distance(buf).reset(std::size_t(g->n) * g->n);
        if (answer_at_load_) {
            Answers& a = answers_[buf];
            min_distance(buf).set(std::move(a.hits), a.hits_found);
            rti.account(0, a.hits_found, 0);
        }
    }
    // The answers are the loaded group's (answer_at_load).
    bool answered() const { return answer_at_load_; }
    bool active() const { return group_ != nullptr; }
    // Loads a group's planes and rays into buffer `buf` and computes its PSI
    // results ahead of start_pass (thread-safe across ICCs: the host loads
    // them in parallel).
    void preload(const TraceGroup* g, std::uint8_t buf = 0) {
        if (g) load(*g, buf);
        loaded_[buf] = g;
    }
    // Event-driven simulation in the compute functional mode: a group's
    // ray-triangle answers are found when it is loaded (on the loading
    // thread), not when its triangles are selected. Every triangle of every
    // sphere the Decoder queues with a row and a column plane is selected in
    // the pass, with that sphere's masks, and the nearest hit does not depend
    // on the order of the tests, so these are the answers the selections
    // would give, test for test; the event engine only times them. The tests
    // run in selection order (spheres, then triangles, ascending), so an
    // injected wrong answer (sim.fault = wrong_rti) goes to the same test.
    void answer_at_load(const SphereInfo& info) {
        answer_info_ = info;
        answer_at_load_ = !rti.stuck();  // a stuck RTI never tests (its ICC stops the run)
    }
    void add_idle(std::uint64_t cycles) { stats_.idle_cycles += cycles; }
    // Fault injection (sim.fault = wrong_rti): one wrong ray-triangle answer
    // in this ICC, whichever buffer's group meets it first.
    void inject_wrong_rti() {
        wrong_rti_fired_ = std::make_shared<bool>(false);
        for (auto& u : units_) u = with_wrong_rti(std::move(u), wrong_rti_fired_);
    }
    // The injected fault counts as fired already (it fired in a pass another
    // run simulates).
    void disarm_wrong_rti() {
        if (wrong_rti_fired_) *wrong_rti_fired_ = true;
    }
    const TraceGroup* group() const { return group_; }

    bool sphere_ready() const { return sphere_selector.ready(active(), sphere_fifo); }
    void note_sphere_blocked(std::uint64_t cycles = 1) { sphere_selector.note_blocked(sphere_fifo, cycles); }
    bool triangle_ready(std::uint32_t sphere) const {
        return triangle_selector.ready(active(), sphere, decoder.decided(), first_tri_fifo, triangle_fifo);
    }
    void note_triangle_blocked(std::uint32_t sphere) {
        triangle_selector.note_blocked(sphere, decoder.decided(), triangle_fifo);
    }

    // Decoder, PSI and Sphere Selector.
    void tick_front(std::int64_t sphere, const SphereInfo& info, bool spheres_pending) {
        const bool hold = decoder.tick(psi, planeid_fifo, first_tri_fifo, info);
        psi.tick(sphere_fifo, hold, spheres_pending || !sphere_fifo.empty());
        if (sphere >= 0) sphere_selector.receive(true, std::uint32_t(sphere), sphere_fifo);
    }
    // The Decoder holds this cycle: its PSI's result is to be queued and the
    // PlaneID or First-Triangle-ID FIFO is full.
    bool decoder_holds() const { return decoder.holds(psi, planeid_fifo, first_tri_fifo); }
    // n cycles of tick_front with no sphere and the Decoder holding
    // (decoder_holds() stays true): its counters, and those of a full Sphere
    // FIFO stopping the sphere stream (event-driven simulation).
    void hold_front(std::uint64_t n) {
        decoder.note_held(n, planeid_fifo, first_tri_fifo);
        psi.add_stalled(n);
        if (!sphere_ready()) note_sphere_blocked(n);
    }
    bool back_idle() const { return rti.empty() && ray_data_fetcher.idle() && triangle_fifo.empty(); }
    // The unit of this pass's group (and of buffer `buf`).
    const GroupUnit& unit() const { return *units_[buf_]; }
    GroupUnit& unit() { return *units_[buf_]; }
    GroupUnit& unit(std::uint8_t buf) { return *units_[buf]; }
    // This pass's Ray Memory / Min-distance Memory buffer.
    std::uint8_t buffer() const { return buf_; }
    MinDistanceMemory& min_distance(std::uint8_t buf) { return buf ? min_distance_1 : min_distance_0; }
    const MinDistanceMemory& min_distance(std::uint8_t buf) const { return buf ? min_distance_1 : min_distance_0; }
    // Nothing left in flight behind the Triangle Selector.
    bool drained() const { return back_idle(); }
    // No work of buffer `buf`'s group left behind the Triangle Selector (the
    // Triangle FIFO is in issue order: older groups' entries come first).
    bool drained(std::uint8_t buf) const {
        return !(!triangle_fifo.empty() && triangle_fifo.front().buf == buf) && !ray_data_fetcher.holds(buf) &&
               rti.inflight(buf) == 0;
    }

    // End of this ICC's pass (`cycles` long, `triangles` broadcast): the
    // front end's figures.
    void finish_pass(std::uint64_t cycles, std::uint64_t triangles) {
        stats_.pass_cycles += cycles;
        psi.end_group();
        decoder.end_group();
        triangle_selector.end_group(triangles, selected_before_);
        sphere_selector.end_group(sphere_fifo.stats().pushes - sphere_pushes_before_);
    }
    // Group g, in buffer `buf`, has drained: its results out through the
    // Output Link.
    const std::vector<Hit>& results(const TraceGroup& g, std::uint8_t buf) {
        MinDistanceMemory& m = min_distance(buf);
        if (functional_.mode() == FunctionalMode::trace) m.set(g.hits);
        output.send(std::uint64_t(g.n) * g.n);
        return m.hits();
    }
    // End of the run: pass cycles in which the RTI took no pair.
    void finish_run() {
        const std::uint64_t busy = rti.stats().busy_cycles;
        ray_data_fetcher.add_starved(stats_.pass_cycles > busy ? stats_.pass_cycles - busy : 0);
    }

    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

    SphereSelector sphere_selector;
    SphereFifo sphere_fifo;
    PlaneSphereIntersector psi;
    Decoder decoder;
    Fifo<PlaneIdEntry> planeid_fifo;
    Fifo<FirstTriEntry> first_tri_fifo;
    TriangleSelector triangle_selector;
    Fifo<TriWork> triangle_fifo;
    RayDataFetcher ray_data_fetcher;
    RayTriangleIntersector rti;
    MinDistanceMemory min_distance_0, min_distance_1;  // double-buffered (overlapped passes)
    OutputLink output;

private:
    void load(const TraceGroup& g, std::uint8_t buf) {
        GroupUnit& u = *units_[buf];
        u.load(g);
        if (!answer_at_load_) return;
        Answers& a = answers_[buf];
        a.hits.assign(std::size_t(g.n) * g.n, Hit{});
        a.hits_found = 0;
        for (const SphereHitRec& s : u.sphere_hits()) {
            const std::uint32_t first = answer_info_.first_tri(s.sphere), end = first + answer_info_.tri_count(s.sphere);
            for (std::uint32_t tri = first; tri < end; ++tri)
                a.hits_found += u.rti_tests(s.rows, s.cols, tri, g.n, [&](std::uint32_t ray, double t) {
                    keep_nearest(a.hits[ray], t, std::int32_t(tri));
                });
        }
    }

    Params params_;
    std::unique_ptr<GroupUnit> units_[2];  // Ray Memory (and plane tests) of the two buffers
    std::shared_ptr<bool> wrong_rti_fired_;  // sim.fault = wrong_rti: shared by both buffers' units
    const Functional& functional_;
    const TraceGroup* group_ = nullptr;
    const TraceGroup* loaded_[2] = {nullptr, nullptr};
    struct Answers {
        std::vector<Hit> hits;  // per ray, the nearest
        std::uint64_t hits_found = 0;
    };
    Answers answers_[2];  // answer_at_load: per buffer, its loaded group's
    bool answer_at_load_ = false;
    SphereInfo answer_info_{nullptr};
    std::uint8_t buf_ = 0;
    std::uint64_t selected_before_ = 0, sphere_pushes_before_ = 0;
    Stats stats_;
};

}  // namespace raplas::model
