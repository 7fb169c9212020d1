// Sphere Stream Link / Triangle Stream Link: broadcast one record per cycle
// from a memory to every ICC. The broadcast of a record happens in a cycle
// only if every receiving ICC can take it; otherwise nobody receives it and
// the link stalls (paper §3.1: "If one of the FIFOs becomes full, the
// broadcasting operation must be ceased").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace raplas::model {

class StreamLink {
public:
    struct Params {
        std::uint32_t record_bytes = 16;
    };
    struct Stats {
        std::uint64_t records_sent = 0;
        std::uint64_t stall_cycles = 0;   // cycles with a record to send that was held back
        std::uint64_t idle_cycles = 0;    // cycles of a pass with nothing left to send
        std::uint64_t bytes = 0;
        // The stall anatomy (Triangle Stream Link): stalled cycles by how many
        // ICCs' FIFOs held the link in them, in bins 1, 2, 3-4, 5-8, ...,
        // 2049-4096 (held_bin); stalled cycles held by none (only undecided
        // spheres held it) are stall_cycles less their sum.
        static constexpr std::size_t kHeldBins = 13;
        std::uint64_t held_by[kHeldBins] = {};
    };
    // The bin of a stalled cycle held by m >= 1 ICCs' FIFOs, and its name ("1", "2", "3-4", ...).
    static std::size_t held_bin(std::uint64_t m) {
        std::size_t b = 0;  // (the bit width of m - 1)
        for (std::uint64_t v = m ? m - 1 : 0; v; v >>= 1) ++b;
        return b < Stats::kHeldBins ? b : Stats::kHeldBins - 1;
    }
    static std::string held_bin_name(std::size_t b) {
        if (b < 2) return std::to_string(b + 1);
        return std::to_string((std::uint64_t(1) << (b - 1)) + 1) + "-" + std::to_string(std::uint64_t(1) << b);
    }

    explicit StreamLink(const Params& p) : params_(p) {}

    void start_pass(std::uint64_t records) {
        pos_ = 0;
        end_ = records;
    }
    bool has_record() const { return pos_ < end_; }
    std::uint64_t position() const { return pos_; }
    std::uint64_t end() const { return end_; }
    void sent() {
        ++pos_;
        ++stats_.records_sent;
        stats_.bytes += params_.record_bytes;
    }
    void stalled(std::uint64_t cycles = 1) { stats_.stall_cycles += cycles; }
    void idle(std::uint64_t cycles = 1) { stats_.idle_cycles += cycles; }
    // `cycles` stalled cycles in which m ICCs' FIFOs held it (nothing for m = 0).
    void held(std::uint64_t m, std::uint64_t cycles = 1) {
        if (m) stats_.held_by[held_bin(m)] += cycles;
    }
    // Bulk advance used by the event-skipping driver: n records sent back to back.
    void sent_many(std::uint64_t n) {
        pos_ += n;
        stats_.records_sent += n;
        stats_.bytes += n * params_.record_bytes;
    }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    Params params_;
    std::uint64_t pos_ = 0, end_ = 0;
    Stats stats_;
};

}  // namespace raplas::model
