// Event-driven pass of the timing model (sim.mode = "event"): the same
// machine, the same cycle-by-cycle semantics as the netlist (models/netlist/), computed with
// less work. Exactness rests on three facts:
//  1. Every ICC sees the same sphere stream, so the sphere side (Sphere FIFO,
//     PSI timing, Decoder's `decided` count) of every ICC whose PSI has never
//     been held is identical: one shared reference pipeline stands for all of
//     them. An ICC whose Decoder cannot queue a hit takes over the reference
//     state and is stepped on its own ("individual") until its sphere side
//     runs dry (Sphere FIFO and PSI empty, every sphere received decided)
//     while the reference's has too: both are then in the same state, and
//     it rejoins the reference.
//  2. Behind the Triangle Selector each ICC is a work-conserving queue: a
//     triangle selected in cycle c with m = |rows|·|cols| pairs is popped by
//     the Ray Data Fetcher at the first free issue slot from c+1 on, issues
//     its pairs R per cycle, and its last result leaves the RTI L cycles
//     after its last pair. All of this follows from the selection cycle
//     alone, and nearest hits do not depend on the order of the tests, so
//     each selected triangle is scheduled once, when selected; its tests are
//     made when its group is loaded (Icc::answer_at_load), or when it is
//     selected where that cannot be (an ICC with an injected wrong answer).
//     Only the Triangle FIFO's occupancy is visible to the link.
//  3. An ICC is therefore touched only when the Decoder releases one of its
//     kept spheres, when the triangle stream reaches its pending spheres'
//     triangles, and while its Triangle FIFO is full. When none of that
//     happens and the shared pipeline streams steadily (a sphere in and a
//     decision out every cycle), nothing but the stream positions changes
//     until the next such event: those cycles are skipped in one step. The
//     same holds once every sphere is decided (only the triangle stream
//     moves), once the triangle stream is done too (only the back ends
//     drain, in closed form by 2.), and while full Triangle FIFOs hold the
//     triangle stream (nothing changes until the first of them is popped).
//     A skip takes every cycle before the event that ends it and closes the
//     last as a stepped cycle closes (the cruises that end, the holds on the
//     link in the next cycle); the event's own cycle is stepped.
//  4. Under icc.triangle_select = any most selected triangles have no pair
//     (spheres cut by row planes only or column planes only). Each holds the
//     Fetcher one cycle, so an ICC pops them in closed form from the cycles
//     they are broadcast, and as long as its Triangle FIFO can neither fill
//     nor pass its largest occupancy so far, the pair-less spheres queued in
//     its FIFOs, contiguous or not, change nothing in it but counts and its
//     PlaneID / First-Triangle-ID FIFOs: it "coasts", taken out of the
//     selection until the last of them (past it, to the next queued sphere
//     with a pair, when that is queued already), and its FIFOs are brought up
//     to date whenever they are read. (Not with icc.rdf_empty_cycles > 1,
//     where such triangles pile up; with 0 only from an idle Fetcher; not
//     with a one-entry Triangle FIFO, which one of them fills.)
//  5. On the Decoder's side, a reference ICC queues each of its kept
//     spheres in the cycle the shared side decides it; while its PlaneID
//     FIFO can neither fill nor pass its largest occupancy so far, those
//     pushes are made only when its FIFOs are read, and the ICC is touched
//     once per such span, not once per sphere. Its FIFOs do not store what
//     it queues: they hold a stretch of its kept spheres, in order, so what
//     follows their stored entries is a count and a cursor into its lists;
//     pushes move one cursor and a coast's pops the other, by runs of
//     pair-less spheres (a run holds consecutive triangles), and an entry
//     is stored only when a selection reads it, or the ICC leaves the
//     shared side.
//  6. An ICC stepped on its own whose Decoder holds (its PlaneID or
//     First-Triangle-ID FIFO full) "dozes": until a selection pops that
//     FIFO, only counts change and its Sphere FIFO takes the spheres
//     broadcast, up to full. It is left out of the per-cycle steps; the links
//     see it through the link position at which its Sphere FIFO fills and its
//     decision count, and its counts are settled when it wakes. A dozer that
//     coasts (4.) wakes too when its coast takes the last triangle of its
//     FIFOs' head entry, when that comes before the coast's end: it waits for
//     that triangle in a queue of its own.
//  7. An ICC stepped on its own whose pipe streams (one batch per sphere,
//     a full pipe, its Sphere FIFO neither empty nor full) decides one
//     sphere a cycle until its Sphere FIFO runs dry (once the sphere stream
//     has stood still in as many cycles as that FIFO held) or its next
//     queued sphere leaves the pipe: it "cruises", left out of the per-cycle
//     steps, and is brought up to date in one step then. With
//     link.stall_policy = any_full (the link then reads no ICC's FIFOs) a
//     cruise also passes as many kept spheres as its PlaneID and
//     First-Triangle-ID FIFOs have room for (pops only add to it), and ends
//     at the next, where its Decoder may hold. Each is pushed when its FIFOs
//     are read, before the pops of later cycles (the triangle stream's sends
//     are kept as runs of cycles, which places a coast's pops), so that the
//     FIFOs' largest occupancy comes out as in the steps.
//     The skips of 3. run past dozers and cruisers, stopping short of a
//     dozer's Sphere FIFO filling, a cruise's end or its FIFO running dry;
//     once the sphere stream is done, dozers and cruisers are all that is
//     left of the sphere side, and the skips run on. A frozen sphere side
//     ticks the shared pipeline within the skip until it runs dry when no
//     hand-over is due to a sphere it holds: nothing reads it meanwhile.
//     The sphere stream is steady too when no ICC is on the shared pipeline
//     but some cruise or doze (a lone ICC under the any-plane reading): the
//     shared side still follows the stream, and the Decoder's hand-overs it
//     passes only move the ICCs' cursors, which the next stepped cycle does.
//     With one batch per sphere it is not even ticked while no ICC is on it:
//     never held, it takes each sphere when every ICC's Sphere FIFO does and
//     decides it no later, so it has run dry, every sphere broadcast
//     decided, by the time an ICC's own sphere side has, the only time an
//     ICC reads it (to rejoin); it is set so then.
//  8. The only ICC stepped on its own whose PSI pipe is full (one batch per
//     sphere; under the any-plane reading mostly one whose coast's pops
//     free a FIFO slot every few cycles, each letting its Decoder decide up
//     to its next kept sphere) keeps it full: each cycle its Decoder
//     decides the next sphere or holds, its PSI takes a sphere or stalls,
//     and its Sphere FIFO, which takes every sphere broadcast and stops the
//     stream when full, does not run dry. Its front end is then counted,
//     not ticked, while the links, the shared side and its coast's pops are
//     stepped; its blocks are brought up to date at the end. While it holds
//     with a full Sphere FIFO (the stream stopped), or holds while its
//     Sphere FIFO fills and the shared side streams steadily, the cycles up
//     to its next pop are skipped in one step.
// The equivalence with the netlist (every block stepped every cycle) is checked in CI on a grid of
// scenes, ICC counts, FIFO depths and policies (tests/equivalence_modes.py).
#include <algorithm>
#include <limits>

#include "raplas/core/bits.hpp"
#include "top.hpp"

