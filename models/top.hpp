// The top module (`raplas`): the machine's blocks (Host, Sphere/Triangle
// Memory, the two Stream Links, K ICCs: C++ state machines) and one SystemC
// thread that runs the Host's passes, each stepped by the event engine
// (event_engine.cpp; SystemC time advances every sim.sync_cycles) or by the
// netlist of modules built on those blocks (models/netlist/, one clock).
#pragma once

#include <atomic>
#include <deque>
#include <functional>
#include <memory>
#include <thread>
#include <optional>
#include <string>
#include <vector>

#include <systemc>
#include <tlm>

#include "bucket_queue.hpp"
#include "config.hpp"
#include "host.hpp"
#include "icc.hpp"
#include "raplas/frontend/group_source.hpp"
#include "memories.hpp"
#include "ring_queue.hpp"
#include "stream_link.hpp"
#include "watchdog.hpp"

namespace raplas::model {

namespace netlist {
class Netlist;
template <class Mem>
class MemoryTarget;
}  // namespace netlist

struct IccSnapshot {
    Icc::Stats icc;
    SphereSelector::Stats sphere_selector;
    FifoStats sphere_fifo, planeid_fifo, first_tri_fifo, triangle_fifo;
    PlaneSphereIntersector::Stats psi;
    Decoder::Stats decoder;
    TriangleSelector::Stats triangle_selector;
    RayDataFetcher::Stats ray_data_fetcher;
    RayTriangleIntersector::Stats rti;
    MinDistanceMemory::Stats min_distance;
    OutputLink::Stats output;
};

struct SimResult {
    std::uint64_t total_cycles = 0;         // an estimate when `estimated`
    std::vector<std::uint64_t> pass_cycles;  // of the simulated passes, in order
    std::vector<std::uint32_t> pass_index;   // their indices in the host's plan
    bool estimated = false;
    double estimate_ci95 = 0;  // sample_passes: 95 % confidence half-width of total_cycles, cycles
    bool lower_bound = false;  // fifo_bound: total_cycles is a lower bound of the exact count
    Host::Stats host;
    StreamLink::Stats sphere_link, triangle_link;
    SphereMemory::Stats sphere_memory;
    TriangleMemory::Stats triangle_memory;
    std::vector<IccSnapshot> iccs;
    bool functional_checked = false;
    bool functional_match = false;
    std::uint64_t rays_checked = 0, rays_mismatched = 0;
    // The first ray, in pass order, whose model hit differs from the front end's.
    struct Mismatch {
        std::size_t group = 0;    // index in the trace
        std::uint32_t h = 0, v = 0;  // the ray in its group
        Hit model, frontend;
        bool primary = true;      // the group's kind and pixel
        std::int32_t px = 0, py = 0;
    };
    std::optional<Mismatch> first_mismatch;
    double model_wall_s = 0;  // wall time of the timing model alone
    // CPU time of the model's thread (the group loads it made itself
    // excluded), of the group loads (on every thread), and the wall time the
    // model's thread waited for groups not yet handed over, and for a pass's
    // groups to be loaded (by itself or by the load started a pass ahead).
    double model_cpu_s = 0, loads_cpu_s = 0, model_waits_s = 0, load_waits_s = 0;
    double observers_cpu_s = 0;  // the workload's observers, on their own thread (ObserveAhead)
    // Why the simulation stopped early ("watchdog: ..." or an error inside the
    // model); empty when it finished. Reported here rather than thrown: under
    // AddressSanitizer, Debian's SystemC leaves the main thread's stack
    // bounds wrong after sc_start, and any throw after it warns (FUZZING.md).
    std::string error;
};

struct SimOptions {
    std::string vcd_path;  // empty: no waveform
    // Simulate only the passes of shard `shard` of `shards`: pass p belongs
    // to shard p mod shards (every shards-th pass, so each shard gets its
    // share of primary and shadow passes). Passes are independent (each
    // starts from empty FIFOs and record 0), so the shards' results add up
    // to the whole run's; not with host.overlap_passes, sim.estimate =
    // sample_passes or a waveform.
    std::uint32_t shard = 0, shards = 1;
    // Called after every pass: (passes done, passes total, cycles so far).
    std::function<void(std::size_t, std::size_t, std::uint64_t)> progress;
    // Called after every cycle with the records broadcast in it (-1: none;
    // runs the netlist);
    // for tests and debugging (slows the simulation down).
    std::function<void(const class Top&, std::uint64_t cycle, std::int64_t sphere, std::int64_t tri)> on_cycle;
    // sim.mode = netlist: binds the Sphere (Triangle) Stream Link's TLM-2.0
    // initiator socket to a memory model of the caller's instead of the
    // default target; called during elaboration with the socket and the
    // default target, which holds the records (a model may forward its reads
    // to it); returns the module it made, which the netlist owns.
    // Empty: the default target (docs/MODEL.md §2, "Binding a memory model").
    template <class Target>
    using BindMemory = std::function<std::unique_ptr<sc_core::sc_module>(tlm::tlm_initiator_socket<>& link, Target& memory)>;
    BindMemory<netlist::MemoryTarget<SphereMemory>> bind_sphere_memory;
    BindMemory<netlist::MemoryTarget<TriangleMemory>> bind_triangle_memory;
};

// The passes a run simulates (indices into `passes`, ascending): every one;
// shard `opt.shard` of `opt.shards`; or, under sim.estimate = sample_passes,
// every primary pass and a stratified sample of the shadow passes.
std::vector<std::uint32_t> choose_passes(const std::vector<Host::Pass>& passes, const SimConfig& cfg,
                                         const SimOptions& opt);
// Which of a run's `total` groups (`primary` of them primary) the model
// reads: those of the passes choose_passes() picks (1), not the others (0).
std::vector<std::uint8_t> simulated_groups(const SimConfig& cfg, const SimOptions& opt, std::uint32_t primary,
                                           std::uint32_t total);

class Top : public sc_core::sc_module {
public:
    SC_HAS_PROCESS(Top);
    // The groups come from `groups`, whose header must outlive the module.
    Top(sc_core::sc_module_name n, const SimConfig& cfg, GroupSource& groups, const Functional& f,
        const SimOptions& opt);
    ~Top() override;

