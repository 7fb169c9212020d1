#include "top.hpp"

#include "netlist/netlist.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "raplas/util/atomic_file.hpp"
#include "raplas/util/cpu_time.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/parallel.hpp"
#include "raplas/util/priority.hpp"
#include "raplas/util/worker.hpp"

namespace raplas::model {

struct Top::Vcd {
    sc_core::sc_trace_file* file = nullptr;
    std::string tmp_base, final_path;
};

Top::Top(sc_core::sc_module_name n, const SimConfig& cfg, GroupSource& groups, const Functional& f,
         const SimOptions& opt)
    : sc_core::sc_module(n),
      host(Host::Params{cfg.iccs, cfg.pass_overhead_cycles, cfg.overlap_passes}),
      sphere_memory(SphereMemory::Params{cfg.sphere_record_bytes}),
      triangle_memory(TriangleMemory::Params{cfg.triangle_record_bytes}),
      sphere_link(StreamLink::Params{cfg.sphere_record_bytes}),
      triangle_link(StreamLink::Params{cfg.triangle_record_bytes}),
      cfg_(cfg),
      groups_(groups),
      trace_(groups.header()),
      functional_(f),
      opt_(opt),
      period_(1.0e6 / cfg.clock_mhz, sc_core::SC_PS) {
    for (std::uint32_t k = 0; k < cfg.iccs; ++k) iccs.emplace_back(cfg.icc, f);
    if (cfg.fault == Fault::stuck_rti) iccs[cfg.fault_icc].rti.set_stuck(true);
    if (cfg.fault == Fault::stuck_psi) iccs[cfg.fault_icc].psi.set_stuck(true);
    if (cfg.fault == Fault::wrong_rti) iccs[cfg.fault_icc].inject_wrong_rti();
    std::vector<SphereRecord> srec(trace_.spheres.size());
    std::vector<std::uint32_t> sphere_of(trace_.triangles.size());
    for (std::size_t s = 0; s < trace_.spheres.size(); ++s) {
        srec[s] = {trace_.spheres[s], trace_.first_tri[s], trace_.tri_count[s]};
        for (std::uint32_t t = 0; t < trace_.tri_count[s]; ++t) sphere_of[trace_.first_tri[s] + t] = std::uint32_t(s);
    }
    sphere_memory.load(std::move(srec));
    triangle_memory.load(trace_.triangles, std::move(sphere_of));
    if (opt_.shards == 0 || opt_.shard >= opt_.shards) throw InputError("shard index out of range");
    if (opt_.shards > 1 && (cfg.overlap_passes || cfg.estimate == Estimate::sample_passes || !opt_.vcd_path.empty()))
        throw InputError("a shard of the passes needs independent passes: no host.overlap_passes, sim.estimate = "
                         "sample_passes or waveform");
    if (cfg.estimate == Estimate::fifo_bound && (!opt_.vcd_path.empty() || opt_.on_cycle))
        throw InputError("sim.estimate = fifo_bound computes the cycles in closed form: no waveform (--vcd) or "
                         "per-cycle hook; use sim.estimate = exact");
    // The event-driven mode is exact; per-cycle hooks need every cycle, and a
    // waveform the netlist's signals: they run the netlist.
    const bool waveform = !opt_.vcd_path.empty();
    event_mode_ = cfg.mode == SimMode::event && !waveform && !opt_.on_cycle;
    if (!event_mode_ && cfg.estimate != Estimate::fifo_bound) {
        netlist_ = std::make_unique<netlist::Netlist>(
            cfg, netlist::MachineState{host, iccs, sphere_link, triangle_link, sphere_memory, triangle_memory},
            f.mode() == FunctionalMode::trace, opt_.bind_sphere_memory, opt_.bind_triangle_memory);
        netlist::HostModule& h = netlist_->host;
        auto stop = [this](const std::string& why) {  // (a memory model's error response)
            if (error_.empty()) error_ = why;
            netlist_->host.stop();
        };
        netlist_->sphere_link.on_error = stop;
        netlist_->triangle_link.on_error = stop;
        h.check = [this](std::uint64_t cycle) {
            if (++since_sync_ < cfg_.sync_cycles) return true;
            since_sync_ = 0;
            return watchdog_ok(cycle, netlist_watch_, 0, [&] { return active_views(); });
        };
        if (opt_.on_cycle)
            h.each_cycle = [this](std::uint64_t cycle) {
                std::int64_t sent[2] = {-1, -1};
                const StreamLink* links[2] = {&sphere_link, &triangle_link};
                for (int i = 0; i < 2; ++i)
                    if (links[i]->stats().records_sent != netlist_sent_[i]) {
                        netlist_sent_[i] = links[i]->stats().records_sent;
                        sent[i] = std::int64_t(links[i]->position()) - 1;
                    }
                opt_.on_cycle(*this, cycle - 1, sent[0], sent[1]);
            };
    }
    if (waveform) setup_vcd();
    // In the event-driven mode a group's ray-triangle answers are found when
    // it is loaded, on the loading threads (Icc::answer_at_load). Not for an
    // ICC with an injected wrong answer: whether it fires in a pass depends on
    // the passes before it (sharding), so its tests stay at selection time.
    if (event_mode_ && f.mode() == FunctionalMode::compute)
        for (std::size_t k = 0; k < iccs.size(); ++k)
            if (cfg.fault != Fault::wrong_rti || k != cfg.fault_icc) iccs[k].answer_at_load(SphereInfo{&sphere_memory});
    const bool bound = cfg.estimate == Estimate::fifo_bound;
    if (event_mode_ || bound) {
        ref_fifo_ = std::make_unique<SphereFifo>("shared_sphere_fifo", cfg.icc.sphere_fifo);
        ref_psi_ = std::make_unique<PlaneSphereIntersector>(cfg.icc.psi);
        ref_decoder_ = std::make_unique<Decoder>(cfg.icc.decoder);
        ref_planeid_ = std::make_unique<Fifo<PlaneIdEntry>>("shared_planeid_fifo", FifoParams{1});
        ref_first_tri_ = std::make_unique<Fifo<FirstTriEntry>>("shared_first_tri_fifo", FifoParams{1});
    }
    SC_THREAD(run);
}

Top::~Top() {
    if (vcd_ && vcd_->file) {
        sc_core::sc_close_vcd_trace_file(vcd_->file);
        std::rename((vcd_->tmp_base + ".vcd").c_str(), vcd_->final_path.c_str());
    }
}

void Top::setup_vcd() {
    vcd_ = std::make_unique<Vcd>();
    vcd_->final_path = opt_.vcd_path;
    // A temporary name beside it (".NAME.raplas-tmp-PID.vcd", whose dead
    // namesakes are removed first), without the ".vcd" SystemC appends.
    std::string base = temp_path_for(opt_.vcd_path);
    if (base.size() > 4 && base.substr(base.size() - 4) == ".vcd") base.resize(base.size() - 4);
    vcd_->tmp_base = base;
    vcd_->file = sc_core::sc_create_vcd_trace_file(vcd_->tmp_base.c_str());
    if (!vcd_->file) throw InputError(opt_.vcd_path + ": cannot create VCD file");
    vcd_->file->set_time_unit(1, sc_core::SC_PS);
    netlist_->trace(vcd_->file);  // every signal, port and FIFO, by hierarchical name
}

std::uint64_t Top::progress_signature() const {
    return sphere_link.position() * 3 + triangle_link.position() * 7 + block_progress();
}

std::uint64_t Top::block_progress() const {
    std::uint64_t sig = 0;
    for (const auto& icc : iccs) sig += icc.rti.stats().tests + icc.psi.stats().spheres + icc.decoder.stats().decided;
    return sig;
}

IccView Top::view_of(const Icc& c, std::size_t k) const {
    IccView v;
    v.index = k;
    v.sphere_fifo = c.sphere_fifo.size();
    v.sphere_depth = c.sphere_fifo.depth();
    v.planeid_fifo = std::max(c.planeid_fifo.size(), c.first_tri_fifo.size());
    v.planeid_depth = c.planeid_fifo.depth();
    // (in the netlist through the ICC's port: its Triangle FIFO may be RTL, sim.rtl)
    v.triangle_fifo = netlist_ ? netlist_->iccs[k].triangle_fifo_status->size() : c.triangle_fifo.size();
    v.triangle_depth = c.triangle_fifo.depth();
    v.decided = c.decoder.decided();
    v.psi_held = c.psi.has_output() && queued(c.psi.output(), cfg_.icc.decoder.select) &&
                 (c.planeid_fifo.full() || c.first_tri_fifo.full());
    v.back_busy = !(c.rti.empty() && c.ray_data_fetcher.idle() && v.triangle_fifo == 0);
    return v;
}

std::string Top::stuck_report(std::uint64_t cycle, const std::vector<IccView>& views) const {
    StallPicture p;
    p.watchdog_cycles = cfg_.watchdog_cycles;
    p.cycle = cycle;
    p.pass = current_pass_ + 1;
    p.sphere_link = {sphere_link.position(), sphere_link.end()};
    p.triangle_link = {triangle_link.position(), triangle_link.end()};
    if (triangle_link.has_record()) p.triangle_sphere = triangle_memory.sphere_of(std::uint32_t(triangle_link.position()));
    p.iccs = views;
    p.fault = cfg_.fault;
    p.fault_icc = cfg_.fault_icc;
    return describe_stall(p);
}

void Top::broadcast(bool s_has, bool s_ok, bool t_has, bool t_ok, std::int64_t& s, std::int64_t& t) {
    if (s_ok) {
        s = std::int64_t(sphere_link.position());
        sphere_memory.read(std::size_t(s));
        sphere_link.sent();
    } else if (s_has) {
        sphere_link.stalled();
    } else {
        sphere_link.idle();
    }
    if (t_ok) {
        t = std::int64_t(triangle_link.position());
        triangle_memory.read(std::size_t(t));
        triangle_link.sent();
    } else if (t_has) {
        triangle_link.stalled();
    } else if (!triangle_link.has_record()) {
        triangle_link.idle();  // (before the triangle lag has passed it is neither)
    }
}

bool Top::sync_time(std::uint64_t cycle, Watch& w, std::uint64_t extra_progress,
                    const std::function<std::vector<IccView>()>& views) {
    wait(period_ * double(since_sync_));
    since_sync_ = 0;
    return watchdog_ok(cycle, w, extra_progress, views);
}

std::vector<IccView> Top::active_views() const {
    std::vector<IccView> v;
    for (std::size_t k = 0; k < iccs.size(); ++k)
        if (iccs[k].active()) v.push_back(view_of(iccs[k], k));
    return v;
}

bool Top::watchdog_ok(std::uint64_t cycle, Watch& w, std::uint64_t extra_progress,
                      const std::function<std::vector<IccView>()>& views) {
    const std::uint64_t sig = progress_signature() + extra_progress;
    if (sig != w.signature || cycle <= cfg_.triangle_lag_cycles) {  // the initial lag is no stall
        w.signature = sig;
        w.changed_at = cycle;
    } else if (cycle - w.changed_at >= cfg_.watchdog_cycles) {
        error_ = stuck_report(cycle, views());
        return false;
    }
    return true;
}

std::uint64_t Top::run_pass_netlist(const Host::Pass& p, std::uint8_t buf) {
    std::vector<const TraceGroup*> g(iccs.size(), nullptr);
    for (std::size_t k = 0; k < iccs.size(); ++k)
        if (p.begin + k < p.end) g[k] = &groups_.group(p.begin + std::uint32_t(k));
    netlist_watch_ = Watch{block_progress(), 0};  // (both links start at record 0)
    netlist_sent_[0] = sphere_link.stats().records_sent;
    netlist_sent_[1] = triangle_link.stats().records_sent;
    const std::uint64_t cycle = netlist_->host.control->run_pass(g, buf, cfg_.overlap_passes, p.drain);
    if (!error_.empty()) return cycle;  // the watchdog fired
    for (auto& icc : iccs)
        if (!icc.active()) icc.add_idle(cycle);
    return cycle;
}

void Top::end_pass(const Host::Pass& p) {
    for (std::size_t k = 0; k < p.end - p.begin; ++k) iccs[k].finish_pass(pass_len_, triangle_memory.size());
}

void Top::check_pass(const Host::Pass& p, std::uint8_t buf) {
    for (std::size_t k = 0; k < p.end - p.begin; ++k) {
        const TraceGroup& g = groups_.group(p.begin + k);
        const std::vector<Hit>& hits =
            netlist_ ? netlist_->host.control->results(k, g, buf) : iccs[k].results(g, buf);
        if (functional_.mode() != FunctionalMode::compute) continue;
        for (std::uint32_t v = 0; v < g.n; ++v)
            for (std::uint32_t h = 0; h < g.n; ++h) {
                if (!g.ray_valid(h, v)) continue;
                ++result_.rays_checked;
                const Hit& mine = hits[v * g.n + h];
                if (mine == g.hits[v * g.n + h]) continue;
                ++result_.rays_mismatched;
                if (!result_.first_mismatch)
                    result_.first_mismatch = SimResult::Mismatch{p.begin + k, h, v, mine, g.hits[v * g.n + h],
                                                                 g.kind == GroupKind::primary, g.px, g.py};
            }
    }
}

void Top::preload(const Host::Pass& p, std::uint8_t buf) {
    const std::size_t n = p.end - p.begin;
    std::vector<const TraceGroup*> g(n);
    for (std::size_t k = 0; k < n; ++k) g[k] = &groups_.group(p.begin + k);
    parallel_for(n, default_threads(), [&](std::size_t k) {
        const double cpu0 = thread_cpu_s();
        iccs[k].preload(g[k], buf);
        const auto ns = std::uint64_t(std::max(0.0, thread_cpu_s() - cpu0) * 1e9);
        loads_cpu_ns_ += ns;
        if (std::this_thread::get_id() == model_thread_) loads_cpu_model_ns_ += ns;
    });
}

std::vector<std::uint32_t> choose_passes(const std::vector<Host::Pass>& passes, const SimConfig& cfg,
                                         const SimOptions& opt) {
    if (opt.shards > 1) {
        std::vector<std::uint32_t> mine;
        for (std::uint32_t i = opt.shard; i < passes.size(); i += opt.shards) mine.push_back(i);
        return mine;
    }
    std::vector<std::uint32_t> all(passes.size());
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    if (cfg.estimate != Estimate::sample_passes) return all;
    std::vector<std::uint32_t> chosen, shadow;
    for (std::uint32_t i = 0; i < all.size(); ++i) (passes[i].primary ? chosen : shadow).push_back(i);
    const std::size_t ns = shadow.size();
    const std::size_t n = std::min<std::size_t>(ns, std::max<std::size_t>(2, std::size_t(std::ceil(cfg.sample_fraction * double(ns)))));
    if (n == ns) return all;
    // Stratified sample: one pass in each of n equal strata of the shadow
    // passes, at an offset drawn independently per stratum from the seed (a
    // common offset would alias with the image's rows: at 16 ICCs and 64
    // pixels a row is 4 passes).
    const double step = double(ns) / double(n);
    for (std::size_t j = 0; j < n; ++j) {
        std::uint64_t x = (cfg.sample_seed * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(j) * 0xD1B54A32D192ED03ull);
        x ^= x >> 31;
        x *= 0xBF58476D1CE4E5B9ull;
        x ^= x >> 29;
        x *= 0x94D049BB133111EBull;
        x ^= x >> 32;
        const double u = double(x >> 11) * 0x1p-53;
        const std::size_t lo = std::size_t(double(j) * step), hi = std::max(lo + 1, std::size_t(double(j + 1) * step));
        chosen.push_back(shadow[std::min(ns - 1, lo + std::min(hi - lo - 1, std::size_t(u * double(hi - lo))))]);
    }
    return chosen;
}

std::vector<std::uint8_t> simulated_groups(const SimConfig& cfg, const SimOptions& opt, std::uint32_t primary,
                                           std::uint32_t total) {
    const std::vector<Host::Pass> passes =
        Host::plan(Host::Params{cfg.iccs, cfg.pass_overhead_cycles, cfg.overlap_passes}, primary, total);
    std::vector<std::uint8_t> read(total, 0);
    for (std::uint32_t i : choose_passes(passes, cfg, opt))
        for (std::uint32_t g = passes[i].begin; g < passes[i].end; ++g) read[g] = 1;
    return read;
}

bool Top::wrong_rti_decided(const Host::Pass& pass, bool chosen) {
    // The fault turns the first miss of the faulty ICC's RTI into a hit. The
    // pass it fires in is the first whose group on that ICC has a (ray,
    // triangle) pair that misses: the pairs are every triangle of a kept
    // sphere with the rays of its row and column masks, as the Ray Data
    // Fetcher issues them (which of them misses first is the pass's own
    // business, simulated by whoever simulates that pass). Passes are asked
    // in order until one decides.
    const std::uint32_t k = cfg_.fault_icc;
    auto has_miss = [&](const TraceGroup& g) {
        auto unit = functional_.make_unit();
        unit->load(g);
        for (const SphereHitRec& rec : unit->sphere_hits())
            for (std::uint32_t tri = trace_.first_tri[rec.sphere]; tri < trace_.first_tri[rec.sphere] + trace_.tri_count[rec.sphere]; ++tri)
                for (std::uint64_t rm = rec.rows; rm; rm &= rm - 1)
                    for (std::uint64_t cm = rec.cols; cm; cm &= cm - 1) {
                        double t;
                        const std::uint32_t ray = std::uint32_t(__builtin_ctzll(rm)) * g.n + std::uint32_t(__builtin_ctzll(cm));
                        if (!unit->rti(ray, tri, t)) return true;
                    }
        return false;
    };
    const std::uint32_t gi = pass.begin + k;
    if (gi >= pass.end || !has_miss(groups_.group(gi))) return false;
    if (!chosen) iccs[k].disarm_wrong_rti();
    return true;
}

void Top::extrapolate(const std::vector<Host::Pass>& passes) {
    // Primary passes are all simulated; the shadow total is N times the mean
    // of the n sampled shadow passes, with the finite-population standard
    // error of a simple random sample, N s / sqrt(n) sqrt(1 - n/N) (for one
    // pass per stratum usually an overestimate).
    std::uint64_t primary = 0;
    std::vector<double> sample;
    for (std::size_t k = 0; k < result_.pass_index.size(); ++k)
        if (passes[result_.pass_index[k]].primary)
            primary += result_.pass_cycles[k];
        else
            sample.push_back(double(result_.pass_cycles[k]));
    double ns = 0;
    for (const auto& p : passes) ns += !p.primary;
    const double n = double(sample.size());
    double mean = 0, var = 0;
    for (double c : sample) mean += c / n;
    for (double c : sample) var += (c - mean) * (c - mean) / (n - 1);
    result_.total_cycles = primary + std::uint64_t(std::llround(ns * mean));
    result_.estimate_ci95 = 1.96 * ns * std::sqrt(var / n) * std::sqrt(std::max(0.0, 1 - n / ns));
    result_.estimated = true;
}

void Top::run() {
    model_thread_ = std::this_thread::get_id();
    const double cpu0 = thread_cpu_s();
    try {
        run_passes();
    } catch (const std::exception& e) {
        error_ = e.what();
    }
    // (every load has ended: the next pass's is waited for before run_passes returns)
    if (netlist_) sc_core::sc_stop();  // (its clock would run on)
    result_.loads_cpu_s = 1e-9 * double(loads_cpu_ns_.load());
    result_.model_cpu_s = std::max(0.0, thread_cpu_s() - cpu0 - 1e-9 * double(loads_cpu_model_ns_.load()));
    // sc_start() returns when no event is left. The thread parks here for good
    // rather than returning: a returning thread's last switch (QuickThreads
    // abort) is not reported to AddressSanitizer by Debian's SystemC 2.3.4,
    // which then keeps this coroutine's freed stack as the main thread's stack
    // and crashes LeakSanitizer at exit. wait() with no static sensitivity
    // never resumes.
    wait();
}

void Top::run_passes() {
    const bool bound = cfg_.estimate == Estimate::fifo_bound;
    // The host's plan: the primary passes, and the shadow passes once the
    // source knows how many groups there are (a stream: once the front end
    // has traced every primary group). A plan of the primary passes alone is
    // the whole plan's start, and so is the choice of passes in it.
    std::vector<Host::Pass> passes;
    std::vector<std::uint32_t> chosen;
    bool planned_all = false;
    auto source_stopped = [&] {
        const std::string why = groups_.failure_message();
        error_ = why.empty() ? "the ray groups ended early" : why;
    };
    auto make_plan = [&](bool all) {
        planned_all = all;
        passes = host.plan(trace_.primary_groups, all ? std::uint32_t(groups_.total_groups()) : trace_.primary_groups);
        chosen = choose_passes(passes, cfg_, opt_);
    };
    make_plan(groups_.total_known());
    bool wrong_rti_pending = cfg_.fault == Fault::wrong_rti && opt_.shards > 1;
    std::uint64_t total = 0;
    // Pass i uses buffer i % 2. With overlapped passes a pass's results are
    // final once the next pass has ended (it waits for them to drain), or at
    // the end of its phase; its groups are released once they are checked.
    std::optional<Host::Pass> unchecked;
    std::uint8_t unchecked_buf = 0;
    std::size_t ci = 0;  // passes simulated so far
    constexpr std::size_t kNone = ~std::size_t(0);
    // A wait for the source, timed (model_waits_s).
    auto timed_wait = [&](auto&& wait) {
        const ScopeWall timed(result_.model_waits_s);
        return wait();
    };
    Worker feeder([] { lower_thread_priority(kFeederNice); });  // the next pass's preload
    std::size_t ahead_pass = kNone;
    for (std::size_t i = 0;; ++i) {
        if (i == passes.size()) {
            if (planned_all) break;
            if (!timed_wait([&] { return groups_.wait_total(); })) {
                source_stopped();
                return;
            }
            make_plan(true);
            if (i == passes.size()) break;
        }
        const Host::Pass pass = passes[i];
        if (!timed_wait([&] { return groups_.wait_for(pass.end); })) {
            source_stopped();
            return;
        }
        const bool is_chosen = ci < chosen.size() && chosen[ci] == i;
        if (wrong_rti_pending && wrong_rti_decided(pass, is_chosen)) wrong_rti_pending = false;
        if (!is_chosen) {
            groups_.release(unchecked ? unchecked->begin : pass.end);
            continue;
        }
        ++ci;
        const std::uint8_t buf = std::uint8_t(i % 2);
        current_pass_ = i;
        std::uint64_t c;
        if (bound) {  // closed form: nothing is simulated or checked
            c = run_pass_bound(pass);
            since_sync_ += c;
        } else {
            {  // (the wait for this pass's groups to be loaded, timed)
                const ScopeWall timed(result_.load_waits_s);
                feeder.wait();
                if (ahead_pass != i) preload(pass, buf);
            }
            // The next pass's groups are loaded into the other buffer (their
            // plane tests computed) on other threads while this pass runs:
            // only without overlapped passes (that buffer is then idle), and
            // only when the groups are there already (it never waits for the
            // front end). Nothing but the wall time changes. (In the trace
            // functional mode a load only unpacks the trace's records: it is
            // made in place, where handing it to another thread would cost more.)
            ahead_pass = kNone;
            if (cfg_.functional == FunctionalMode::compute && !cfg_.overlap_passes && ci < chosen.size() &&
                chosen[ci] < passes.size() && chosen[ci] % 2 != buf && groups_.has(passes[chosen[ci]].end)) {
                ahead_pass = chosen[ci];
                feeder.run([this, next = passes[ahead_pass], nb = std::uint8_t(1 - buf)] { preload(next, nb); });
            }
            c = event_mode_ ? run_pass_event(pass, buf) : run_pass_netlist(pass, buf);
            if (!error_.empty()) break;  // the watchdog fired
            pass_len_ = c;
            end_pass(pass);
            if (unchecked) check_pass(*unchecked, unchecked_buf);
            unchecked.reset();
            if (pass.drain) check_pass(pass, buf);
            else unchecked = pass, unchecked_buf = buf;
        }
        groups_.release(unchecked ? unchecked->begin : pass.end);
        c += cfg_.pass_overhead_cycles;
        result_.pass_cycles.push_back(c);
        result_.pass_index.push_back(std::uint32_t(i));
        total += c;
        if (opt_.progress) opt_.progress(ci, chosen.size(), total);
    }
    if (!error_.empty()) return;
    groups_.release(groups_.total_groups());
    for (auto& icc : iccs) icc.finish_run();
    if (!netlist_) {  // (the netlist's clock has advanced time cycle by cycle)
        if (since_sync_) wait(period_ * double(since_sync_));
        if (cfg_.pass_overhead_cycles) wait(period_ * double(cfg_.pass_overhead_cycles * chosen.size()));
    }
    result_.total_cycles = total;
    if (bound) result_.estimated = result_.lower_bound = true;
    if (cfg_.estimate == Estimate::sample_passes && chosen.size() < passes.size()) extrapolate(passes);
}

void check_trace_reading(const Trace& t, const SimConfig& cfg, const std::string& name) {
    if (cfg.icc.decoder.select == TriangleSelect::any && !t.pairless)
        throw InputError(name + ": made for icc.triangle_select = both, it carries no pair-less spheres; "
                                "icc.triangle_select = any needs a trace from 'raplas trace --triangle-select any'");
}

SimResult simulate(const Trace& trace, const SimConfig& cfg, const SimOptions& opt) {
    TraceSource source(trace);
    return simulate(source, cfg, opt);
}

SimResult simulate(GroupSource& groups, const SimConfig& cfg, const SimOptions& opt) {
    sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
    const Trace& trace = groups.header();
    // fifo_bound reads the sphere hits from the trace and tests nothing.
    const bool bound = cfg.estimate == Estimate::fifo_bound;
    const bool pairless = cfg.icc.decoder.select == TriangleSelect::any;
    check_trace_reading(trace, cfg);
    auto functional =
        Functional::create(trace, cfg.format, bound ? FunctionalMode::trace : cfg.functional, cfg.cull, pairless);
    auto top = std::make_unique<Top>("raplas", cfg, groups, *functional, opt);
    auto t0 = std::chrono::steady_clock::now();
    sc_core::sc_start();
    SimResult r = top->result();
    r.model_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!top->error().empty()) {
        r.error = top->error();
        top.reset();
        if (!opt.vcd_path.empty()) std::remove(opt.vcd_path.c_str());
        return r;
    }
    r.host = top->host.stats();
    r.sphere_link = top->sphere_link.stats();
    r.triangle_link = top->triangle_link.stats();
    r.sphere_memory = top->sphere_memory.stats();
    r.triangle_memory = top->triangle_memory.stats();
    for (auto& c : top->iccs) {
        IccSnapshot s;
        s.icc = c.stats();
        s.sphere_selector = c.sphere_selector.stats();
        s.sphere_fifo = c.sphere_fifo.stats();
        s.planeid_fifo = c.planeid_fifo.stats();
        s.first_tri_fifo = c.first_tri_fifo.stats();
        s.triangle_fifo = c.triangle_fifo.stats();
        s.psi = c.psi.stats();
        s.decoder = c.decoder.stats();
        s.triangle_selector = c.triangle_selector.stats();
        s.ray_data_fetcher = c.ray_data_fetcher.stats();
        s.rti = c.rti.stats();
        s.min_distance.updates = c.min_distance_0.stats().updates + c.min_distance_1.stats().updates;
        s.output = c.output.stats();
        r.iccs.push_back(s);
    }
    top.reset();  // closes and renames the waveform
    r.functional_checked = cfg.functional == FunctionalMode::compute && !bound;
    r.functional_match = r.functional_checked && r.rays_mismatched == 0;
    return r;
}

}  // namespace raplas::model
