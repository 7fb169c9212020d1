// Watchdog report: when nothing has moved for sim.watchdog_cycles cycles the
// simulation stops with one line that names the stuck blocks (those holding
// work they do not take), the blocks held behind them, and the FIFO states of
// the ICCs. Both timing modes fill in the same picture.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace raplas::model {

// Fault injection (sim.fault): makes one block of one ICC stop making
// progress, to provoke the watchdog (stuck_*), or gives one wrong answer, to
// provoke the functional check (wrong_rti), or builds that ICC's RTL Triangle
// FIFO from its broken variant, to provoke the RTL co-simulation check
// (rtl_full_early). Off by default.
enum class Fault { none, stuck_rti, stuck_psi, wrong_rti, rtl_full_early };

const char* fault_name(Fault f);

struct IccView {
    std::size_t index = 0;
    std::uint32_t sphere_fifo = 0, sphere_depth = 0;
    std::uint32_t planeid_fifo = 0, planeid_depth = 0;  // the First-Triangle-ID FIFO moves in lockstep
    std::uint32_t triangle_fifo = 0, triangle_depth = 0;
    std::uint32_t decided = 0;   // spheres decided by the Decoder
    bool psi_held = false;       // the Decoder cannot queue a hit: PSI held
    bool back_busy = false;      // Ray Data Fetcher / RTI hold a triangle or pairs
};

struct LinkView {
    std::uint64_t position = 0, end = 0;
};

struct StallPicture {
    std::uint64_t watchdog_cycles = 0, cycle = 0;
    std::size_t pass = 0;
    LinkView sphere_link, triangle_link;
    std::uint32_t triangle_sphere = 0;  // sphere of the triangle at the head of the triangle stream
    std::vector<IccView> iccs;          // the ICCs with a group this pass
    Fault fault = Fault::none;
    std::uint32_t fault_icc = 0;
};

// The one-line report ("watchdog: ..."), FIFO states of at most 8 ICCs.
std::string describe_stall(const StallPicture& p);

}  // namespace raplas::model
