// Running raplas itself as child processes, and the shell words that name
// such a run in a job list (sweeps; any command that spreads one run over
// processes uses the same).
#pragma once

#include <sys/types.h>

#include <signal.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace raplas {

// `s` as one /bin/sh word (unquoted when it needs no quoting).
std::string shell_quote(const std::string& s);
std::string shell_join(const std::vector<std::string>& argv);
// The running executable's path (/proc/self/exe).
std::string self_exe();
// CPUs this process may run on.
unsigned core_count();
// "m:ss", or "h:mm:ss" from an hour on.
std::string format_duration(double seconds);
// Starts `raplas ARGS` (this very executable) with stdin and stdout on
// /dev/null (stdin on `stdin_fd` when given) and stderr into `log`; the child
// dies with its parent (PR_SET_PDEATHSIG), so a killed run leaves no workers.
// Block SIGCHLD around the calls to wait for it.
pid_t spawn_self(const std::vector<std::string>& args, const std::string& log, int stdin_fd = -1);
// A temporary directory ($TMPDIR, else /tmp) named raplas-NAME-XXXXXX,
// removed with everything in it when this goes; InputError naming `option`
// when it cannot be made.
class TempDir {
public:
    TempDir(const std::string& name, const std::string& option);
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::string& path() const { return path_; }

private:
    std::string path_;
};
// The last non-blank line of a text file ("" if none).
std::string last_line(const std::string& path);
// A child's wait status as "exit N" or "killed by signal N".
std::string exit_text(int status);

// Children `raplas ARGS` (spawn_self), at most `jobs` at a time. SIGCHLD is
// blocked while the pool lives, so that wait() sleeps until a child ends or
// the timeout passes (to redraw a progress line); the destructor restores the
// signal mask. Children that are still running die with the process.
class ProcessPool {
public:
    explicit ProcessPool(unsigned jobs);
    ~ProcessPool();
    ProcessPool(const ProcessPool&) = delete;
    ProcessPool& operator=(const ProcessPool&) = delete;

    bool full() const { return children_.size() >= jobs_; }
    std::size_t running() const { return children_.size(); }
    // Starts a child; `tag` names it when it ends.
    void start(std::size_t tag, const std::vector<std::string>& args, const std::string& log);
    struct Ended {
        std::size_t tag;
        int status;  // as waitpid gives it
    };
    // A child that ended, or nothing when none did within `timeout_s`.
    std::optional<Ended> wait(double timeout_s);

private:
    unsigned jobs_;
    sigset_t chld_, old_mask_;
    std::vector<std::pair<pid_t, std::size_t>> children_;
};

}  // namespace raplas
