#include "raplas/app/processes.hpp"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "raplas/util/error.hpp"

namespace raplas {

std::string shell_quote(const std::string& s) {
    const bool plain = !s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                        "0123456789_./=,:+-@%") == std::string::npos;
    if (plain) return s;
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

std::string shell_join(const std::vector<std::string>& argv) {
    std::string s;
    for (const auto& a : argv) s += (s.empty() ? "" : " ") + shell_quote(a);
    return s;
}

std::string self_exe() {
    char buf[4096];
    const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) throw std::runtime_error(std::string("cannot find the raplas executable: ") + std::strerror(errno));
    return std::string(buf, std::size_t(n));
}

unsigned core_count() {
    cpu_set_t set;
    if (::sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return unsigned(CPU_COUNT(&set));
    return std::max(1u, std::thread::hardware_concurrency());
}

std::string format_duration(double s) {
    const long t = long(s + 0.5);
    char buf[32];
    if (t >= 3600) std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
    else std::snprintf(buf, sizeof buf, "%ld:%02ld", t / 60, t % 60);
    return buf;
}

pid_t spawn_self(const std::vector<std::string>& args, const std::string& log, int stdin_fd) {
    std::vector<std::string> argv{"raplas"};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> cargv;
    for (auto& s : argv) cargv.push_back(s.data());
    cargv.push_back(nullptr);
    const int logfd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (logfd < 0) throw InputError(log + ": cannot write: " + std::strerror(errno));
    const int nullfd = ::open("/dev/null", O_RDWR | O_CLOEXEC);
    const pid_t parent = ::getpid();
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != parent) ::_exit(kExitInternalError);
        if (nullfd >= 0) {
            ::dup2(stdin_fd >= 0 ? stdin_fd : nullfd, 0);
            ::dup2(nullfd, 1);
        }
        ::dup2(logfd, 2);
        sigset_t none;
        sigemptyset(&none);
        ::sigprocmask(SIG_SETMASK, &none, nullptr);
        ::execv("/proc/self/exe", cargv.data());
        const std::string msg =
            std::string("raplas: internal error: cannot run /proc/self/exe: ") + std::strerror(errno) + "\n";
        if (::write(2, msg.data(), msg.size()) < 0) {}
        ::_exit(kExitInternalError);
    }
    const int err = errno;
    ::close(logfd);
    if (nullfd >= 0) ::close(nullfd);
    if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(err));
    return pid;
}

TempDir::TempDir(const std::string& name, const std::string& option) {
    const char* tmp_env = std::getenv("TMPDIR");
    const std::string dir_template = std::string(tmp_env && *tmp_env ? tmp_env : "/tmp") + "/raplas-" + name + "-XXXXXX";
    std::vector<char> buf(dir_template.begin(), dir_template.end());
    buf.push_back('\0');
    if (!::mkdtemp(buf.data()))
        throw InputError(option + ": cannot make a temporary directory " + dir_template + ": " + std::strerror(errno));
    path_ = buf.data();
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

std::string last_line(const std::string& path) {
    std::ifstream in(path);
    std::string line, last;
    while (std::getline(in, line))
        if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
    return last;
}

std::string exit_text(int status) {
    return WIFEXITED(status) ? "exit " + std::to_string(WEXITSTATUS(status))
                             : "killed by signal " + std::to_string(WTERMSIG(status));
}

ProcessPool::ProcessPool(unsigned jobs) : jobs_(std::max(1u, jobs)) {
    sigemptyset(&chld_);
    sigaddset(&chld_, SIGCHLD);
    ::sigprocmask(SIG_BLOCK, &chld_, &old_mask_);
}

ProcessPool::~ProcessPool() { ::sigprocmask(SIG_SETMASK, &old_mask_, nullptr); }

void ProcessPool::start(std::size_t tag, const std::vector<std::string>& args, const std::string& log) {
    children_.emplace_back(spawn_self(args, log), tag);
}

std::optional<ProcessPool::Ended> ProcessPool::wait(double timeout_s) {
    for (;;) {
        int status = 0;
        const pid_t pid = ::waitpid(-1, &status, WNOHANG);
        if (pid < 0 && errno != EINTR) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
        if (pid > 0) {
            const auto it = std::find_if(children_.begin(), children_.end(), [&](const auto& c) { return c.first == pid; });
            if (it == children_.end()) continue;  // not one of ours
            const Ended e{it->second, status};
            children_.erase(it);
            return e;
        }
        if (pid == 0 || errno == EINTR) {
            timespec ts{time_t(timeout_s), long((timeout_s - double(time_t(timeout_s))) * 1e9)};
            if (::sigtimedwait(&chld_, nullptr, &ts) < 0) return std::nullopt;  // timeout (or a signal)
        }
    }
}

}  // namespace raplas
