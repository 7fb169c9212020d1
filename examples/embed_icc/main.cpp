// One Intersection Calculation Core of the raplas netlist in a testbench of
// one's own: this file plays the Host, the two Stream Links and the clock,
// drives one pass of one ray group through the ICC and checks the nearest
// hits it reads back through the ICC's Output Link.
//
// The scene: a floor at z = 0 made of two triangles (T0, T1) in sphere 0, a
// triangle T2 floating at z = 4 in sphere 1, and a triangle T3 far away in
// sphere 2 that no ray comes near. The group: 4 x 4 rays from (0, 0, 10)
// through the grid x, y = -0.375, -0.125, 0.125, 0.375 at z = 9: ray (h, v),
// through grid point (x, y), meets z = 4 at (6x, 6y) (t = 6) and the floor at
// (10x, 10y) (t = 10).
#include <systemc>

#include <cstdio>
#include <cstdlib>
#include <vector>

#include <raplas/frontend/raygroups.hpp>
#include <raplas/frontend/trace_io.hpp>
#include <raplas/models/netlist/icc_module.hpp>

using namespace raplas;
using namespace raplas::model;
using netlist::LinkRecord;

namespace {

TriangleRec triangle(Vec3f a, Vec3f b, Vec3f c) {
    const Vec3f e1 = b - a, e2 = c - a;
    return {a, e1, e2, cross(e1, e2), b, c};
}

// The wires between a Stream Link and the ICC.
struct LinkWires {
    sc_core::sc_signal<LinkRecord> record;          // the record offered this cycle (a register)
    sc_core::sc_signal<bool> valid, stall, more;    // broadcast, held back; records left after this cycle's
    sc_core::sc_signal<bool> ready;                 // from the ICC: it can take the record
};

// A Stream Link as the ICC sees it: from the start of a pass (`pass`
// changes), records[0], records[1], ... in order, one a cycle at most.
// `valid` is combinational: a record is offered and the ICC is ready for it.
SC_MODULE(StreamLink) {
    sc_core::sc_in<bool> clk, ready;
    sc_core::sc_in<std::uint32_t> pass;
    sc_core::sc_out<LinkRecord> record;
    sc_core::sc_out<bool> valid, stall, more;

    StreamLink(sc_core::sc_module_name n, std::vector<LinkRecord> records)
        : sc_module(n), records_(std::move(records)) {
        SC_METHOD(settle);
        sensitive << record << ready << pass;
        dont_initialize();
        SC_METHOD(tick);
        sensitive << clk.pos() << pass;
        dont_initialize();
    }
    void bind(sc_core::sc_clock& c, sc_core::sc_signal<std::uint32_t>& p, LinkWires& w) {
        clk(c);
        pass(p);
        record(w.record);
        valid(w.valid);
        stall(w.stall);
        more(w.more);
        ready(w.ready);
    }
    bool done() const { return sent_ == records_.size(); }

private:
    SC_HAS_PROCESS(StreamLink);
    void settle() {
        const bool offered = record.read().present, go = offered && ready.read();
        valid.write(go);
        stall.write(offered && !go);
        more.write(sent_ + go < records_.size());
    }
    void tick() {
        if (pass.event()) sent_ = 0;
        else if (valid.read()) ++sent_;
        record.write(done() ? LinkRecord{} : records_[sent_]);
    }
    std::vector<LinkRecord> records_;
    std::size_t sent_ = 0;
};

// The Host: starts the pass, counts its cycles until both links have sent
// everything and the ICC has drained, then reads the group's nearest hits.
SC_MODULE(Host) {
    sc_core::sc_in<bool> clk;
    sc_core::sc_in<netlist::BufMask> fetcher_busy, rti_busy;
    sc_core::sc_out<std::uint32_t> pass;
    std::vector<Hit> hits;
    std::uint64_t cycles = 0;

    Host(sc_core::sc_module_name n, netlist::IccModule& icc, const StreamLink& spheres, const StreamLink& triangles,
         const TraceGroup& group)
        : sc_module(n), icc_(icc), spheres_(spheres), triangles_(triangles), group_(group) {
        SC_THREAD(run);
    }

private:
    SC_HAS_PROCESS(Host);
    void run() {
        icc_.host->start_pass(&group_, /*buffer*/ 0, /*overlap*/ false);  // loads its rays and planes
        pass.write(1);
        do {
            wait(clk.posedge_event());
            wait(sc_core::SC_ZERO_TIME);  // the edge's registers settle
            ++cycles;
        } while (!(spheres_.done() && triangles_.done() && fetcher_busy.read() == 0 && rti_busy.read() == 0 &&
                   icc_.triangle_fifo_status->empty()));
        hits = icc_.results->results(group_, 0);  // through its Output Link
        sc_core::sc_stop();
        wait();  // (parks: nothing notifies it)
    }
    netlist::IccModule& icc_;
    const StreamLink &spheres_, &triangles_;
    const TraceGroup& group_;
};

}  // namespace