    Host host;
    SphereMemory sphere_memory;
    TriangleMemory triangle_memory;
    StreamLink sphere_link;
    StreamLink triangle_link;
    std::deque<Icc> iccs;

    const SimResult& result() const { return result_; }
    const std::string& error() const { return error_; }

private:
    void run();
    // Every pass (or a sample under sim.estimate = sample_passes, or a
    // shard's), simulated, each pass's groups released once checked.
    void run_passes();
    // Pass p with its groups in Ray / Min-distance Memory buffer `buf`:
    // stepped by the event engine (event_engine.cpp), or run by the netlist's Host.
    std::uint64_t run_pass_event(const Host::Pass& p, std::uint8_t buf);
    std::uint64_t run_pass_netlist(const Host::Pass& p, std::uint8_t buf);
    // sim.estimate = fifo_bound: the pass's cycles with unbounded Triangle,
    // PlaneID and First-Triangle-ID FIFOs, in closed form (bound_engine.cpp).
    std::uint64_t run_pass_bound(const Host::Pass& p);
    void preload(const Host::Pass& p, std::uint8_t buf);
    // The extrapolated total from a sample of passes.
    // sim.fault = wrong_rti when not every pass is simulated: the fault fires
    // at the first ray-triangle miss of the faulty ICC in the whole run; a
    // run without that pass must not fire it in a later one. Asked of every
    // pass in order: true when this pass decides (and the fault is disarmed
    // when the pass is not simulated here).
    bool wrong_rti_decided(const Host::Pass& pass, bool chosen);
    void extrapolate(const std::vector<Host::Pass>& passes);
    // The front end's figures of a pass that ended, and the results of a
    // pass whose groups have drained (Output Link; compared with the front
    // end's in compute mode).
    void end_pass(const Host::Pass& p);
    void check_pass(const Host::Pass& p, std::uint8_t buf);
    // The watchdog's one-line report (models/watchdog.hpp) from the active ICCs' states.
    std::string stuck_report(std::uint64_t cycle, const std::vector<IccView>& views) const;
    IccView view_of(const Icc& c, std::size_t k) const;
    std::uint64_t progress_signature() const;
    std::uint64_t block_progress() const;  // its part from the ICCs' blocks
    // One cycle of both Stream Links: send, stall or idle; s/t get the records sent.
    void broadcast(bool s_has, bool s_ok, bool t_has, bool t_ok, std::int64_t& s, std::int64_t& t);
    // Advances SystemC time by the cycles since the last sync and runs the watchdog.
    struct Watch {
        std::uint64_t signature = 0, changed_at = 0;
    };
    // `views` gives the active ICCs' states for the report should the watchdog fire.
    // Returns false when the watchdog fired (error_ holds its report; no
    // exception: none is thrown inside the SystemC thread, whose coroutine
    // stack AddressSanitizer does not follow through an unwind).
    [[nodiscard]] bool sync_time(std::uint64_t cycle, Watch& w, std::uint64_t extra_progress,
                   const std::function<std::vector<IccView>()>& views);
    // The watchdog alone (no time advanced): false when it fired.
    [[nodiscard]] bool watchdog_ok(std::uint64_t cycle, Watch& w, std::uint64_t extra_progress,
                                   const std::function<std::vector<IccView>()>& views);
    std::vector<IccView> active_views() const;
    void setup_vcd();  // --vcd: the netlist's signals

