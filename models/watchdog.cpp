#include "watchdog.hpp"

#include <sstream>

namespace raplas::model {

const char* fault_name(Fault f) {
    switch (f) {
        case Fault::stuck_rti: return "stuck_rti";
        case Fault::stuck_psi: return "stuck_psi";
        case Fault::wrong_rti: return "wrong_rti";
        case Fault::rtl_full_early: return "rtl_full_early";
        case Fault::none: break;
    }
    return "none";
}

namespace {

std::string occupancy(std::uint32_t n, std::uint32_t depth) {
    return std::to_string(n) + "/" + std::to_string(depth) + (n == depth ? " full" : "");
}

void join(std::ostringstream& o, const std::vector<std::string>& items) {
    for (std::size_t i = 0; i < items.size(); ++i) o << (i ? ", " : "") << items[i];
}

}  // namespace

std::string describe_stall(const StallPicture& p) {
    // Nothing moved for watchdog_cycles cycles, so every block that holds
    // work it could take is stuck; blocks that wait on a full FIFO or an
    // undecided sphere are held behind them.
    std::vector<std::string> stuck, held;
    for (const IccView& v : p.iccs) {
        const std::string icc = "icc_" + std::to_string(v.index);
        if (v.back_busy || v.triangle_fifo > 0)
            stuck.push_back(icc + ".rti (takes no ray-triangle pair; triangle_fifo " +
                            occupancy(v.triangle_fifo, v.triangle_depth) + ")");
        if (v.sphere_fifo > 0 && !v.psi_held)
            stuck.push_back(icc + ".psi (takes no sphere; sphere_fifo " + occupancy(v.sphere_fifo, v.sphere_depth) +
                            ")");
        if (v.psi_held) held.push_back(icc + ".psi (planeid_fifo " + occupancy(v.planeid_fifo, v.planeid_depth) + ")");
    }
    auto link = [&](const char* name, const LinkView& l, bool triangle) {
        if (l.position >= l.end) return;
        std::vector<std::string> by;
        for (const IccView& v : p.iccs) {
            const std::string icc = "icc_" + std::to_string(v.index);
            if (!triangle && v.sphere_fifo >= v.sphere_depth) by.push_back(icc + ".sphere_fifo full");
            if (triangle && v.triangle_fifo >= v.triangle_depth) by.push_back(icc + ".triangle_fifo full");
            if (triangle && v.decided <= p.triangle_sphere)
                by.push_back(icc + " has not decided sphere " + std::to_string(p.triangle_sphere));
        }
        std::ostringstream o;
        o << name << " at record " << l.position << "/" << l.end;
        if (by.size() > 3) by.resize(3), by.push_back("...");
        if (!by.empty()) {
            o << " (";
            join(o, by);
            o << ")";
        }
        held.push_back(o.str());
    };
    link("sphere_stream_link", p.sphere_link, false);
    link("triangle_stream_link", p.triangle_link, true);

    std::ostringstream o;
    o << "watchdog: no progress for " << p.watchdog_cycles << " cycles (sim.watchdog_cycles) in pass " << p.pass
      << " at cycle " << p.cycle << "; stuck: ";
    if (stuck.empty()) o << "no block identified";
    else join(o, stuck);
    if (!held.empty()) {
        o << "; held: ";
        join(o, held);
    }
    o << "; FIFOs:";
    std::size_t shown = 0;
    for (const IccView& v : p.iccs) {
        if (shown == 8) {
            o << " (" << p.iccs.size() - shown << " more active ICCs)";
            break;
        }
        o << (shown++ ? ";" : "") << " icc_" << v.index << " sphere_fifo " << occupancy(v.sphere_fifo, v.sphere_depth)
          << ", planeid_fifo " << occupancy(v.planeid_fifo, v.planeid_depth) << ", triangle_fifo "
          << occupancy(v.triangle_fifo, v.triangle_depth) << ", decided " << v.decided;
    }
    if (p.fault != Fault::none)
        o << " [fault injected: sim.fault = " << fault_name(p.fault) << ", sim.fault_icc = " << p.fault_icc << "]";
    return o.str();
}

}  // namespace raplas::model