int sc_main(int, char*[]) {
    // Sphere Memory and Triangle Memory: each sphere's triangles are consecutive.
    Trace scene;
    scene.format = NumFormat::float32();
    scene.triangles = {triangle({-5, -5, 0}, {2.5f, -5, 0}, {-5, 5, 0}),     // T0: the floor, 4x + 3y < -5
                       triangle({2.5f, -5, 0}, {2.5f, 5, 0}, {-5, 5, 0}),    // T1: the floor, 4x + 3y > -5
                       triangle({-1, -1, 4}, {3, -1, 4}, {-1, 3, 4}),        // T2: x, y > -1, x + y < 2
                       triangle({50, 50, 0}, {51, 50, 0}, {50, 51, 0})};     // T3: far away
    scene.spheres = {{{-1.25f, 0, 0}, 6.25f}, {{1, 1, 4}, 3}, {{50.5f, 50.5f, 0}, 1}};
    scene.first_tri = {0, 2, 3};
    scene.tri_count = {2, 1, 1};

    // The ray group: its origin, grid and 2N planes (the host's work).
    RayGroup rays;
    rays.n = 4;
    rays.origin = {0, 0, 10};
    rays.grid_corner = {-0.5, -0.5, 9};
    rays.du = {0.25, 0, 0};
    rays.dv = {0, 0.25, 0};
    rays.tmax = 1e30f;
    rays.row_valid = rays.col_valid = 0xf;
    build_planes(rays);
    const TraceGroup group = trace_group(std::move(rays), GroupResult{}, false);

    // What the links broadcast: a sphere's index and triangle range; a triangle's sphere.
    std::vector<LinkRecord> sphere_records, triangle_records;
    for (std::uint32_t s = 0; s < scene.spheres.size(); ++s) {
        sphere_records.push_back({true, s, s, scene.first_tri[s], scene.tri_count[s]});
        for (std::uint32_t t = scene.first_tri[s]; t < scene.first_tri[s] + scene.tri_count[s]; ++t)
            triangle_records.push_back({true, t, s, 0, 0});
    }

    // The ICC: the paper's blocks with their default parameters, computing
    // its answers with the scene's float32 records.
    const Icc::Params params;
    const auto functional = Functional::create(scene, scene.format, FunctionalMode::compute);
    netlist::IccModule icc("icc", params, *functional);

    const sc_core::sc_time period(2.5, sc_core::SC_NS);  // 400 MHz; the first edge after one period
    sc_core::sc_clock clock("clock", period, 0.5, period, true);
    sc_core::sc_signal<std::uint32_t> pass("pass");
    sc_core::sc_signal<netlist::BufMask> fetcher_busy("fetcher_busy"), rti_busy("rti_busy");
    LinkWires sphere_wires, triangle_wires;
    StreamLink spheres("sphere_link", sphere_records), triangles("triangle_link", triangle_records);
    spheres.bind(clock, pass, sphere_wires);
    triangles.bind(clock, pass, triangle_wires);
    Host host("host", icc, spheres, triangles, group);
    host.clk(clock);
    host.pass(pass);
    host.fetcher_busy(fetcher_busy);
    host.rti_busy(rti_busy);

    // The ICC's ports (its exports host, results and triangle_fifo_status
    // are bound inside it: the Host calls them).
    icc.clk(clock);
    icc.pass(pass);
    icc.sphere_record(sphere_wires.record);
    icc.sphere_valid(sphere_wires.valid);
    icc.sphere_stall(sphere_wires.stall);
    icc.sphere_more(sphere_wires.more);
    icc.sphere_ready(sphere_wires.ready);
    icc.triangle_record(triangle_wires.record);
    icc.triangle_valid(triangle_wires.valid);
    icc.triangle_stall(triangle_wires.stall);
    icc.triangle_ready(triangle_wires.ready);  // (the ICC does not read the triangle link's `more`)
    icc.fetcher_busy(fetcher_busy);
    icc.rti_busy(rti_busy);

    // (no "simulation stopped by user" note at sc_stop)
    sc_core::sc_report_handler::set_actions("/OSCI/SystemC", sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
    sc_core::sc_start();

    // Expected nearest hits, ray (h, v) at index 4v + h: the triangle and t
    // (the floor ends at x = 2.5: column 3, at x = 3.75, misses it).
    const Hit T0{10, 0}, T1{10, 1}, T2{6, 2}, none{0, -1};
    const Hit expected[16] = {T0, T0, T0, none,   // v = 0
                              T0, T2, T2, T2,     // v = 1
                              T0, T2, T2, none,   // v = 2
                              T1, T2, T1, none};  // v = 3
    int wrong = 0;
    for (std::uint32_t i = 0; i < 16; ++i) {
        const Hit& got = host.hits[i];
        const bool ok = got == expected[i];
        wrong += !ok;
        std::printf("ray (%u, %u): triangle %2d at t = %-4g  expected %2d at t = %-4g %s\n", i % 4, i / 4, got.tri,
                    got.tri < 0 ? 0.0 : got.t, expected[i].tri, expected[i].t, ok ? "" : "WRONG");
    }
    // Expected timing. The planes of rows and columns 0-3 cut sphere 0, those
    // of rows and columns 1-3 sphere 1, none sphere 2: 2 x 16 + 3 x 3 = 41
    // ray-triangle tests. Sphere 0 is sent in cycle 0 and decided in cycle
    // 1 + L_psi, T0 is sent the cycle after and reaches the Ray Data Fetcher
    // the next; the RTI then takes the 41 pairs one a cycle (T1 and T2 follow
    // T0 closely enough), and the last result leaves L_rti cycles after it
    // entered: L_psi + 3 + 41 + L_rti cycles (model::simulate of this scene on
    // one ICC counts the same).
    const std::uint64_t tests = icc.state().rti.stats().tests;
    const std::uint64_t expected_cycles = params.psi.stages + 3 + 41 + params.rti.stages;
    std::printf("%llu cycles (expected %llu), %llu ray-triangle tests (expected 41)\n", (unsigned long long)host.cycles,
                (unsigned long long)expected_cycles, (unsigned long long)tests);
    const bool timing_ok = host.cycles == expected_cycles && tests == 41;

    if (wrong == 0 && timing_ok) {
        std::printf("PASS: the 16 nearest hits, the cycles and the tests as expected\n");
        return EXIT_SUCCESS;
    }
    std::printf("FAIL: %d of the 16 nearest hits wrong%s\n", wrong, timing_ok ? "" : "; the cycles or tests differ");
    return EXIT_FAILURE;
}
