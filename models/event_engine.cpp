// Event-driven pass of the timing model (sim.mode = "event"): the same
// machine, the same cycle-by-cycle semantics as Top::run_pass, computed with
// less work. Exactness rests on three facts:
//  1. Every ICC sees the same sphere stream, so the sphere side (Sphere FIFO,
//     PSI timing, Decoder's `decided` count) of every ICC whose PSI has never
//     been held is identical: one shared reference pipeline stands for all of
//     them. An ICC whose Decoder cannot queue a hit takes over the reference
//     state and is stepped on its own from then on ("individual").
//  2. A reference ICC does nothing visible except when the reference Decoder
//     releases one of its hit spheres, when the triangle stream reaches the
//     triangles of its pending spheres, and while its Triangle FIFO, Ray Data
//     Fetcher or RTI hold work: only then is it touched.
//  3. When no ICC holds work and the reference pipeline streams steadily (a
//     sphere in and a decision out every cycle), nothing but the stream
//     positions changes until the next such event: those cycles are skipped
//     in one step.
// The equivalence with the cycle-by-cycle mode is checked in CI on a grid of
// scenes, ICC counts, FIFO depths and policies (tests/equivalence_modes.py).
#include <algorithm>
#include <queue>

#include "top.hpp"

namespace raplas::model {

std::uint64_t Top::run_pass_event(const Host::Pass& p) {
    enum Role : std::uint8_t { ref, individual };
    std::vector<Icc*> active;
    for (std::size_t k = 0; k < iccs.size(); ++k) {
        const std::uint32_t gi = p.begin + std::uint32_t(k);
        const TraceGroup* g = gi < p.end ? &trace_.groups[gi] : nullptr;
        iccs[k].start_pass(g);
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
    rf.clear();
    rp.start_group(2 * n, &no_hits_);
    rd.start_group();
    const std::uint64_t rf_pushes0 = rf.stats().pushes;
    const std::uint64_t rp_starved0 = rp.stats().starved_cycles;
    std::uint64_t ref_max = 0;
    std::uint64_t lazy_sphere_blocked = 0, lazy_undecided = 0;
    const std::uint32_t stages = cfg_.icc.psi.stages;
    const bool any_full = cfg_.icc.selector.policy == StallPolicy::any_full;

    std::vector<Role> role(na, ref);
    std::size_t n_ref = na;
    // Hit spheres of the reference ICCs, in sphere order.
    struct HitEv {
        std::uint32_t sphere, icc;
        std::uint64_t rows, cols;
    };
    std::vector<HitEv> hits;
    for (std::size_t k = 0; k < na; ++k)
        for (const auto& h : active[k]->unit().sphere_hits()) hits.push_back({h.sphere, std::uint32_t(k), h.rows, h.cols});
    std::sort(hits.begin(), hits.end(), [](const HitEv& a, const HitEv& b) {
        return a.sphere < b.sphere || (a.sphere == b.sphere && a.icc < b.icc);
    });
    std::size_t hpos = 0;
    // ICCs waiting for the triangle stream to reach their head sphere, by its first triangle.
    using Wait = std::pair<std::uint32_t, std::uint32_t>;
    std::priority_queue<Wait, std::vector<Wait>, std::greater<Wait>> waiting;
    std::vector<std::uint32_t> selecting, working, individuals, ref_full;
    std::vector<std::uint8_t> in_working(na, 0);

    auto adopt_reference = [&](std::size_t k) {
        Icc& c = *active[k];
        c.sphere_fifo.adopt(rf, rf.stats().pushes - rf_pushes0, ref_max);
        c.psi.adopt(rp);
        c.decoder.set_decided(rd.decided());
        c.sphere_selector.add_blocked(lazy_sphere_blocked);
        c.sphere_fifo.note_full(lazy_sphere_blocked);
        c.triangle_selector.add_blocked_undecided(lazy_undecided);
        c.psi.add_starved(rp.stats().starved_cycles - rp_starved0);
    };
    auto first_tri = [&](std::uint32_t sphere) { return sphere_memory.peek(sphere).first_tri; };

    std::uint64_t cycle = 0;
    std::uint64_t last_sig = progress_signature(), last_change = 0;
    for (;;) {
        const std::uint32_t sp = std::uint32_t(sphere_link.position());
        const std::uint32_t tp = std::uint32_t(triangle_link.position());
        const bool s_has = sphere_link.has_record();
        const bool t_has = triangle_link.has_record() && cycle >= cfg_.triangle_lag_cycles;
        const std::uint32_t ts = t_has ? triangle_memory.sphere_of(tp) : 0;

        // ---- skip steady streaming -------------------------------------
        if (individuals.empty() && working.empty() && selecting.empty() && n_ref > 0 && s_has && t_has &&
            rp.batches() == 1 && rp.in_flight() == stages && rp.has_output() && !rf.empty() && !rf.full() &&
            rd.decided() > ts) {
            const std::uint32_t xf = rp.output().sphere;  // decided now; then xf+1, xf+2, ... one per cycle
            std::uint64_t d = std::min<std::uint64_t>(sphere_link.end() - sp, triangle_link.end() - tp);
            if (hpos < hits.size()) d = std::min<std::uint64_t>(d, hits[hpos].sphere - xf);
            if (!waiting.empty()) d = std::min<std::uint64_t>(d, waiting.top().first - tp);
            if (d > 1) {
                --d;  // the event cycle itself is stepped normally
                sphere_memory.read_many(d);
                sphere_link.sent_many(d);
                triangle_memory.read_many(d);
                triangle_link.sent_many(d);
                rp.fast_forward(d, rf.front());
                rf.advance(std::uint32_t(d));
                rd.set_decided(rd.decided() + std::uint32_t(d));
                cycle += d;
                since_sync_ += d;
                if (since_sync_ >= cfg_.sync_cycles) {
                    wait(period_ * double(since_sync_));
                    since_sync_ = 0;
                }
                continue;
            }
        }

        // ---- link decisions (state at the start of the cycle) -----------
        bool s_ok = s_has, t_ok = t_has;
        if (n_ref) {
            s_ok = s_ok && !rf.full();
            t_ok = t_ok && rd.decided() > ts;
            if (t_ok)
                for (std::uint32_t k : ref_full)
                    if (any_full || TriangleSelector::wants(ts, active[k]->first_tri_fifo)) t_ok = false;
        }
        for (std::uint32_t k : individuals) {
            s_ok = s_ok && active[k]->sphere_ready();
            t_ok = t_ok && active[k]->triangle_ready(ts);
        }
        if (s_has && !s_ok) {
            if (n_ref && rf.full()) ++lazy_sphere_blocked;
            for (std::uint32_t k : individuals)
                if (!active[k]->sphere_ready()) active[k]->note_sphere_blocked();
        }
        if (t_has && !t_ok) {
            if (n_ref) {
                if (rd.decided() <= ts) {
                    ++lazy_undecided;
                } else
                    for (std::uint32_t k : ref_full)
                        if (any_full || TriangleSelector::wants(ts, active[k]->first_tri_fifo)) {
                            // a reference ICC's own Decoder count is not kept up to date: use the shared one
                            active[k]->triangle_selector.note_blocked(ts, rd.decided(), active[k]->triangle_fifo);
                        }
            }
            for (std::uint32_t k : individuals)
                if (!active[k]->triangle_ready(ts)) active[k]->note_triangle_blocked(ts);
        }
        std::int64_t s = -1, t = -1;
        if (s_ok) {
            s = sp;
            sphere_memory.read(sp);
            sphere_link.sent();
        } else if (s_has) {
            sphere_link.stalled();
        } else {
            sphere_link.idle();
        }
        if (t_ok) {
            t = tp;
            triangle_memory.read(tp);
            triangle_link.sent();
        } else if (t_has) {
            triangle_link.stalled();
        } else if (!triangle_link.has_record()) {
            triangle_link.idle();
        }
        const bool spheres_pending = sphere_link.has_record();

        // ---- reference ICCs: back ends, then triangle selection -----------
        for (std::uint32_t k : working) active[k]->tick_back(-1, 0);
        if (t >= 0) {
            while (!waiting.empty() && waiting.top().first <= std::uint32_t(t)) {
                const std::uint32_t k = waiting.top().second;
                waiting.pop();
                if (role[k] == ref) selecting.push_back(k);
            }
            for (std::size_t i = 0; i < selecting.size();) {
                const std::uint32_t k = selecting[i];
                Icc& c = *active[k];
                c.triangle_selector.receive(true, std::uint32_t(t), ts, c.planeid_fifo, c.first_tri_fifo, c.triangle_fifo);
                if (!in_working[k]) {
                    in_working[k] = 1;
                    working.push_back(k);
                }
                if (c.first_tri_fifo.empty() || c.first_tri_fifo.front().sphere != ts) {
                    if (!c.first_tri_fifo.empty()) waiting.push({c.first_tri_fifo.front().first, k});
                    selecting[i] = selecting.back();
                    selecting.pop_back();
                } else {
                    ++i;
                }
            }
        }

        // ---- reference Decoder: release hit spheres to their ICCs ---------
        std::vector<std::uint32_t> diverged;
        if (rp.has_output()) {
            const std::uint32_t x = rp.output().sphere;
            while (hpos < hits.size() && hits[hpos].sphere < x) ++hpos;
            for (; hpos < hits.size() && hits[hpos].sphere == x; ++hpos) {
                const HitEv& h = hits[hpos];
                if (role[h.icc] != ref) continue;
                Icc& c = *active[h.icc];
                if (c.planeid_fifo.full() || c.first_tri_fifo.full()) {
                    adopt_reference(h.icc);  // its Decoder holds: from now on it has its own sphere side
                    role[h.icc] = individual;
                    --n_ref;
                    diverged.push_back(h.icc);
                    continue;
                }
                const bool was_empty = c.first_tri_fifo.empty();
                c.planeid_fifo.push({h.rows, h.cols});
                c.first_tri_fifo.push({x, first_tri(x), sphere_memory.peek(x).tri_count});
                c.decoder.note_hit();
                if (was_empty) waiting.push({first_tri(x), h.icc});
            }
        }
        rd.tick(rp, *ref_planeid_, *ref_first_tri_, info);
        rp.tick(rf, false, spheres_pending || !rf.empty());
        if (s >= 0) {
            rf.push(std::uint32_t(s));
            ref_max = std::max<std::uint64_t>(ref_max, rf.size());
        }

        // ---- individual ICCs --------------------------------------------
        for (std::uint32_t k : individuals) active[k]->tick(s, t, ts, info, spheres_pending);
        for (std::uint32_t k : diverged) {
            active[k]->tick_front(s, info, spheres_pending);
            individuals.push_back(k);
            if (in_working[k]) {
                in_working[k] = 0;
                working.erase(std::find(working.begin(), working.end(), k));
            }
            auto it = std::find(selecting.begin(), selecting.end(), k);
            if (it != selecting.end()) selecting.erase(it);
        }

        // ---- bookkeeping ------------------------------------------------
        ref_full.clear();
        for (std::size_t i = 0; i < working.size();) {
            const std::uint32_t k = working[i];
            if (active[k]->back_idle()) {
                in_working[k] = 0;
                working[i] = working.back();
                working.pop_back();
                continue;
            }
            if (active[k]->triangle_fifo.full()) ref_full.push_back(k);
            ++i;
        }
        std::sort(ref_full.begin(), ref_full.end());  // notes in ICC order, as in cycle mode
        ++cycle;
        if (!sphere_link.has_record() && !triangle_link.has_record() && working.empty() && selecting.empty()) {
            bool drained = true;
            for (std::uint32_t k : individuals) drained = drained && active[k]->drained();
            if (drained) break;
        }
        if (++since_sync_ >= cfg_.sync_cycles) {
            wait(period_ * double(since_sync_));
            since_sync_ = 0;
            const std::uint64_t sig = progress_signature();
            if (sig != last_sig) {
                last_sig = sig;
                last_change = cycle;
            } else if (cycle - last_change >= cfg_.watchdog_cycles) {
                throw std::runtime_error(stuck_report(cycle));
            }
        }
    }
    for (std::size_t k = 0; k < na; ++k)
        if (role[k] == ref) adopt_reference(k);
    for (auto& icc : iccs)
        if (!icc.active()) icc.add_idle(cycle);
    return cycle;
}

}  // namespace raplas::model
