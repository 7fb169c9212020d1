// One progress line on stderr for a long phase: redrawn in place on a
// terminal (bar, counts, elapsed time, ETA), and otherwise written as a new
// line only when the counts change (of more than 100 units, when the percent
// done changes), so a log gets one line per step.
#pragma once

#include <chrono>
#include <cstddef>
#include <memory>
#include <mutex>
#include <string>

namespace raplas {

class ProgressLine {
public:
    // on: draw at all; tty: stderr is a terminal.
    ProgressLine(bool on, bool tty) : on_(on), tty_(tty) {}
    // done of total units; eta_done of eta_total units measured for the ETA
    // (units done in this run only: resumed work does not count); `extra` is
    // appended to the counts, `unit` names them.
    void draw(std::size_t done, std::size_t total, const std::string& unit, const std::string& extra,
              std::size_t eta_done, std::size_t eta_total);
    // Prints `text` (whole lines) above the progress line.
    void message(const std::string& text);
    // Ends the line on a terminal.
    void finish();
    double elapsed() const;

private:
    void clear();
    bool on_, tty_;
    bool drawn_ = false;
    std::string last_;
    std::size_t last_percent_ = 0;
    std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
};

// The front end's progress (FrameOptions::progress): one ProgressLine per
// phase, so that each phase's elapsed time and ETA are its own.
class PhaseProgress {
public:
    PhaseProgress(bool on, bool tty) : on_(on), tty_(tty) {}
    void operator()(const char* phase, std::size_t done, std::size_t total);
    void finish();

private:
    bool on_, tty_;
    std::string phase_;
    std::unique_ptr<ProgressLine> line_;
};

// A streamed simulation's one progress line: the model's passes (the bar,
// the ETA) and, beside them, the front end's phase as it runs ahead. Both
// threads report; one draws at a time. Not on a terminal, a line is written
// only when the model's count moves (one per percent of a long count).
class StreamProgress {
public:
    explicit StreamProgress(bool tty) : line_(true, tty), tty_(tty) {}
    void front_end(const char* phase, std::size_t done, std::size_t total);
    void model(std::size_t done, std::size_t total, std::uint64_t cycles);
    void finish();

private:
    void draw();
    std::mutex mutex_;
    ProgressLine line_;
    bool tty_;
    std::string phase_;
    std::size_t fe_done_ = 0, fe_total_ = 0, done_ = 0, total_ = 0;
    std::uint64_t cycles_ = 0;
};

}  // namespace raplas
