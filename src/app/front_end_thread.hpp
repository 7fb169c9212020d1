// Internal to the app layer: a producer of ray groups (the front end, or a
// trace read as a stream) on its own thread, feeding a GroupStream.
#pragma once

#include <functional>
#include <new>
#include <string>
#include <thread>

#include "raplas/frontend/group_source.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/priority.hpp"

namespace raplas {

// The front end of a streamed run, on its own thread (which starts the
// worker threads), kFeederNice below the model's: its failure is kept as a
// message for the command and handed to the stream, whose waits then stop.
// Joined on destruction, the stream cancelled first so that no worker waits
// for room.
class FrontEndThread {
public:
    FrontEndThread() = default;
    FrontEndThread(const FrontEndThread&) = delete;
    FrontEndThread& operator=(const FrontEndThread&) = delete;
    ~FrontEndThread() {
        if (!thread_.joinable()) return;
        stream_->cancel();
        thread_.join();
    }
    void start(GroupStream& stream, std::function<void()> body) {
        stream_ = &stream;
        thread_ = std::thread([this, body = std::move(body)] {
            lower_thread_priority(kFeederNice);  // (its workers inherit it)
            try {
                body();
            } catch (const GroupStream::Cancelled&) {
                // the model stopped first and says why
            } catch (const InputError& e) {
                stop(e.what(), true);
            } catch (const std::bad_alloc&) {
                stop("out of memory", false);
            } catch (const std::exception& e) {
                stop(e.what(), false);
            }
        });
    }
    void join() {
        if (thread_.joinable()) thread_.join();
    }
    const std::string& error() const { return error_; }
    bool input_error() const { return input_; }

private:
    void stop(const std::string& what, bool input) {
        error_ = what;
        input_ = input;
        stream_->fail(std::current_exception(), "front end: " + what);
    }
    GroupStream* stream_ = nullptr;
    std::thread thread_;
    std::string error_;
    bool input_ = false;
};

// Writes the groups `stream` hands over to `w` as they come, in issue order:
// the header, the groups, TOTAL after the primary ones, then END
// (docs/TRACE.md), releasing each group once written. False when the front
// end stopped first (its FrontEndThread says why); `waited_s` adds the
// seconds spent waiting for it. `written`, if given, is told after each group
// how many are written and of how many (the primary groups until the total
// is known). `observe`, if given, sees the header (group null) and then each
// group as it is written.
bool write_streamed_trace(GroupStream& stream, TraceWriter& w, double& waited_s,
                          const std::function<void(std::uint64_t written, std::uint64_t total)>& written = {},
                          const std::function<void(const Trace& header, const TraceGroup* g)>& observe = {});

}  // namespace raplas