    SimConfig cfg_;
    GroupSource& groups_;
    const Trace& trace_;  // the header: Sphere and Triangle Memory
    const Functional& functional_;
    SimOptions opt_;
    sc_core::sc_time period_;
    SimResult result_;
    std::string error_;
    std::size_t current_pass_ = 0;  // index in the host's plan of the pass being simulated
    // CPU time of the group loads, in ns: on every thread, and on the model's.
    std::atomic<std::uint64_t> loads_cpu_ns_{0}, loads_cpu_model_ns_{0};
    std::thread::id model_thread_;
    std::uint64_t since_sync_ = 0;
    std::uint64_t pass_len_ = 0;

    struct Vcd;
    std::unique_ptr<Vcd> vcd_;
    // sim.mode = netlist: the machine as modules with ports (models/netlist/),
    // and the watchdog's record of the pass it runs.
    std::unique_ptr<netlist::Netlist> netlist_;
    Watch netlist_watch_;
    std::uint64_t netlist_sent_[2] = {0, 0};  // records sent by the links (on_cycle)
    // Event mode: the sphere side shared by every ICC that was never held.
    bool event_mode_ = false;
    std::unique_ptr<SphereFifo> ref_fifo_;
    std::unique_ptr<PlaneSphereIntersector> ref_psi_;
    std::unique_ptr<Decoder> ref_decoder_;
    std::unique_ptr<Fifo<PlaneIdEntry>> ref_planeid_;
    std::unique_ptr<Fifo<FirstTriEntry>> ref_first_tri_;
    std::vector<SphereHitRec> no_hits_;
    // Event mode and fifo_bound: an ICC's back end as a work-conserving queue
    // (FetcherQueue), in the current pass's cycles, with the pop cycles of the
    // triangles still in its Triangle FIFO. Kept from pass to pass when passes
    // overlap, moved to the next pass's cycles by shift_back.
    // One cache line per ICC (a selection reads and writes both parts).
    struct alignas(64) EventBack : FetcherQueue {
        RingQueue starts;
    };
    static_assert(sizeof(EventBack) == 64, "an ICC's Fetcher record in one cache line");
    std::vector<EventBack> event_back_;
    BucketQueue kept_queue_, wait_queue_;  // event mode: ICCs by next kept sphere, by the triangle they wait for
    BucketQueue coast_pop_queue_;          // ... dozing ICCs by the triangle whose take pops their full FIFOs
    static void shift_back(EventBack& b, std::uint64_t by);
    // The shared sphere side at the start of a pass with groups of size n,
    // and one cycle of it after the link decided (the sphere sent, if any,
    // is pushed by the caller): the event mode and fifo_bound step it alike.
    void start_shared_side(std::uint32_t n);
    void tick_shared_side(bool spheres_pending);
    // fifo_bound: per group size N, the cycle in which each triangle is
    // broadcast when only the sphere side can hold the triangle stream (the
    // same in every pass), and the cycle after the last sphere was sent.
    struct BoundSchedule {
        std::uint32_t n = 0;
        std::vector<std::uint64_t> tri_cycle;
        std::uint64_t spheres_sent_by = 0;
    };
    std::vector<BoundSchedule> bound_schedules_;
    const BoundSchedule& bound_schedule(std::uint32_t n);
};

// Throws InputError when the trace cannot serve the configured reading
// (icc.triangle_select = any needs the pair-less spheres).
void check_trace_reading(const Trace& t, const SimConfig& cfg, const std::string& name = "the trace");

// Runs one simulation in this process (SystemC allows one per process).
// Throws InputError for a configuration that cannot run before it starts; a
// run the watchdog stops returns with SimResult::error set.
SimResult simulate(const Trace& trace, const SimConfig& cfg, const SimOptions& opt = {});
// The same with the groups taken from `groups` as the passes need them (and
// released as they are checked): a stream from the front end holds only its
// window.
SimResult simulate(GroupSource& groups, const SimConfig& cfg, const SimOptions& opt = {});

}  // namespace raplas::model
