#include "raplas/app/progress.hpp"

#include <cstdio>

#include "raplas/app/processes.hpp"

namespace raplas {

double ProgressLine::elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
}

void ProgressLine::clear() {
    if (on_ && tty_ && drawn_) std::fputs("\r\033[K", stderr);
    drawn_ = false;
}

void ProgressLine::draw(std::size_t done, std::size_t total, const std::string& unit, const std::string& extra,
                        std::size_t eta_done, std::size_t eta_total) {
    if (!on_) return;
    const double el = elapsed();
    const int width = 24;
    const int fill = total ? int(double(done) / double(total) * width) : width;
    const std::string bar =
        "[" + std::string(std::size_t(fill), '#') + std::string(std::size_t(width - fill), '.') + "]";
    std::string eta = "--";
    if (eta_done) eta = format_duration(el / double(eta_done) * double(eta_total - eta_done));
    else if (eta_total == 0) eta = format_duration(0);
    const std::string counts = std::to_string(done) + "/" + std::to_string(total) + " " + unit + extra;
    const std::string line = bar + " " + counts + ", " + format_duration(el) + " elapsed, ETA " + eta;
    if (tty_) {
        std::fprintf(stderr, "\r%s\033[K", line.c_str());
        drawn_ = true;
    } else {
        // One line per change of the counts, not per clock tick; of a long
        // count, one line per percent.
        if (counts == last_) return;
        if (total > 100 && done != total && done * 100 / total == last_percent_ && !last_.empty()) return;
        last_ = counts;
        last_percent_ = total ? done * 100 / total : 0;
        std::fprintf(stderr, "%s\n", line.c_str());
    }
    std::fflush(stderr);
}

void ProgressLine::message(const std::string& text) {
    clear();
    std::fputs(text.c_str(), stderr);
    std::fflush(stderr);
}

void ProgressLine::finish() {
    if (on_ && tty_ && drawn_) std::fputs("\n", stderr);
    drawn_ = false;
}

void PhaseProgress::operator()(const char* phase, std::size_t done, std::size_t total) {
    if (!on_) return;
    if (!line_ || phase_ != phase) {
        finish();
        line_ = std::make_unique<ProgressLine>(on_, tty_);
        phase_ = phase;
    }
    line_->draw(done, total, "front end " + phase_ + " ray groups", "", done, total);
}

void PhaseProgress::finish() {
    if (line_) line_->finish();
    line_.reset();
}

void StreamProgress::front_end(const char* phase, std::size_t done, std::size_t total) {
    std::lock_guard<std::mutex> lock(mutex_);
    phase_ = phase;
    fe_done_ = done;
    fe_total_ = total;
    if (tty_) draw();
}

void StreamProgress::model(std::size_t done, std::size_t total, std::uint64_t cycles) {
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = done;
    total_ = total;
    cycles_ = cycles;
    draw();
}

void StreamProgress::draw() {
    std::string extra = ", " + std::to_string(cycles_) + " cycles";
    if (!phase_.empty())
        extra += "; front end " + phase_ + " ray groups " + std::to_string(fe_done_) + "/" + std::to_string(fe_total_);
    line_.draw(done_, total_, "model passes", extra, done_, total_);
}

void StreamProgress::finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    line_.finish();
}

}  // namespace raplas
