// simulate --jobs N on one frame (docs/SHARDING.md, "On one machine"): the
// front end runs once, here, and streams its trace to N shard processes,
// whose partial results are merged into exactly the unsharded result.
#include "shard.hpp"
#include "front_end_thread.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <utility>

#include "raplas/app/processes.hpp"
#include "raplas/app/progress.hpp"
#include "raplas/frontend/group_source.hpp"
#include "raplas/util/error.hpp"

namespace raplas {

namespace {

// A shard process that stopped reading its trace (it ended or failed).
struct ShardGone {
    std::size_t shard;
};

// Writes all of [p, p + n) to fd; false when the reader is gone.
bool write_all(int fd, const char* p, std::size_t n) {
    while (n) {
        const ssize_t k = ::write(fd, p, n);
        if (k < 0) {
            if (errno == EINTR) continue;
            return false;  // EPIPE (SIGPIPE ignored meanwhile): the shard ended
        }
        p += k;
        n -= std::size_t(k);
    }
    return true;
}

// SIGPIPE ignored while it lives: a shard that ends early shows as a failed write.
struct IgnoreSigpipe {
    struct sigaction old {};
    IgnoreSigpipe() {
        struct sigaction ign {};
        ign.sa_handler = SIG_IGN;
        ::sigaction(SIGPIPE, &ign, &old);
    }
    ~IgnoreSigpipe() { ::sigaction(SIGPIPE, &old, nullptr); }
};

}  // namespace

int simulate_local_shards(const LocalShards& run, GroupStream& stream, FrontEndThread& frontend) {
    const std::uint32_t n = run.jobs;
    const std::string option = "--jobs " + std::to_string(n);
    const TempDir temp("jobs", option);
    const std::string tag = "-of-" + std::to_string(n);
    std::vector<std::string> parts, logs;
    std::vector<int> pipes;
    std::vector<pid_t> pids;
    struct ClosePipes {
        std::vector<int>& fds;
        ~ClosePipes() {
            for (int& fd : fds)
                if (fd >= 0) ::close(std::exchange(fd, -1));
        }
    } close_pipes{pipes};
    const IgnoreSigpipe ignore_sigpipe;

    // The shards, each reading the trace from a pipe on its stdin.
    for (std::uint32_t i = 0; i < n; ++i) {
        parts.push_back(temp.path() + "/shard-" + std::to_string(i) + tag + ".json");
        logs.push_back(temp.path() + "/shard-" + std::to_string(i) + tag + ".log");
        int fd[2];
        if (::pipe2(fd, O_CLOEXEC) != 0)
            throw std::runtime_error(option + ": cannot make a pipe: " + std::strerror(errno));
        (void)::fcntl(fd[1], F_SETPIPE_SZ, 1 << 20);  // (fewer wake-ups; the default size works too)
        std::vector<std::string> args{"simulate", "--trace", "/dev/stdin"};
        args.insert(args.end(), run.child_args.begin(), run.child_args.end());
        args.insert(args.end(), {"--shard", std::to_string(i) + "/" + std::to_string(n), "--json", parts.back(), "-q",
                                 "--no-workload-hash"});
        try {
            pids.push_back(spawn_self(args, logs.back(), fd[0]));
        } catch (...) {
            ::close(fd[0]);
            ::close(fd[1]);
            throw;
        }
        ::close(fd[0]);
        pipes.push_back(fd[1]);
    }

    // The trace, as the front end makes it, to every shard (each takes its
    // passes and skips the others'; the slowest sets the pace). Each shard
    // holds a window of passes, so the groups handed over lead its simulation
    // by no more: they show the run's progress. The workload hash is folded
    // here, once, not by every shard.
    ProgressLine line(run.progress, run.tty);
    const std::string unit = "ray groups to " + std::to_string(n) + " shards";
    std::optional<std::size_t> gone;
    std::optional<WorkloadTally> tally;
    try {
        TraceWriter w([&](const char* p, std::size_t bytes) {
            for (std::size_t i = 0; i < pipes.size(); ++i)
                if (!write_all(pipes[i], p, bytes)) throw ShardGone{i};
        });
        double waited_s = 0;
        // (false: the front end stopped, and says why below)
        write_streamed_trace(stream, w, waited_s, [&](std::uint64_t done, std::uint64_t total) {
            line.draw(std::size_t(done), std::size_t(total), unit, "", std::size_t(done), std::size_t(total));
        }, [&](const Trace& header, const TraceGroup* g) {
            if (!g) tally.emplace(header, run.pairless);
            else tally->add(*g);
        });
    } catch (const ShardGone& g) {
        gone = g.shard;
        stream.cancel();
    }
    line.finish();
    for (int& fd : pipes) ::close(std::exchange(fd, -1));  // (a shard whose trace ends early fails: it is not reported)
    frontend.join();

    // Every shard's end; the first that failed, if any.
    std::optional<std::size_t> failed;
    std::vector<int> status(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
        while (::waitpid(pids[i], &status[i], 0) < 0)
            if (errno != EINTR) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
        // 0, or 1 for a functional mismatch after its part was written (the merge reports it)
        const bool ok = WIFEXITED(status[i]) && (WEXITSTATUS(status[i]) == 0 ||
                                                 (WEXITSTATUS(status[i]) == 1 && std::filesystem::exists(parts[i])));
        if (!ok && !failed) failed = i;
    }
    if (!frontend.error().empty()) return kFrontEndFailed;  // (the caller reports it)
    if (gone && !failed) failed = *gone;
    if (failed) {
        const std::size_t i = *failed;
        std::string why = last_line(logs[i]);
        for (const char* prefix : {"raplas: error: ", "raplas: internal error: "})
            if (why.rfind(prefix, 0) == 0) why.erase(0, std::strlen(prefix));
        const bool input = WIFEXITED(status[i]) && WEXITSTATUS(status[i]) == kExitInputError;
        std::cerr << "raplas: " << (input ? "error: " : "internal error: ") << "shard " << i << "/" << n << " ("
                  << exit_text(status[i]) << "): " << (why.empty() ? "no message" : why) << "; no result written\n";
        return input ? kExitInputError : kExitInternalError;
    }

    MergeArgs m;
    m.parts = parts;
    m.json = run.json;
    m.csv = run.csv;
    m.quiet = run.quiet;
    m.summary_only = true;
    m.workload_hash = tally && tally->hasher ? tally->hasher->value() : "";  // (none: the merge refuses the parts)
    return cmd_merge(m);
}

}  // namespace raplas