namespace raplas::model {

namespace {

// An ICC's records of the event mode (each described where run_pass_event
// uses it: 4. coasts, the selections' tally, 5. the lazy Decoder, the
// cursor over its kept spheres). A selection and the Decoder's hand-overs
// read them together: one array of them, two cache lines per ICC, instead of
// an array each.
struct Coast {
    std::uint32_t pos = 0;    // the link position up to which it has taken its triangles
    std::uint32_t next = 0;   // the triangle it selects next, in `waiting`: it takes those before it
    std::uint32_t count = 0;  // the triangles it takes: those of its entries from its start up to `next`
    std::uint64_t pop0 = 0;   // the pop cycle of the triangle that began the coast
    bool on = false;
};
struct Tally {
    std::uint32_t selected = 0, triangles = 0, empty = 0, max_occupancy = 0;
};
struct Lazy {
    std::uint32_t end = 0;
    std::uint32_t vn = 0;  // the kept spheres queued behind its FIFOs' entries, not stored (5.)
    bool on = false;
    bool has = false;  // its cursor holds a sphere not pushed yet
};
struct alignas(64) Record {
    Tally tally;
    Lazy lazy;
    Coast coast;
    KeptSpheres kept;
};
static_assert(sizeof(Record) <= 128, "an ICC's record in two cache lines");

// One field of every record, indexed by ICC.
template <auto Field>
struct Column {
    Record* base;
    auto& operator[](std::size_t k) const { return base[k].*Field; }
};

}  // namespace

void Top::start_shared_side(std::uint32_t n) {
    ref_fifo_->clear();
    ref_psi_->start_group(2 * n, &no_hits_);
    ref_decoder_->start_group();
}

void Top::tick_shared_side(bool spheres_pending) {
    ref_decoder_->tick(*ref_psi_, *ref_planeid_, *ref_first_tri_, SphereInfo{&sphere_memory});
    ref_psi_->tick(*ref_fifo_, false, spheres_pending || !ref_fifo_->empty());
}

std::uint64_t Top::run_pass_event(const Host::Pass& p, std::uint8_t buf) {
    enum Role : std::uint8_t { ref, individual };
    std::vector<Icc*> active;
    for (std::size_t k = 0; k < iccs.size(); ++k) {
        const std::uint32_t gi = p.begin + std::uint32_t(k);
        const TraceGroup* g = gi < p.end ? &groups_.group(gi) : nullptr;
        iccs[k].start_pass(g, buf, cfg_.overlap_passes);
        if (g) active.push_back(&iccs[k]);
    }
    const std::size_t na = active.size();
    sphere_link.start_pass(sphere_memory.size());
    triangle_link.start_pass(triangle_memory.size());
    const SphereInfo info{&sphere_memory};
    const std::uint32_t n = active.empty() ? 1 : active[0]->group()->n;

    // The shared sphere side.
    SphereFifo& rf = *ref_fifo_;
    PlaneSphereIntersector& rp = *ref_psi_;
    Decoder& rd = *ref_decoder_;
    start_shared_side(n);
    const std::uint64_t rf_pushes0 = rf.stats().pushes;
    const std::uint64_t rp_starved0 = rp.stats().starved_cycles;
    std::uint64_t ref_max = 0;
    std::uint64_t lazy_sphere_blocked = 0, lazy_undecided = 0;
    const std::uint32_t stages = cfg_.icc.psi.stages;
    const std::uint32_t rti_pipes = cfg_.icc.rti.pipes, rti_stages = cfg_.icc.rti.stages;
    const std::uint32_t tri_depth = cfg_.icc.triangle_fifo.depth;
    const std::uint32_t rdf_empty = cfg_.icc.fetcher.empty_cycles;
    const bool any_full = cfg_.icc.selector.policy == StallPolicy::any_full;
    const bool computes = functional_.mode() == FunctionalMode::compute;  // else the trace gives the hits

    std::vector<Role> role(na, ref);
    std::size_t n_ref = na;
    // Spheres every ICC's Decoder queues, in sphere order (used for the
    // reference ICCs): its hit spheres and, under icc.triangle_select = any,
    // its pair-less spheres (masks 0: their triangles give no pair). Each
    // ICC's are read through a cursor over its two lists; `kept_at` finds the
    // ICCs by their next kept sphere.
    const bool keep_pairless = cfg_.icc.decoder.select == TriangleSelect::any;
    // ICC k's records (Record, at the top of this file), one array of them.
    std::vector<Record> records(na);
    const Column<&Record::kept> kept{records.data()};
    const Column<&Record::coast> coast{records.data()};
    const Column<&Record::tally> tally{records.data()};
    const Column<&Record::lazy> lazy{records.data()};
    BucketQueue& kept_at = kept_queue_;
    kept_at.reset(sphere_memory.size(), na);
    for (std::uint32_t k = 0; k < na; ++k) {
        kept[k] = KeptSpheres(active[k]->unit().sphere_hits(), keep_pairless ? &active[k]->unit().pairless() : nullptr);
        records[k].lazy.has = kept[k].next();  // (the cursor holds its next kept sphere)
        if (records[k].lazy.has) kept_at.push(kept[k].sphere, k);
    }
    // ICCs waiting for the triangle stream to reach their head sphere, by its first triangle.
    BucketQueue& waiting = wait_queue_;
    waiting.reset(triangle_memory.size(), na);
    std::vector<std::uint32_t> selecting, individuals, full_now, diverged;
    // ICC k is in `waiting` for a kept sphere a cruise (7.) has still to
    // queue: the path that queues it into its empty FIFOs does not add it again.
    std::vector<std::uint8_t> wait_ahead(na, 0);
    auto wait_for = [&](std::uint32_t k, std::uint32_t tri) {
        if (wait_ahead[k]) return;
        waiting.push(tri, k);
    };
    // ... in `waiting` for the first triangle of sphere x, which its cruise has still to queue.
    auto wait_ahead_for = [&](std::uint32_t k, std::uint32_t x) {
        wait_for(k, info.first_tri(x));
        wait_ahead[k] = 1;
    };
    // The triangle stream's sends in this pass, as runs in consecutive
    // cycles (first position, its cycle): the cycle a triangle was sent.
    std::vector<std::pair<std::uint32_t, std::uint64_t>> sent_runs;
    auto note_sent = [&](std::uint64_t pos, std::uint64_t c) {
        if (sent_runs.empty() || c - sent_runs.back().second != pos - sent_runs.back().first)
            sent_runs.push_back({std::uint32_t(pos), c});
    };
    auto sent_cycle = [&](std::uint32_t pos) {
        auto r = sent_runs.end() - 1;  // (mostly a recent send: the last runs first)
        for (int i = 0; i < 4 && r->first > pos; ++i) --r;
        if (r->first > pos)
            r = std::upper_bound(sent_runs.begin(), r, pos, [](std::uint32_t x, const auto& e) { return x < e.first; }) - 1;
        return r->second + (pos - r->first);
    };
    // The Triangle FIFOs' holds on the triangle stream (TriangleSelector::hold):
    // ICC k's FIFO stops the link in cycles `from` to `until`. A hold is up
    // at the start of the cycles from the one after the push that raised it
    // (occupancy hold_at) to the pop that brings the FIFO to resume_at, and
    // reaches the link stall_latency cycles later (from the pass's first
    // cycle, for a hold up then). With the plain hold (full, no latency) it
    // is "full from the next cycle until the Fetcher pops the head". A push
    // while the hold is up moves its end; a later hold of the same ICC is
    // another entry, and `hold_of[k]` is the index of its last.
    struct Hold {
        std::uint32_t k;
        std::uint64_t from, until;
    };
    std::vector<Hold> holds;
    const std::uint64_t hold_at = cfg_.icc.selector.hold_at(tri_depth);
    const std::uint64_t resume_at = cfg_.icc.selector.resume_at(tri_depth);
    const std::uint64_t stall_latency = cfg_.icc.selector.stall_latency;
    constexpr std::uint32_t kNoHold = ~std::uint32_t(0);
    std::vector<std::uint32_t> hold_of(na, kNoHold);
    // Back end of every ICC (EventBack, top.hpp): empty at the start of a
    // pass, or with overlapped passes what the previous pass left, in this
    // pass's cycles.
    using Back = EventBack;
    std::vector<Back>& back = event_back_;
    if (!cfg_.overlap_passes || back.size() != iccs.size()) back.assign(iccs.size(), Back{});
    constexpr std::uint64_t kNever = ~std::uint64_t(0);
    constexpr std::uint32_t kMinCruise = 8;  // a cruise shorter than this is stepped
    std::vector<std::uint8_t> is_full(na, 0);
    // The last busy cycle of the previous pass's work (the pass cannot end
    // before it under overlap), and of all work.
    std::uint64_t prev_done = 0;
    for (const Back& b : back) prev_done = std::max(prev_done, b.done);
    std::uint64_t max_done = prev_done;
    // The last link cycle a hold reaches, its FIFO holding the entries
    // that pop in `starts` (more than resume_at of them): the pop that
    // leaves resume_at, stall_latency cycles on.
    auto hold_end = [&](const RingQueue& starts) {
        const std::uint64_t until = starts[std::size_t(starts.size() - resume_at - 1)];
        return until == kNever ? kNever : until + stall_latency;
    };
    // A hold raised by ICC k's push in cycle c (its FIFO then holding the
    // entries that pop in `starts`), or moved on by it.
    auto after_push = [&](std::uint32_t k, std::uint64_t c, const RingQueue& starts) {
        const std::uint64_t size = starts.size();
        const std::uint32_t h = hold_of[k];
        const bool up = h != kNoHold && holds[h].until >= c + stall_latency;  // (up at the start of cycle c)
        if (size < hold_at && !(up && size > resume_at)) return;
        const std::uint64_t end = hold_end(starts);
        if (up) {
            holds[h].until = end;
        } else {
            hold_of[k] = std::uint32_t(holds.size());
            holds.push_back({k, c + 1 + stall_latency, end});
        }
    };
    for (std::uint32_t k = 0; k < na; ++k)
        if (back[k].starts.size() >= hold_at) {  // held by the previous pass's triangles
            hold_of[k] = std::uint32_t(holds.size());
            holds.push_back({k, 0, hold_end(back[k].starts)});
            is_full[k] = 1;
            full_now.push_back(k);
        }

    // The shared side's counters when each ICC last joined it (at the start
    // of the pass, or when it rejoined): what it owes that ICC is the difference.
    struct Joined {
        std::uint64_t pushes, sphere_blocked, undecided, starved;
    };
    auto joined_now = [&] {
        return Joined{rf.stats().pushes, lazy_sphere_blocked, lazy_undecided, rp.stats().starved_cycles};
    };
    std::vector<Joined> joined(na, Joined{rf_pushes0, 0, 0, rp_starved0});
    auto adopt_reference = [&](std::size_t k) {
        Icc& c = *active[k];
        const Joined& j = joined[k];
        c.sphere_fifo.adopt(rf, rf.stats().pushes - j.pushes, ref_max);
        c.psi.adopt(rp);
        c.decoder.set_decided(rd.decided());
        c.note_sphere_blocked(lazy_sphere_blocked - j.sphere_blocked);
        c.triangle_selector.add_blocked_undecided(lazy_undecided - j.undecided);
        c.psi.add_starved(rp.stats().starved_cycles - j.starved);
    };
    // An individual ICC whose sphere side has run dry (Sphere FIFO empty,
    // nothing in the PSI, every sphere received decided) is in the state the
    // shared side is in when that has run dry too: it rejoins it, and is
    // stepped with it again until its Decoder holds next.
    // With no ICC on it, the shared side is read only when an ICC may
    // rejoin, once that ICC's own sphere side has run dry. With one batch
    // per sphere the shared side, never held, is a delay line that takes the
    // spheres broadcast when that ICC's Sphere FIFO does and decides each no
    // later: it has run dry by then too, every sphere broadcast decided. It
    // is therefore left "off" (not ticked) while no ICC is on it, and set so
    // when an ICC's own side runs dry. (What it counts meanwhile is owed to
    // no ICC: an ICC is owed what it counts from its (re)joining on.)
    const bool may_leave_shared = cfg_.fault == Fault::none && rp.batches() == 1;
    bool shared_off = false;
    auto may_rejoin = [&](std::uint32_t k) {
        const Icc& c = *active[k];
        if (!(c.sphere_fifo.empty() && c.psi.drained() && !c.psi.stuck())) return false;
        if (shared_off) {
            const std::uint32_t broadcast = std::uint32_t(sphere_link.position());
            rf.clear();
            rp.set_drained(broadcast);
            rd.set_decided(broadcast);
            shared_off = false;
        }
        return rf.empty() && rp.drained() && c.decoder.decided() == rd.decided();
    };

    // Coasting (4. in the header): ICC k takes the triangles of its queued
    // pair-less spheres after the one that began the coast and before
    // `next` without being touched (`count` of them: the spheres need not
    // follow one another), and selects as usual the triangle it waits for in
    // `waiting`, `next`: the last queued pair-less sphere's last triangle
    // or, when a sphere with pairs is queued behind them, that sphere's
    // first triangle (the coast then takes every pair-less one before it).
    // Each coasted triangle holds the Fetcher one cycle, so the j-th is
    // popped in cycle max(pop0 + j, c_i + 1 + j - i for i <= j), pop0 the
    // pop cycle of the triangle that began the coast and c_i the cycle the
    // i-th is broadcast. The coasted triangles are broadcast in distinct
    // cycles, in order, before the next selection's cycle c, so every
    // c_i + 1 + j - i is at most c: the pops after c are pop0 + j, whatever
    // the gaps between the spheres and the stalls of the stream. The coast
    // is cut where the Triangle FIFO could fill or exceed its largest
    // occupancy so far, so every figure of
    // the Selector, FIFO and Fetcher is a count, and the Fetcher's record is
    // rebuilt when the next triangle is selected (end_coast). Its PlaneID
    // and First-Triangle-ID FIFOs are popped when someone reads them
    // (catch_up): the Decoder, and the ICC's own sphere side while it is
    // individual.
    // (coast[k]: the Coast of ICC k's Record, at the top of this file)
    // What the selections add to the Triangle Selector's, Triangle FIFO's and
    // Fetcher's counters, per ICC, settled at the end of the pass (or when the
    // watchdog looks): one small record per selection instead of three
    // blocks' counters. Every selected triangle is pushed into the Triangle
    // FIFO, so `selected` counts its pushes too; `max_occupancy` starts at
    // the FIFO's.
    // (tally[k]: the Tally of ICC k's Record, at the top of this file)
    for (std::uint32_t k = 0; k < na; ++k)
        tally[k].max_occupancy = std::uint32_t(active[k]->triangle_fifo.stats().max_occupancy);
    auto settle_tallies = [&] {
        for (std::uint32_t k = 0; k < na; ++k) {
            Tally& t = tally[k];
            Icc& icc = *active[k];
            icc.triangle_selector.add_selected(t.selected);
            icc.triangle_fifo.record_push(t.max_occupancy, t.selected);
            icc.ray_data_fetcher.note_triangles(t.triangles, t.empty);
            t = Tally{0, 0, 0, t.max_occupancy};
        }
    };
    auto note_occupancy = [&](Tally& t, std::size_t occupancy) {
        t.max_occupancy = std::max(t.max_occupancy, std::uint32_t(occupancy));
    };
    const bool may_coast = keep_pairless && rdf_empty <= 1 && hold_at >= 2 && cfg_.fault == Fault::none;
    // Coasting ICC k is about to select its next triangle in cycle c:
    // its Fetcher record as the coasted triangles left it. Of the j-th of
    // them (j = 1..L) only a pop in cycle pop0 + j can come after cycle c
    // (above): those still in the FIFO in cycle c are the ones with
    // pop0 + j > c, and the last is popped in pop0 + L or by cycle c, which
    // the next selection's slot treats alike.
    auto end_coast = [&](std::uint32_t k, std::uint64_t c) {
        Coast& co = coast[k];
        Back& b = back[k];
        const std::uint64_t L = co.count;
        for (std::uint64_t j = c >= co.pop0 ? c - co.pop0 + 1 : 1; j <= L; ++j) b.starts.push_back(co.pop0 + j);
        b.next_cyc = co.pop0 + L;
        b.next_used = rdf_empty ? rti_pipes : 0;  // (0: the next slot is free after it)
        b.any = true;
        b.done = std::max(b.done, b.next_cyc);
        co.on = false;
    };
    // Lazy Decoder (5. in the header): reference ICC k queues its kept
    // spheres from its cursor on, each in the cycle the shared side decides
    // it, without being touched: they are pushed when someone reads its FIFOs
    // (push_lazy), and it is in `kept_at` only at `end`, the last sphere up
    // to which it cannot queue more than keep its FIFOs from filling or
    // passing their largest occupancy so far. The order of these pushes and
    // the pops between them then changes no figure.
    // (lazy[k]: the Lazy of ICC k's Record, at the top of this file)
    const bool may_lazy = any_full && cfg_.fault == Fault::none;
    // A reference ICC's FIFOs (with may_lazy) are its stored entries
    // followed by `vn` kept spheres in order from the cursor `vhead[k]`,
    // queued but not stored: pushes move the cursor `kept[k]`, a coast's
    // pops move `vhead[k]`, by runs of pair-less spheres, and only the entry
    // a selection reads is stored (head_in_fifo). Its figures are recorded
    // as the pushes are made.
    std::vector<KeptSpheres> vhead(na);
    auto occupancy_of = [&](std::uint32_t k) { return active[k]->planeid_fifo.size() + lazy[k].vn; };
    // ICC k's first unstored entry stored, behind the stored ones.
    auto store_one = [&](std::uint32_t k) {
        Icc& c = *active[k];
        KeptSpheres& h = vhead[k];
        c.planeid_fifo.place({h.rows, h.cols});
        c.first_tri_fifo.place(info.entry(h.sphere));
        if (--lazy[k].vn) h.next();
    };
    // ... when it has none stored: a selection reads its head entry.
    auto head_in_fifo = [&](std::uint32_t k) {
        if (lazy[k].vn && active[k]->first_tri_fifo.empty()) store_one(k);
    };
    // ... all of them (the blocks read them: an ICC on its own, the watchdog).
    auto store_all = [&](std::uint32_t k) {
        while (lazy[k].vn) store_one(k);
    };
    // ICC k's Decoder queues its kept spheres from its cursor below `upto`
    // (decided by now): the cursor moves past them, a run of pair-less ones
    // at a time, `each(e, run)` seeing each sphere e.sphere with the `run` of
    // its run after it before it moves on. Returns how many.
    auto queue_from_cursor = [&](std::uint32_t k, std::uint32_t upto, auto&& each) -> std::uint64_t {
        Lazy& z = lazy[k];
        KeptSpheres& e = kept[k];
        if (!z.has || e.sphere >= upto) return 0;
        std::uint64_t pairs = 0, pairless = 0;
        do {
            const std::uint32_t run = std::min(e.run_left(), upto - e.sphere - 1);
            each(e, run);
            if (e.rows && e.cols) ++pairs;
            else pairless += run + 1;
            if (run) e.skip(run);
            z.has = e.next();
        } while (z.has && e.sphere < upto);
        Decoder& d = active[k]->decoder;
        d.note_hit(false, pairs);
        d.note_hit(true, pairless);
        return pairs + pairless;
    };
    // Pushes ICC k's lazy spheres below `upto`: unstored for a reference ICC,
    // else into its FIFOs.
    auto push_lazy = [&](std::uint32_t k, std::uint32_t upto) {
        Icc& c = *active[k];
        if (may_lazy && role[k] == ref) {
            bool first = lazy[k].vn == 0;
            const std::uint64_t n = queue_from_cursor(k, upto, [&](const KeptSpheres& e, std::uint32_t) {
                if (first) vhead[k] = e;
                first = false;
            });
            if (n == 0) return;
            lazy[k].vn += std::uint32_t(n);
            const std::uint32_t occupancy = occupancy_of(k);
            c.planeid_fifo.record_push(occupancy, n);
            c.first_tri_fifo.record_push(occupancy, n);
            return;
        }
        queue_from_cursor(k, upto, [&](const KeptSpheres& e, std::uint32_t run) {
            for (std::uint32_t y = e.sphere; y <= e.sphere + run; ++y) {
                c.planeid_fifo.push({e.rows, e.cols});
                c.first_tri_fifo.push(info.entry(y));
            }
        });
    };
    // A cruise that queues kept spheres (7.): ICC k, individual, decides
    // sphere d0 + i in cycle c0 + i and queues the kept ones from its cursor
    // (kept[k], lazy[k].has) without being touched; they are pushed when its
    // FIFOs are read, each before the pops of later cycles, so that the
    // FIFOs' largest occupancy is as the cycle-by-cycle steps leave it.
    struct Ahead {
        bool on = false;
        std::uint32_t d0 = 0;
        std::uint64_t c0 = 0;
    };
    std::vector<Ahead> ahead(na);
    // Pushes the kept spheres ICC k decided before cycle c.
    auto push_ahead = [&](std::uint32_t k, std::uint64_t c) {
        const Ahead& a = ahead[k];
        if (a.on) push_lazy(k, c <= a.c0 ? a.d0 : std::uint32_t(a.d0 + (c - a.c0)));
    };
    // Coasting ICC k takes the triangles from `pos` on below `upto` of its
    // unstored entries (its stored ones are gone), and pops the entries whose
    // last triangle is among them. Returns how many it takes. (A run of
    // consecutive spheres holds consecutive triangles.)
    auto take_unstored = [&](std::uint32_t k, std::uint32_t upto, std::uint32_t pos) {
        Lazy& z = lazy[k];
        KeptSpheres& h = vhead[k];
        std::uint32_t taken = 0;
        while (z.vn) {
            const std::uint32_t y = h.sphere, r = std::min(h.run_left(), z.vn - 1), last = y + r;
            const std::uint32_t first = info.first_tri(y), end = info.first_tri(last) + info.tri_count(last);
            const std::uint32_t from = std::max(first, pos), to = std::min(end, upto);
            if (to > from) taken += to - from;
            // (the spheres of y..last that end by `upto`: those before the one that holds triangle `upto`)
            const std::uint32_t popped = end <= upto ? r + 1 : upto > first ? triangle_memory.sphere_of(upto) - y : 0;
            if (popped == 0) break;
            z.vn -= popped;
            if (popped <= r) {  // (the rest of the run ends past `upto`)
                if (popped > 1) h.skip(popped - 1);
                h.next();
                break;
            }
            if (z.vn == 0) break;
            if (r) h.skip(r);
            h.next();
        }
        return taken;
    };
    // Coasting ICC k has taken every triangle of its entries below `upto`
    // (the link's position): those from `pos` on are counted, and the
    // entries whose last triangle is among them popped. (Every sphere with a
    // triangle below `upto` is decided, and so queued by now.)
    auto catch_up = [&](std::uint32_t k, std::uint32_t upto) {
        Coast& co = coast[k];
        upto = std::min(upto, co.next);
        if (upto <= co.pos) return;
        if (lazy[k].on) push_lazy(k, rd.decided());  // (a coast may take spheres not queued when it began)
        Icc& icc = *active[k];
        Fifo<FirstTriEntry>& f = icc.first_tri_fifo;
        std::uint32_t taken = 0;
        for (;;) {  // (the entry of `next` stays: it ends past `upto`)
            if (f.empty() && lazy[k].vn) {  // the unstored ones, by runs of consecutive spheres
                taken += take_unstored(k, upto, co.pos);
                break;
            }
            if (f.empty()) {  // (a coast begun on the shared side takes spheres a cruise has still to queue)
                if (!ahead[k].on || !lazy[k].has || info.first_tri(kept[k].sphere) >= upto) break;
                push_lazy(k, kept[k].sphere + 1);
            }
            const FirstTriEntry& e = f.front();
            const std::uint32_t from = std::max(e.first, co.pos), end = e.first + e.count;
            if (end > upto) {
                if (upto > from) taken += upto - from;
                break;
            }
            if (end > from) taken += end - from;
            if (ahead[k].on) push_ahead(k, sent_cycle(end - 1));  // (what it queued before that pop's cycle)
            f.pop();
            icc.planeid_fifo.pop();
        }
        Tally& t = tally[k];
        t.selected += taken;  // (each finds at most its quiet limit in the FIFO: select's cut)
        t.triangles += taken;
        t.empty += taken;
        co.pos = upto;
    };
    // Reference ICC k, its FIFOs as they are after sphere x was decided: lazy
    // up to the sphere its room allows, if it has room and spheres left, else
    // back in `kept_at` at its next kept sphere. (The caller has moved its
    // cursor past x.)
    constexpr std::uint64_t kScan = 32;
    auto arm_lazy = [&](std::uint32_t k, std::uint32_t x) {
        Lazy& z = lazy[k];
        const Icc& c = *active[k];
        const std::uint64_t most = c.planeid_fifo.quiet_limit(), occupancy = occupancy_of(k);
        z.on = z.has && most > occupancy;
        if (!z.on) {
            if (z.has) kept_at.push(kept[k].sphere, k);  // (its FIFOs are not empty)
            return;
        }
        // At most `room` spheres are queued from x + 1 to `end` when there
        // are at most that many spheres, or when there are at most that many
        // of its kept ones: the farther of the two (its kept spheres counted
        // up to kScan; with nearly full FIFOs the first alone would end the
        // span at the next sphere).
        const std::uint64_t room = most - occupancy, counted = std::min<std::uint64_t>(room, kScan);
        KeptSpheres ahead = kept[k];  // (at its first lazy sphere)
        bool more = true;
        std::uint64_t last = ahead.sphere;  // the counted-th, when there is one
        for (std::uint64_t i = 1; i < counted && more;) {
            const std::uint64_t run = ahead.run_left();  // (its spheres follow one another)
            if (run >= counted - i) {
                last = ahead.sphere + (counted - i);
                break;
            }
            if (run) ahead.skip(std::uint32_t(run));
            i += run;
            more = ahead.next();
            last = ahead.sphere;
            ++i;
        }
        const std::uint64_t end = more ? std::max<std::uint64_t>(std::uint64_t(x) + room, last) : sphere_memory.size();
        z.end = std::uint32_t(std::min<std::uint64_t>(end, sphere_memory.size()));
        if (z.end < sphere_memory.size()) kept_at.push(z.end, k);
    };
    // Dozing (6. in the header): individual ICC k whose Decoder holds (its
    // PlaneID or First-Triangle-ID FIFO full) changes nothing but counts
    // until a selection pops that FIFO: its Sphere FIFO takes every sphere
    // broadcast until it is full, and then stops the sphere stream. (Its
    // decisions stop too, but the triangle stream cannot reach its next
    // undecided sphere meanwhile: the head entry of its full FIFOs is a
    // decided sphere whose last triangle is still to be selected.) It
    // leaves `individuals`; the links see it through two bounds (the sphere
    // link position at which a dozer's Sphere FIFO fills, the smallest
    // decision count), and its counts are settled when it wakes, when the
    // watchdog looks, and at the end of the pass.
    struct Doze {
        std::uint64_t from = 0;           // the first cycle not yet counted
        std::uint64_t spos = 0;           // the sphere link's position at the start of cycle `from`
        std::uint64_t fill_pos = 0;       // the sphere link's position at which its Sphere FIFO is full
        std::uint64_t full_from = kNever; // from this cycle on it stops the sphere stream
        bool s_has_full = false;          // ... which has a record then
        bool planeid_full = false, first_tri_full = false;  // which of its FIFOs holds its Decoder
    };
    std::vector<Doze> doze(na);
    std::vector<std::uint8_t> dozing(na, 0);
    std::vector<std::uint32_t> dozers;
    std::uint32_t dozers_full = 0, doze_decided = ~std::uint32_t(0);
    std::uint64_t doze_fill = kNever;
    const bool may_doze = cfg_.fault == Fault::none;
    auto doze_bounds = [&] {
        doze_decided = ~std::uint32_t(0);
        doze_fill = kNever;
        for (std::uint32_t k : dozers) {
            const Doze& z = doze[k];
            doze_decided = std::min(doze_decided, active[k]->decoder.decided());
            if (z.full_from == kNever) doze_fill = std::min(doze_fill, z.fill_pos);
        }
    };
    // Counts dozing ICC k's cycles: held and taking spheres up to cycle
    // `held_end` (the sphere link then at `spos`), stopping the sphere
    // stream in the link decisions of the cycles before `link_end`.
    auto settle = [&](std::uint32_t k, std::uint64_t held_end, std::uint64_t link_end, std::uint64_t spos) {
        Doze& z = doze[k];
        Icc& c = *active[k];
        if (held_end > z.from) {  // (its FIFOs were as full as when it began to doze: a wake comes after the pop)
            const std::uint64_t h = held_end - z.from;
            c.decoder.note_held(h);
            if (z.planeid_full) c.planeid_fifo.note_full(h);
            if (z.first_tri_full) c.first_tri_fifo.note_full(h);
            c.psi.add_stalled(h);
        }
        c.sphere_fifo.push_run(std::uint32_t(z.spos), std::uint32_t(spos - z.spos));
        if (z.full_from != kNever) {
            if (z.s_has_full && link_end > z.full_from) c.note_sphere_blocked(link_end - z.full_from);
            z.full_from = std::max(z.full_from, link_end);
        }
        z.from = held_end;
        z.spos = spos;
    };
    // A dozing ICC that coasts wakes when its coast takes the last triangle
    // of its FIFOs' head entry (when that comes before the coast's end): it
    // is in `coast_pops` at that triangle. (The queue holds an ICC once: an
    // entry it has left behind is moved on to the triangle it waits for now
    // when it comes up, or dropped.)
    BucketQueue& coast_pops = coast_pop_queue_;
    coast_pops.reset(triangle_memory.size(), na);
    constexpr std::uint32_t kNoPop = ~std::uint32_t(0);
    std::vector<std::uint32_t> pop_wanted(na, kNoPop);
    std::vector<std::uint8_t> in_pops(na, 0);
    auto wait_coast_pop = [&](std::uint32_t k) {
        const Coast& co = coast[k];
        const Fifo<FirstTriEntry>& f = active[k]->first_tri_fifo;
        pop_wanted[k] = kNoPop;
        if (!co.on || f.empty() || f.front().first + f.front().count > co.next) return;
        pop_wanted[k] = f.front().first + f.front().count - 1;
        if (!in_pops[k]) {
            coast_pops.push(pop_wanted[k], k);
            in_pops[k] = 1;
        }
    };
    // ICC k, individual, after its step in cycle c, holds: it dozes from cycle c + 1.
    auto start_doze = [&](std::uint32_t k, std::uint64_t c) {
        const Icc& icc = *active[k];
        Doze z;
        z.from = c + 1;
        z.spos = sphere_link.position();
        z.fill_pos = z.spos + (icc.sphere_fifo.depth() - icc.sphere_fifo.size());
        z.planeid_full = icc.planeid_fifo.full();
        z.first_tri_full = icc.first_tri_fifo.full();
        if (z.fill_pos == z.spos) {
            z.full_from = c + 1;
            z.s_has_full = sphere_link.has_record();
            ++dozers_full;
        }
        doze[k] = z;
        dozing[k] = 1;
        dozers.push_back(k);
        doze_bounds();
        wait_coast_pop(k);
    };
    // Dozing ICC k wakes in cycle c, after the link decisions (its FIFOs
    // popped by a selection); `s`: the sphere broadcast in c (-1: none),
    // which its own step takes.
    auto wake = [&](std::uint32_t k, std::uint64_t c, std::int64_t s) {
        settle(k, c, c + 1, sphere_link.position() - (s >= 0 ? 1 : 0));
        if (doze[k].full_from != kNever) --dozers_full;
        dozing[k] = 0;
        pop_wanted[k] = kNoPop;
        dozers.erase(std::find(dozers.begin(), dozers.end(), k));
        individuals.push_back(k);
        doze_bounds();
    };

    // Cruising (7. in the header): individual ICC k whose PSI streams on its
    // own (one batch per sphere, a full pipe, free to issue, its Sphere FIFO
    // neither empty nor full) decides one sphere a cycle for as long as its
    // Sphere FIFO does not run dry, which it does once the sphere stream has
    // been idle or stalled in as many cycles as the FIFO held at the start
    // (it takes one sphere a cycle and receives every sphere broadcast). Up
    // to the cycle its next queued sphere leaves the pipe, nothing but its
    // decision count and positions changes; the links see it through that
    // count, and it is brought up to date (and stepped again) then, when its
    // FIFO runs dry, when the watchdog looks, and at the end of the pass.
    struct Cruise {
        std::uint64_t c0 = 0;    // its first cruising cycle
        std::uint32_t d0 = 0;    // its decision count then
        std::uint32_t count0 = 0;  // its Sphere FIFO's occupancy then
        std::uint64_t spos0 = 0; // the sphere link's position then
        std::uint64_t nb0 = 0;   // cycles without a sphere broadcast before it
        std::uint64_t end = 0;   // the cycle its next queued sphere leaves the pipe
    };
    std::vector<Cruise> cruise(na);
    std::vector<std::uint8_t> cruising(na, 0);
    std::vector<std::uint32_t> cruisers;
    std::uint64_t no_sphere_cycles = 0;  // cycles of the pass without a sphere broadcast
    std::uint64_t cruise_end = kNever, cruise_dry = kNever;
    std::int64_t cruise_offset = std::numeric_limits<std::int64_t>::max();  // decisions - cycle, smallest
    const bool may_cruise = cfg_.fault == Fault::none && cfg_.icc.psi.pipes >= 2 * n;
    auto cruise_bounds = [&] {
        cruise_end = cruise_dry = kNever;
        cruise_offset = std::numeric_limits<std::int64_t>::max();
        for (std::uint32_t k : cruisers) {
            const Cruise& z = cruise[k];
            cruise_end = std::min(cruise_end, z.end);
            cruise_dry = std::min(cruise_dry, z.nb0 + z.count0);
            cruise_offset = std::min(cruise_offset, std::int64_t(z.d0) - std::int64_t(z.c0));
        }
    };
    auto cruise_decided = [&](std::uint32_t k, std::uint64_t c) { return std::uint32_t(cruise[k].d0 + (c - cruise[k].c0)); };
    // The first sphere from `from` on that ICC k's Decoder queues (the sphere
    // count if none). An ICC that cannot cruise asks again a cycle later, a
    // sphere or so on (its decision count only grows in a pass): a cursor per
    // ICC over its two lists moves forward to the answer, and the answer x
    // stands for every `from` up to x.
    struct Queued {
        const std::vector<SphereHitRec>* hits = nullptr;
        const std::vector<SphereRun>* runs = nullptr;
        std::uint32_t from = 0, at = 0;
        std::size_t hit = 0, run = 0;
        bool known = false;  // `at` is the answer for `from`
    };
    std::vector<Queued> queued(na);
    for (std::uint32_t k = 0; k < na; ++k) {
        queued[k].hits = &active[k]->unit().sphere_hits();
        queued[k].runs = &active[k]->unit().pairless();
    }
    auto next_queued = [&](std::uint32_t k, std::uint32_t from) {
        Queued& q = queued[k];
        if (q.known && q.from <= from && from <= q.at) return q.at;
        if (from < q.from) q = Queued{q.hits, q.runs};  // (never in the normal course)
        const auto& hits = *q.hits;
        const auto& runs = *q.runs;
        while (q.hit < hits.size() && hits[q.hit].sphere < from) ++q.hit;
        std::uint32_t x = q.hit == hits.size() ? std::uint32_t(sphere_memory.size()) : hits[q.hit].sphere;
        if (keep_pairless) {
            while (q.run < runs.size() && runs[q.run].end() <= from) ++q.run;
            if (q.run < runs.size()) x = std::min(x, std::max(runs[q.run].first, from));
        }
        q.from = from;
        q.at = x;
        q.known = true;
        return x;
    };
    // The kept sphere of ICC k after the first `count` from sphere `from` on
    // (the sphere count if none); `at`: its cursor at `from`. (Not with
    // link.stall_policy = needed_full, whose link reads the FIFOs of an ICC
    // with a full Triangle FIFO.)
    const bool may_queue_ahead = cfg_.fault == Fault::none && any_full;
    constexpr std::uint32_t kAheadScan = 256;
    auto kept_after = [&](std::uint32_t k, std::uint32_t from, std::uint32_t count, KeptSpheres& at) {
        KeptSpheres e(*queued[k].hits, keep_pairless ? queued[k].runs : nullptr);
        e.seek(from);
        at = e;
        bool more = e.next();
        while (more && count) {  // (e.sphere is the next kept one)
            const std::uint32_t run = e.run_left();  // (the spheres of its run after it)
            if (run >= count) return e.sphere + count;
            count -= run + 1;
            if (run) e.skip(run);
            more = e.next();
        }
        return more ? e.sphere : std::uint32_t(sphere_memory.size());
    };
    // Cruising ICC k brought up to the start of cycle c (the sphere link now at its position then).
    auto land = [&](std::uint32_t k, std::uint64_t c) {
        const Cruise& z = cruise[k];
        Icc& icc = *active[k];
        const std::uint64_t m = c - z.c0;
        icc.psi.cruise(m);
        icc.sphere_fifo.cruise(std::uint32_t(m), std::uint32_t(sphere_link.position() - z.spos0));
        icc.decoder.set_decided(std::uint32_t(z.d0 + m));
        // (a coasting ICC's FIFOs are popped as the triangle stream passes, as
        // the per-cycle steps would have done by now: the skip reads them)
        if (coast[k].on) catch_up(k, std::uint32_t(triangle_link.position()));
        if (ahead[k].on) {
            push_ahead(k, c);
            ahead[k].on = false;
            lazy[k].has = false;
        }
        cruising[k] = 0;
        individuals.push_back(k);
    };
    auto land_all = [&](std::uint64_t c) {
        for (std::uint32_t k : cruisers) land(k, c);
        cruisers.clear();
        cruise_bounds();
    };
    auto decided_of = [&](std::size_t k, std::uint64_t c) {
        return role[k] == ref ? rd.decided() : cruising[k] ? cruise_decided(std::uint32_t(k), c) : active[k]->decoder.decided();
    };

    // Triangle tri (of the head sphere) selected by ICC k in cycle c. Returns
    // true if ICC k coasts from the next triangle on.
    const bool may_stick = cfg_.fault == Fault::stuck_rti;
    auto select = [&](std::uint32_t k, std::uint32_t tri, std::uint64_t c) {
        Icc& icc = *active[k];
        const PlaneIdEntry masks = TriangleSelector::take(tri, icc.planeid_fifo, icc.first_tri_fifo);
        Tally& tl = tally[k];
        ++tl.selected;
        Back& b = back[k];
        while (!b.starts.empty() && b.starts.front() <= c) b.starts.pop_front();  // popped by this cycle's Fetcher
        const std::uint64_t m =
            masks.rows && masks.cols ? std::uint64_t(bit_count(masks.rows)) * std::uint64_t(bit_count(masks.cols)) : 0;
        if (may_stick && icc.rti.stuck()) {  // fault injection: the Fetcher never pops this FIFO again
            b.starts.push_back(kNever);
            note_occupancy(tl, b.starts.size());
            after_push(k, c, b.starts);
            max_done = kNever;
            return false;
        }
        const FetcherQueue::Slot slot = b.take(c, m, rti_pipes, rti_stages, rdf_empty);
        const std::uint64_t start = slot.pop;
        if (m) icc.rti.account(m, 0, slot.busy);  // (a triangle with no pair: no test, no busy cycle)
        max_done = std::max(max_done, b.done);
        b.starts.push_back(start);
        note_occupancy(tl, b.starts.size());
        // Held from the next cycle until the Fetcher pops down to resume_at
        // (with the plain hold, a full FIFO takes no push, so nothing else
        // can change that).
        after_push(k, c, b.starts);
        // The RTI's tests, all at once: the nearest hit does not depend on their
        // order. (Made when the group was loaded, unless the ICC answers at
        // selection: Icc::answer_at_load.)
        if (m && computes && !icc.answered())
            icc.rti.account(0,
                            icc.unit().rti_tests(masks.rows, masks.cols, tri, n,
                                                 [&](std::uint32_t ray, double t) { icc.min_distance(buf).update(ray, t, tri); }),
                            0);
        ++tl.triangles;
        tl.empty += m == 0;
        if (!may_coast || m != 0) return false;
        // Cycles the Fetcher is still busy with older triangles, and the FIFO's occupancy.
        const std::uint64_t backlog = start - c - 1, occupancy = b.starts.size();
        if ((backlog || occupancy > 1) && rdf_empty != 1) return false;
        if (hold_of[k] != kNoHold && holds[hold_of[k]].until >= c + 1 + stall_latency) return false;  // held
        // The i-th triangle of a coast finds at most occupancy + min(i,
        // backlog) entries, itself included (older ones pop no later than
        // this one, and the Fetcher takes one of the coast's each cycle once
        // free). When no two entries in the FIFO pop in the same cycle it
        // finds at most backlog + 1: pushed in a cycle c_i >= c + i, it finds
        // the entries that pop after c_i up to its own pop, each in a cycle
        // of its own, and pops in start + i <= c_i + backlog + 1 (or, when
        // the Fetcher has run dry since the coast began, finds itself alone).
        // It must not fill the FIFO or raise its largest occupancy so far
        // (nor raise its hold). `limit`: the most triangles a coast may take so.
        const std::uint64_t most = std::min(Fifo<TriWork>::quiet_limit(tl.max_occupancy, tri_depth), hold_at - 1);
        if (occupancy > most) return false;
        const std::uint64_t reach = b.starts.ties() == 0 ? backlog + 1 : occupancy + backlog;
        const std::uint64_t limit = reach <= most ? ~std::uint64_t(0) : most - occupancy;
        // The pair-less triangles it has still to take from here, in order:
        // those of the spheres queued in its FIFOs and, for a reference ICC,
        // of the spheres it is to queue next (its lists), up to the first
        // sphere with pairs. `stretches(f)` calls f(from, end) for each run of
        // them while f returns true, and returns the first triangle of that
        // sphere with pairs (kNoTri: none, or not known to an ICC on its own,
        // whose FIFOs are not filled from the lists).
        constexpr std::uint32_t kNoTri = ~std::uint32_t(0);
        const Fifo<FirstTriEntry>& f = icc.first_tri_fifo;
        const Fifo<PlaneIdEntry>& pf = icc.planeid_fifo;
        auto stretches = [&](auto&& fn) {
            for (std::size_t i = 0; i < f.size(); ++i) {
                const FirstTriEntry& e = f.at(i);
                const PlaneIdEntry& pm = pf.at(i);
                if (pm.rows && pm.cols) return e.first;
                if (!fn(std::max(e.first, tri + 1), e.first + e.count)) return kNoTri;
            }
            if (role[k] != ref) return kNoTri;
            if (may_lazy) {  // its unstored entries, then the kept spheres it is still to queue: by cursors
                bool in_queue = lazy[k].vn > 0, more = in_queue || lazy[k].has;
                KeptSpheres e = in_queue ? vhead[k] : kept[k];
                std::uint32_t left = lazy[k].vn;  // (in its FIFOs, from e on)
                while (more) {
                    if (e.rows && e.cols) return info.first_tri(e.sphere);
                    const std::uint32_t r = in_queue ? std::min(e.run_left(), left - 1) : e.run_left(), last = e.sphere + r;
                    if (!fn(std::max(info.first_tri(e.sphere), tri + 1), info.first_tri(last) + info.tri_count(last)))
                        return kNoTri;
                    if (in_queue && (left -= r + 1) == 0) {
                        in_queue = false;
                        e = kept[k];
                        more = lazy[k].has;
                        continue;
                    }
                    if (r) e.skip(r);
                    more = e.next();
                }
                return kNoTri;
            }
            const std::uint32_t s0 = f.empty() ? triangle_memory.sphere_of(tri) + 1 : f.at(f.size() - 1).sphere + 1;
            const auto& hits = icc.unit().sphere_hits();
            const auto h = first_hit_from(hits, s0);
            const std::uint32_t paired = h == hits.end() ? ~std::uint32_t(0) : h->sphere;
            const auto& runs = icc.unit().pairless();
            for (auto r = first_run_from(runs, s0); r != runs.end() && r->first < paired; ++r) {
                const std::uint32_t last = r->end() - 1;
                if (!fn(info.first_tri(std::max(r->first, s0)), info.first_tri(last) + info.tri_count(last))) return kNoTri;
            }
            return paired == ~std::uint32_t(0) ? kNoTri : info.first_tri(paired);
        };
        std::uint64_t pairless = 0;  // (counted no further than `limit` is passed)
        const std::uint32_t paired = stretches([&](std::uint32_t from, std::uint32_t end) {
            pairless += end - from;
            return pairless <= limit;
        });
        // It takes them all and selects the sphere with pairs next, or all
        // but the last and selects that one; at most `limit` in either case,
        // the next one selected then.
        const bool behind = paired != kNoTri;
        const std::uint64_t take = std::min(behind ? pairless : pairless ? pairless - 1 : 0, limit);
        if (take == 0) return false;
        std::uint32_t next = paired;
        if (!(behind && take == pairless)) {  // the (take + 1)-th pair-less triangle
            std::uint64_t left = take;
            stretches([&](std::uint32_t from, std::uint32_t end) {
                if (left < end - from) {
                    next = from + std::uint32_t(left);
                    return false;
                }
                left -= end - from;
                return true;
            });
        }
        coast[k] = Coast{tri + 1, next, std::uint32_t(take), start, true};
        return true;
    };

    // Fault injection: a stuck PSI makes its ICC's sphere side its own from the start.
    if (cfg_.fault == Fault::stuck_psi && cfg_.fault_icc < na) {
        adopt_reference(cfg_.fault_icc);
        role[cfg_.fault_icc] = individual;
        --n_ref;
        individuals.push_back(cfg_.fault_icc);
    }

    // The watchdog's picture of the active ICCs at the start of cycle c.
    auto views = [&](std::uint64_t c) {
        settle_tallies();
        for (std::uint32_t k : dozers) settle(k, c, c, sphere_link.position());
        land_all(c);
        for (std::uint32_t k = 0; k < na; ++k) {
            if (lazy[k].on) push_lazy(k, rd.decided());
            if (coast[k].on) catch_up(k, std::uint32_t(triangle_link.position()));
            store_all(k);
        }
        std::vector<IccView> v;
        for (std::size_t k = 0; k < na; ++k) {
            const Icc& icc = *active[k];
            IccView w = view_of(icc, k);  // active[k] is iccs[k]
            if (role[k] == ref) {
                w.sphere_fifo = rf.size();
                w.decided = rd.decided();
            }
            const RingQueue& starts = back[k].starts;
            std::uint32_t in_fifo = 0;
            for (std::size_t i = 0; i < starts.size(); ++i) in_fifo += starts[i] >= c;
            w.triangle_fifo = in_fifo;
            w.back_busy = back[k].any && back[k].done >= c;
            v.push_back(w);
        }
        return v;
    };

    // `cycles` stalled cycles of the triangle stream: the ICCs whose full
    // (held) Triangle FIFO stopped it (`holds_link`), and the stall anatomy.
    auto note_held = [&](std::uint64_t cycles, auto&& holds_link) {
        std::uint32_t held = 0, by = 0;
        for (std::uint32_t k : full_now)
            if (holds_link(k)) {
                active[k]->triangle_selector.note_blocked_full(active[k]->triangle_fifo, cycles);
                ++held;
                by = k;
            }
        triangle_link.held(held, cycles);
        if (held == 1) active[by]->triangle_selector.note_alone(cycles);
    };

    std::uint64_t cycle = 0;
    // d skipped cycles of a finished sphere side: no sphere, every PSI idle.
    auto spheres_idle = [&](std::uint64_t d) {
        no_sphere_cycles += d;
        sphere_link.idle(d);
        rp.idle(d);
        for (std::uint32_t k : individuals) active[k]->psi.idle(d);
    };
    // d skipped cycles of a steady sphere stream on the shared side (a sphere in and a decision out each).
    auto spheres_stream = [&](std::uint64_t d) {
        sphere_memory.read_many(d);
        sphere_link.sent_many(d);
        if (shared_off) return;
        rp.fast_forward(d, rf.front());
        rf.advance(std::uint32_t(d));
        rd.set_decided(rd.decided() + std::uint32_t(d));
    };
    // Nothing is in the shared side (or it is off, and so read as dry when it is next read).
    auto shared_empty = [&] { return shared_off || (rf.empty() && rp.in_flight() == 0); };
    // The shared side streams steadily: a sphere in and a decision out each cycle while the stream sends one.
    auto shared_streams = [&] {
        return rp.batches() == 1 && rp.in_flight() == stages && rp.has_output() && !rf.empty() && !rf.full();
    };
    // The shared side's cycle, sphere s broadcast in it (-1: none), unless it is off.
    auto shared_step = [&](std::int64_t s, bool spheres_pending) {
        if (shared_off) return;
        tick_shared_side(spheres_pending);
        if (s >= 0) {
            rf.push(std::uint32_t(s));
            ref_max = std::max<std::uint64_t>(ref_max, rf.size());
        }
    };
    // d skipped cycles that each send a sphere, the shared side ticked as the steps tick it until it streams.
    auto spheres_follow = [&](std::uint64_t d) {
        for (; d && !shared_off && !shared_streams(); --d) {
            const std::uint64_t s = sphere_link.position();
            sphere_memory.read(std::size_t(s));
            sphere_link.sent();
            shared_step(std::int64_t(s), sphere_link.has_record());
        }
        if (d) spheres_stream(d);
    };
    // d skipped cycles in which the sphere stream is stopped: the shared side, which nothing reads
    // meanwhile, is ticked until it runs dry, then idles.
    auto spheres_stopped = [&](std::uint64_t d) {
        no_sphere_cycles += d;
        sphere_link.stalled(d);
        std::uint64_t drain = 0;
        for (; drain < d && !shared_off && !(rf.empty() && rp.drained()); ++drain) {
            lazy_sphere_blocked += n_ref && rf.full();
            tick_shared_side(true);
        }
        rp.add_starved(d - drain);
        rp.idle(d - drain);
    };
    // d skipped cycles that each send a triangle.
    auto triangles_flow = [&](std::uint64_t d) {
        note_sent(triangle_link.position(), cycle);
        triangle_memory.read_many(d);
        triangle_link.sent_many(d);
    };
    // Moves past d skipped cycles, the simulated time kept in step as a stepped cycle keeps it.
    auto skip = [&](std::uint64_t d) {
        cycle += d;
        since_sync_ += d;
        if (since_sync_ >= cfg_.sync_cycles) {
            wait(period_ * double(since_sync_));
            since_sync_ = 0;
        }
    };
    // The end of cycle c, stepped or the last of a skip: the cruises that end, and the
    // Triangle FIFOs' holds on the link in the next cycle.
    auto end_of_cycle = [&](std::uint64_t c) {
        // Cruising ICCs whose next queued sphere leaves the pipe next cycle, or whose Sphere FIFO is dry then.
        if (!cruisers.empty() && (cruise_end <= c + 1 || no_sphere_cycles >= cruise_dry)) {
            for (std::size_t i = 0; i < cruisers.size();) {
                const std::uint32_t k = cruisers[i];
                if (cruise[k].end <= c + 1 || no_sphere_cycles >= cruise[k].nb0 + cruise[k].count0) {
                    land(k, c + 1);
                    cruisers[i] = cruisers.back();
                    cruisers.pop_back();
                } else {
                    ++i;
                }
            }
            cruise_bounds();
        }

        // Triangle FIFOs full at the start of the next cycle.
        for (std::uint32_t k : full_now) is_full[k] = 0;
        full_now.clear();
        for (std::size_t i = 0; i < holds.size();) {
            if (holds[i].until <= c) {  // fallen by the end of this cycle
                if (hold_of[holds[i].k] == i) hold_of[holds[i].k] = kNoHold;
                if (i + 1 != holds.size()) {
                    holds[i] = holds.back();
                    if (hold_of[holds[i].k] == holds.size() - 1) hold_of[holds[i].k] = std::uint32_t(i);
                }
                holds.pop_back();
                continue;
            }
            if (holds[i].from <= c + 1 && !is_full[holds[i].k]) {
                is_full[holds[i].k] = 1;
                full_now.push_back(holds[i].k);
            }
            ++i;
        }
        std::sort(full_now.begin(), full_now.end());
    };
    // Both streams done, no selection left, the last work done before `cycle`: the pass is over.
    auto pass_over = [&] {
        return !sphere_link.has_record() && !triangle_link.has_record() && selecting.empty() &&
               (p.drain ? max_done : prev_done) < cycle;
    };
    Watch watch{progress_signature(), 0};
    for (;;) {
        const std::uint32_t sp = std::uint32_t(sphere_link.position());
        const std::uint32_t tp = std::uint32_t(triangle_link.position());
        const bool s_has = sphere_link.has_record();
        const bool t_has = triangle_link.has_record() && cycle >= cfg_.triangle_lag_cycles;
        const std::uint32_t ts = t_has ? triangle_memory.sphere_of(tp) : 0;

        auto tri_blocker = [&](std::uint32_t k) {  // ICC k's Triangle FIFO stops this triangle
            return is_full[k] && (any_full || TriangleSelector::wants(ts, active[k]->first_tri_fifo));
        };

        // ---- the drain: both streams done, the back ends finish ----------
        // Every sphere is decided in every ICC (the last triangle was
        // broadcast) and nothing is left in flight on the sphere side: up to
        // the pass's end only the Fetchers and RTIs work, and they are in
        // closed form already (`back`). The cycles up to the last are idle
        // on both links.
        if (!t_has && !s_has && !triangle_link.has_record() && selecting.empty() && dozers.empty() &&
            cruisers.empty() && shared_empty()) {
            const std::uint64_t last = p.drain ? max_done : prev_done;  // the pass's last cycle
            bool quiet = last != kNever;
            for (std::uint32_t k : individuals)
                quiet = quiet && active[k]->sphere_fifo.empty() && active[k]->psi.in_flight() == 0;
            if (quiet && last > cycle + 1) {
                const std::uint64_t d = last - cycle;  // (cycle `last` itself is stepped)
                spheres_idle(d);
                triangle_link.idle(d);
                skip(d);
                continue;
            }
        }

        // ---- skip cycles in which only stream positions change -----------
        // The sphere side either streams steadily (a sphere in and a decision
        // out every cycle, every ICC on the shared pipeline), or is finished
        // (every sphere decided, nothing in flight, in every ICC), or is
        // frozen: every individual ICC's Decoder holds (its PlaneID or
        // First-Triangle-ID FIFO is full), one of them has a full Sphere FIFO
        // that stops the sphere stream, and the shared side has run dry; only
        // a triangle selection can change that. The triangle stream either
        // flows (no ICC selecting, no full Triangle FIFO) up to the next
        // waiting ICC's triangles, or is held by full Triangle FIFOs until the
        // first of them is popped.
        // Dozers and cruisers change only in closed form: a skip stops short of
        // a dozer's Sphere FIFO filling, a cruise's end and its Sphere FIFO
        // running dry. (A cruiser's decisions keep ahead of the triangle
        // stream: it decides a sphere a cycle, and every sphere has a triangle.)
        if (t_has && (n_ref == 0 || rd.decided() > ts) &&
            (cruisers.empty() || std::int64_t(cycle) + cruise_offset > std::int64_t(ts))) {
            // (Steady with no reference ICC too, every ICC then cruising or dozing: a cruiser decides a sphere
            // a cycle and its Sphere FIFO stays as it is while the stream moves, a dozer's Sphere FIFO takes the
            // spheres up to its bound below; the shared side follows the stream all the same, ticked as the
            // steps tick it until it streams: nothing but a rejoining ICC reads it.)
            const bool s_steady = na > 0 && individuals.empty() && dozers_full == 0 && s_has &&
                                  (n_ref == 0 || shared_streams());
            // (done but for dozers, which change nothing but counts up to a selection that pops their FIFOs,
            // and cruisers, which decide a sphere a cycle from their Sphere FIFOs up to the bounds below)
            bool s_done = !s_has && shared_empty() && doze_decided > ts;
            // (with no hand-over due to a sphere it holds, the shared side runs dry in the skip as the steps
            // would run it: nothing reads it meanwhile)
            bool s_frozen = s_has && !(individuals.empty() && dozers.empty()) &&
                            ((rf.empty() && rp.drained()) || kept_at.empty() || kept_at.min_key() >= sp) &&
                            doze_decided > ts;
            bool stops_spheres = dozers_full > 0;
            std::uint32_t min_decided = std::min(n_ref ? rd.decided() : ~std::uint32_t(0), doze_decided);
            for (std::uint32_t k : individuals) {
                const Icc& c = *active[k];
                const std::uint32_t dec = c.decoder.decided();
                s_done = s_done && c.sphere_fifo.empty() && c.psi.in_flight() == 0 && dec > ts;
                s_frozen = s_frozen && dec > ts && c.decoder_holds() && !c.psi.stuck();
                stops_spheres = stops_spheres || c.sphere_fifo.full();
                min_decided = std::min(min_decided, dec);
            }
            s_frozen = s_frozen && stops_spheres;
            const bool t_flows = full_now.empty() && selecting.empty();
            bool t_held = false;
            std::uint64_t d = 0;
            // The first cycle a hold reaches the link, or leaves it after
            // (`popped`): the set of holds is the same up to then.
            std::uint64_t popped = kNever, raised = kNever;
            for (const Hold& h : holds) {
                if (h.from > cycle) raised = std::min(raised, h.from);
                else popped = std::min(popped, h.until);
            }
            if (t_flows) {
                d = triangle_link.end() - tp;
                if (!waiting.empty()) d = std::min<std::uint64_t>(d, waiting.min_key() - tp);
                if (!coast_pops.empty()) d = std::min<std::uint64_t>(d, coast_pops.min_key() - tp);
                if (raised != kNever) d = std::min<std::uint64_t>(d, raised - cycle);
            } else if (!full_now.empty()) {
                for (std::uint32_t k : full_now) t_held = t_held || tri_blocker(k);
                // (a FIFO never popped, under fault injection, is left to the
                // cycle-by-cycle steps and their watchdog)
                if (t_held && popped != kNever) d = std::min(popped + 1, raised) - cycle;  // (held up to `popped`)
            }
            if (s_steady) {
                d = std::min<std::uint64_t>(d, sphere_link.end() - sp);
                // (with no reference ICC the hand-overs only move cursors: the next stepped cycle moves them on)
                if (n_ref && !kept_at.empty()) d = std::min<std::uint64_t>(d, kept_at.min_key() - rp.output().sphere);
            }
            // (the cycle that fills a dozer's Sphere FIFO is stepped: it stops the sphere stream from the next)
            if (s_steady && !dozers.empty()) d = std::min<std::uint64_t>(d, doze_fill - sp - 1);
            if (!cruisers.empty()) {
                d = std::min<std::uint64_t>(d, cruise_end - cycle);
                if (!s_steady) d = std::min<std::uint64_t>(d, cruise_dry - no_sphere_cycles);
            }
            if ((s_frozen || s_done) && t_flows && min_decided < sphere_memory.size())  // (no decision while frozen; a dozer's)
                d = std::min<std::uint64_t>(d, info.first_tri(min_decided) - tp);
            if (s_frozen && t_flows)  // a coasting ICC's pop can free its Decoder
                for (std::uint32_t k : individuals)
                    if (coast[k].on && !active[k]->first_tri_fifo.empty()) {
                        const FirstTriEntry& h = active[k]->first_tri_fifo.front();
                        d = std::min<std::uint64_t>(d, h.first + h.count - 1 - tp);
                    }
            // The d cycles before the event are skipped (d is the distance to it), ended as a
            // stepped cycle ends; the event's cycle is stepped.
            if ((t_flows || t_held) && (s_steady || s_done || s_frozen) && d > 0) {
                if (s_steady) {
                    spheres_follow(d);
                } else if (s_frozen) {
                    spheres_stopped(d);
                    for (std::uint32_t k : individuals) active[k]->hold_front(d);
                } else {
                    spheres_idle(d);
                }
                if (t_flows) {
                    triangles_flow(d);
                } else {
                    triangle_link.stalled(d);
                    note_held(d, tri_blocker);
                }
                skip(d);
                end_of_cycle(cycle - 1);
                if (pass_over()) break;
                continue;
            }
        }

        // ---- the only ICC on its own, its pipe full: its front end counted --
        // (8. in the header) Cycle by cycle the links, the shared side and
        // its coast's pops are stepped as usual, but its own front end is a
        // count: its Decoder decides one sphere a cycle, or holds at a kept
        // sphere while its FIFOs are full; its PSI then takes the next sphere
        // from its Sphere FIFO, or stalls; its Sphere FIFO takes every sphere
        // broadcast and stops the stream when full, so it does not run dry
        // while the stream lasts. Up to a selection, a hand-over, an
        // undecided sphere on the triangle stream, a run of spheres it does
        // not queue long enough to cruise (7.), the end of either stream or
        // a watchdog look; its blocks are then brought up to date at once.
        if (may_cruise && individuals.size() == 1 && dozers.empty() && cruisers.empty() && selecting.empty() &&
            full_now.empty() && holds.empty() && t_has && s_has) {
            const std::uint32_t k = individuals[0];
            Icc& c = *active[k];
            const Coast& co = coast[k];
            if (!(co.on && co.pos >= co.next) && !lazy[k].on && !c.psi.stuck() && c.psi.in_flight() == stages &&
                c.psi.free_to_issue() && c.psi.has_output() && !c.sphere_fifo.empty()) {
                Fifo<FirstTriEntry>& f = c.first_tri_fifo;
                const std::uint32_t s_depth = c.sphere_fifo.depth();
                const std::vector<SphereHitRec>& hits = *queued[k].hits;
                auto head_end = [&] { return f.empty() ? ~std::uint32_t(0) : f.front().first + f.front().count; };
                std::uint32_t x = c.psi.output().sphere;  // its Decoder's next decision
                // (pop_at: the link position at which its coast pops its head entry)
                std::uint32_t occupancy = c.sphere_fifo.size(), most = occupancy, pop_at = co.on ? head_end() : ~0u;
                std::uint64_t took = 0, held = 0, blocked = 0, received = 0;
                // (short of either stream's last record: the steps see the pass end)
                while (occupancy && sphere_link.position() + 1 < sphere_link.end() &&
                       triangle_link.position() + 1 < triangle_link.end() && cycle >= cfg_.triangle_lag_cycles &&
                       since_sync_ + 1 < cfg_.sync_cycles) {
                    const std::uint32_t tp_now = std::uint32_t(triangle_link.position());
                    if (!waiting.empty() && waiting.min_key() <= tp_now) break;
                    const std::uint32_t ts_now = triangle_memory.sphere_of(tp_now);
                    if (x <= ts_now || (n_ref && rd.decided() <= ts_now)) break;
                    if (rp.has_output() && !kept_at.empty() && kept_at.min_key() <= rp.output().sphere) break;
                    const std::uint32_t kept_next = next_queued(k, x);
                    if (kept_next >= x + kMinCruise) break;  // (it would cruise: the steps skip further)
                    // The cycles up to its coast's next pop: it holds (d: how many,
                    // bounded as the per-cycle checks above would end them).
                    const bool holds_on = kept_next == x && f.full() && tp_now + 1 < pop_at;
                    auto held_for = [&](std::uint64_t d) {
                        d = std::min<std::uint64_t>(d, std::min(pop_at - 1, info.first_tri(x)) - tp_now);
                        if (!waiting.empty()) d = std::min<std::uint64_t>(d, waiting.min_key() - tp_now);
                        if (n_ref && rd.decided() < sphere_memory.size())
                            d = std::min<std::uint64_t>(d, info.first_tri(rd.decided()) - tp_now);
                        d = std::min<std::uint64_t>(d, triangle_link.end() - 1 - tp_now);
                        return std::min<std::uint64_t>(d, cfg_.sync_cycles - 1 - since_sync_);
                    };
                    // ... while its Sphere FIFO fills and the shared side streams
                    // steadily (its hand-overs bound them as in the skips).
                    if (holds_on && occupancy < s_depth && (shared_off || shared_streams())) {
                        std::uint64_t d = held_for(s_depth - occupancy);
                        d = std::min<std::uint64_t>(d, sphere_link.end() - 1 - sphere_link.position());
                        if (!kept_at.empty()) d = std::min<std::uint64_t>(d, kept_at.min_key() - rp.output().sphere);
                        if (d >= 2) {
                            spheres_stream(d);
                            triangles_flow(d);
                            occupancy += std::uint32_t(d);
                            most = std::max(most, occupancy);
                            received += d;
                            held += d;
                            skip(d);  // (short of a watchdog look)
                            continue;
                        }
                    }
                    // Frozen up to its coast's next pop: it holds and its full Sphere FIFO
                    // stops the stream; the shared side decides what it holds (its
                    // hand-overs come later: every sphere in it was broadcast) and idles.
                    if (holds_on && occupancy == s_depth &&
                        (kept_at.empty() || kept_at.min_key() >= sphere_link.position())) {
                        const std::uint64_t d = held_for(~std::uint64_t(0));
                        spheres_stopped(d);
                        triangles_flow(d);
                        blocked += d;
                        held += d;
                        skip(d);
                        continue;
                    }
                    const bool ref_full = n_ref && rf.full();
                    const bool s_ok = occupancy < s_depth && !ref_full;
                    lazy_sphere_blocked += ref_full;
                    blocked += occupancy == s_depth;
                    std::int64_t s = -1, t = -1;
                    broadcast(true, s_ok, true, true, s, t);
                    if (t >= 0) note_sent(std::uint64_t(t), cycle);
                    const bool spheres_pending = sphere_link.has_record();
                    if (s < 0) ++no_sphere_cycles;
                    shared_step(s, spheres_pending);
                    if (std::uint32_t(t) + 1 >= pop_at) {  // its coast passes the end of its head entry
                        catch_up(k, std::uint32_t(t) + 1);
                        pop_at = head_end();
                    }
                    bool takes = true;
                    if (kept_next == x) {  // kept
                        if (f.full()) {
                            takes = false;
                            ++held;
                        } else {
                            const Queued& q = queued[k];
                            const bool paired = q.hit < hits.size() && hits[q.hit].sphere == x;
                            const PlaneIdEntry masks = paired ? PlaneIdEntry{hits[q.hit].rows, hits[q.hit].cols} : PlaneIdEntry{};
                            c.planeid_fifo.push(masks);
                            f.push(info.entry(x));
                            c.decoder.note_hit(!paired);
                            if (f.size() == 1) {  // (its FIFOs were empty)
                                if (co.on) pop_at = head_end();
                                else wait_for(k, f.front().first);
                            }
                        }
                    }
                    if (takes) {
                        ++x;
                        ++took;
                        --occupancy;
                    }
                    if (s >= 0) {
                        ++occupancy;
                        ++received;
                    }
                    most = std::max(most, occupancy);
                    skip(1);
                }
                if (took || held) {
                    c.psi.cruise(took);
                    c.psi.add_stalled(held);
                    c.sphere_fifo.cruise(std::uint32_t(took), std::uint32_t(received));
                    c.sphere_fifo.note_occupancy(most);
                    c.decoder.set_decided(x);
                    c.decoder.note_held(held);
                    c.planeid_fifo.note_full(held);
                    f.note_full(held);
                    c.note_sphere_blocked(blocked);
                    continue;
                }
            }
        }

        // ---- link decisions (state at the start of the cycle) -----------
        bool s_ok = s_has, t_ok = t_has;
        if (n_ref) {
            s_ok = s_ok && !rf.full();
            t_ok = t_ok && rd.decided() > ts;
        }
        for (std::uint32_t k : individuals) {
            s_ok = s_ok && active[k]->sphere_ready();
            t_ok = t_ok && active[k]->decoder.decided() > ts;
        }
        s_ok = s_ok && dozers_full == 0;
        t_ok = t_ok && doze_decided > ts && (cruisers.empty() || std::int64_t(cycle) + cruise_offset > std::int64_t(ts));
        if (t_ok)
            for (std::uint32_t k : full_now)
                if (tri_blocker(k)) t_ok = false;
        if (s_has && !s_ok) {
            if (n_ref && rf.full()) ++lazy_sphere_blocked;
            for (std::uint32_t k : individuals)
                if (!active[k]->sphere_ready()) active[k]->note_sphere_blocked();
        }
        if (t_has && !t_ok) {
            if (n_ref && rd.decided() <= ts) ++lazy_undecided;
            for (std::uint32_t k : individuals)
                if (active[k]->decoder.decided() <= ts) active[k]->triangle_selector.add_blocked_undecided(1);
            for (std::uint32_t k : cruisers)
                if (cruise_decided(k, cycle) <= ts) active[k]->triangle_selector.add_blocked_undecided(1);
            note_held(1, [&](std::uint32_t k) { return decided_of(k, cycle) > ts && tri_blocker(k); });
        }
        std::int64_t s = -1, t = -1;
        broadcast(s_has, s_ok, t_has, t_ok, s, t);
        if (t >= 0) note_sent(std::uint64_t(t), cycle);
        const bool spheres_pending = sphere_link.has_record();
        if (s < 0) ++no_sphere_cycles;
        if (s >= 0 && sphere_link.position() >= doze_fill) {  // a dozer's Sphere FIFO is full from the next cycle
            for (std::uint32_t k : dozers)
                if (doze[k].full_from == kNever && doze[k].fill_pos <= sphere_link.position()) {
                    doze[k].full_from = cycle + 1;
                    doze[k].s_has_full = spheres_pending;
                    ++dozers_full;
                }
            doze_bounds();
        }

        // ---- triangle selection ------------------------------------------
        if (t >= 0) {
            while (!coast_pops.empty() && coast_pops.min_key() <= std::uint32_t(t)) {
                const std::uint32_t key = coast_pops.min_key();
                coast_pops.pop_min([&](std::uint32_t k) {
                    in_pops[k] = 0;
                    if (!dozing[k] || pop_wanted[k] == kNoPop) return;
                    if (pop_wanted[k] > key) {  // (an entry left behind)
                        coast_pops.push(pop_wanted[k], k);
                        in_pops[k] = 1;
                        return;
                    }
                    pop_wanted[k] = kNoPop;
                    catch_up(k, std::uint32_t(t) + 1);  // its head entry's last triangle, taken this cycle
                    wake(k, cycle, s);
                });
            }
            while (!waiting.empty() && waiting.min_key() <= std::uint32_t(t))
                waiting.pop_min([&](std::uint32_t k) {
                    if (lazy[k].on) push_lazy(k, rd.decided());
                    if (coast[k].on) {  // the triangle after its coast
                        catch_up(k, std::uint32_t(t));
                        end_coast(k, cycle);
                    }
                    push_ahead(k, cycle);
                    wait_ahead[k] = 0;
                    selecting.push_back(k);
                });
            for (std::size_t i = 0; i < selecting.size();) {
                const std::uint32_t k = selecting[i];
                if (lazy[k].on) push_lazy(k, rd.decided());  // (so that a coast can cover the whole run)
                push_ahead(k, cycle);
                head_in_fifo(k);
                const bool coasts = select(k, std::uint32_t(t), cycle);
                if (dozing[k] && (coasts || !(active[k]->planeid_fifo.full() || active[k]->first_tri_fifo.full())))
                    wake(k, cycle, s);
                if (coasts) {
                    waiting.push(coast[k].next, k);
                    selecting[i] = selecting.back();
                    selecting.pop_back();
                    continue;
                }
                head_in_fifo(k);
                const Fifo<FirstTriEntry>& f = active[k]->first_tri_fifo;
                if (f.empty() || f.front().sphere != ts) {
                    if (!f.empty()) waiting.push(f.front().first, k);
                    else if (lazy[k].on && lazy[k].has) waiting.push(info.first_tri(kept[k].sphere), k);  // (not decided yet)
                    else if (ahead[k].on && lazy[k].has) wait_ahead_for(k, kept[k].sphere);
                    selecting[i] = selecting.back();
                    selecting.pop_back();
                } else {
                    ++i;
                }
            }
        }

        // ---- shared Decoder: release hit spheres to the reference ICCs ----
        diverged.clear();
        if (!shared_off && rp.has_output()) {
            const std::uint32_t x = rp.output().sphere;
            // Moves ICC k's cursor on, to its next kept sphere; returns the masks of this one.
            auto advance = [&](std::uint32_t k) {
                KeptSpheres& e = kept[k];
                const PlaneIdEntry masks{e.rows, e.cols};
                if (e.next()) kept_at.push(e.sphere, k);
                return masks;
            };
            // (A reference ICC is never passed: the skips stop at its next kept sphere. An ICC on its own is
            // not in `kept_at` but from the start under fault injection; passed, its entry is only moved on.)
            while (!kept_at.empty() && kept_at.min_key() < x)
                kept_at.pop_min([&](std::uint32_t k) { advance(k); });
            if (!kept_at.empty() && kept_at.min_key() == x)
                kept_at.pop_min([&](std::uint32_t k) {
                    if (lazy[k].on) {  // the end of its lazy span
                        push_lazy(k, x + 1);
                        arm_lazy(k, x);
                        return;
                    }
                    if (role[k] != ref) return;  // (on its own: its cursor is set again when it rejoins)
                    Icc& c = *active[k];
                    if (coast[k].on) catch_up(k, std::uint32_t(triangle_link.position()));
                    if (occupancy_of(k) >= c.planeid_fifo.depth()) {
                        store_all(k);
                        adopt_reference(k);  // its Decoder holds: it has its own sphere side until it rejoins
                        role[k] = individual;
                        --n_ref;
                        shared_off = n_ref == 0 && may_leave_shared;
                        diverged.push_back(k);
                        return;
                    }
                    const bool was_empty = occupancy_of(k) == 0 && !coast[k].on;  // (a coast waits already)
                    if (was_empty) wait_for(k, info.first_tri(x));
                    if (may_lazy) {  // queued unstored, and the spheres after it lazily
                        lazy[k].has = true;
                        push_lazy(k, x + 1);
                        arm_lazy(k, x);
                        return;
                    }
                    KeptSpheres& e = kept[k];
                    const PlaneIdEntry masks{e.rows, e.cols};
                    c.planeid_fifo.push(masks);
                    c.first_tri_fifo.push(info.entry(x));
                    c.decoder.note_hit(!(masks.rows && masks.cols));
                    advance(k);
                });
        }
        shared_step(s, spheres_pending);

        // ---- individual ICCs: their own sphere side -----------------------
        for (std::uint32_t k : diverged) individuals.push_back(k);
        for (std::size_t i = 0; i < individuals.size();) {
            const std::uint32_t k = individuals[i];
            Icc& c = *active[k];
            if (coast[k].on) catch_up(k, std::uint32_t(triangle_link.position()));
            const bool was_empty = c.first_tri_fifo.empty() && !coast[k].on;
            c.tick_front(s, info, spheres_pending);
            if (was_empty && !c.first_tri_fifo.empty()) wait_for(k, c.first_tri_fifo.front().first);
            if (may_rejoin(k)) {  // (the order of `individuals` changes no figure)
                role[k] = ref;
                ++n_ref;
                joined[k] = joined_now();
                // (every sphere before the shared side's next one is decided)
                kept[k].seek(rd.decided());
                lazy[k].has = kept[k].next();
                if (lazy[k].has) kept_at.push(kept[k].sphere, k);
                individuals[i] = individuals.back();
                individuals.pop_back();
                continue;
            }
            // (a coast's pops wake it: `coast_pops`)
            if (may_doze && !lazy[k].on && !c.psi.stuck() && c.decoder_holds()) {
                start_doze(k, cycle);
                individuals[i] = individuals.back();
                individuals.pop_back();
                continue;
            }
            if (may_cruise && !lazy[k].on && !c.psi.stuck() && c.psi.in_flight() == stages && c.psi.free_to_issue() &&
                c.psi.has_output() && !c.sphere_fifo.empty() && !c.sphere_fifo.full()) {
                const std::uint32_t d0 = c.decoder.decided();
                std::uint32_t x = next_queued(k, d0);
                // Past the kept spheres its FIFOs have room for (pops only add
                // to it), up to the next: its Decoder cannot hold before.
                const std::uint32_t room = std::min(c.planeid_fifo.depth() - c.planeid_fifo.size(),
                                                    c.first_tri_fifo.depth() - c.first_tri_fifo.size());
                const bool queues = may_queue_ahead && x < d0 + kMinCruise && room > 0;
                KeptSpheres at;
                if (queues) x = kept_after(k, d0, std::min(room, kAheadScan), at);
                if (x >= d0 + kMinCruise) {
                    if (queues) {
                        ahead[k] = Ahead{true, d0, cycle + 1};
                        kept[k] = at;
                        lazy[k].has = kept[k].next();
                        if (lazy[k].has && c.first_tri_fifo.empty() && !coast[k].on)
                            wait_ahead_for(k, kept[k].sphere);  // (decided before the stream reaches it)
                    }
                    cruise[k] = Cruise{cycle + 1, d0, c.sphere_fifo.size(), sphere_link.position(), no_sphere_cycles,
                                       cycle + 1 + (x - d0)};
                    cruising[k] = 1;
                    cruisers.push_back(k);
                    cruise_bounds();
                    individuals[i] = individuals.back();
                    individuals.pop_back();
                    continue;
                }
            }
            ++i;
        }
        end_of_cycle(cycle);
        ++cycle;
        if (pass_over()) break;
        std::uint64_t cruised = 0;  // (a cruising ICC's decisions are progress the watchdog must see)
        if (since_sync_ + 1 >= cfg_.sync_cycles)
            for (std::uint32_t k : cruisers) cruised += cruise_decided(k, cycle);
        if (++since_sync_ >= cfg_.sync_cycles && !sync_time(cycle, watch, max_done + cruised, [&] { return views(cycle); }))
            return cycle;
    }
    settle_tallies();
    for (std::uint32_t k : dozers) settle(k, cycle, cycle, sphere_link.position());
    land_all(cycle);
    for (std::uint32_t k = 0; k < na; ++k) {
        if (lazy[k].on) push_lazy(k, rd.decided());
        store_all(k);
        if (role[k] == ref) adopt_reference(k);
    }
    for (auto& icc : iccs)
        if (!icc.active()) icc.add_idle(cycle);
    if (cfg_.overlap_passes)  // the next pass starts at this pass's cycle `cycle`
        for (Back& b : back) shift_back(b, cycle);
    return cycle;
}

void Top::shift_back(EventBack& b, std::uint64_t by) {
    constexpr std::uint64_t kNever = ~std::uint64_t(0);
    while (!b.starts.empty() && b.starts.front() < by) b.starts.pop_front();  // popped by the end of cycle by - 1
    for (std::size_t i = 0; i < b.starts.size(); ++i)
        if (b.starts[i] != kNever) b.starts[i] -= by;
    if (b.any && b.next_cyc >= by) b.next_cyc -= by;
    else b.any = false;  // the next issue slot is free from the pass's first cycle on
    if (b.done != kNever) b.done = b.done >= by ? b.done - by : 0;
}

}  // namespace raplas::model
