// Sphere Stream Link / Triangle Stream Link: broadcast one record per cycle
// from a memory to every ICC. The broadcast of a record happens in a cycle
// only if every receiving ICC can take it; otherwise nobody receives it and
// the link stalls (paper §3.1: "If one of the FIFOs becomes full, the
// broadcasting operation must be ceased").
#pragma once

#include <cstdint>
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
    };

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
