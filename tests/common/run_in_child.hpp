// `raplas ARGS` in a forked child of the test process: the executable's code
// (raplas::run_cli) without the cost of loading the executable each time, and
// one SystemC simulation per child, as SystemC allows one per process. For
// test binaries whose every test runs in its own process (ctest), so that no
// other thread exists at the fork.
#pragma once

#include <fcntl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "raplas/app/cli.hpp"

namespace raplas_test {

struct Outcome {
    int code = -1;
    std::string out, err;
};

// Runs with `dir` as working directory; stdout and stderr go through files
// beside `dir`, removed afterwards. With `exe` the child executes that
// program instead (the raplas executable: a run that starts raplas processes
// of its own, as a sweep does, needs it).
inline Outcome run_in_child(const std::filesystem::path& dir, const std::vector<std::string>& args,
                            const std::vector<std::pair<std::string, std::string>>& env = {},
                            const char* exe = nullptr) {
    namespace fs = std::filesystem;
    const fs::path out = dir.parent_path() / (dir.filename().string() + ".stdout");
    const fs::path err = dir.parent_path() / (dir.filename().string() + ".stderr");
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (o < 0 || e < 0 || ::dup2(o, 1) < 0 || ::dup2(e, 2) < 0 || ::chdir(dir.c_str()) != 0) ::_exit(125);
        ::unsetenv("RAPLAS_SCENE_PATH");
        ::unsetenv("RAPLAS_MAX_MEMORY");
        for (const auto& [k, v] : env) ::setenv(k.c_str(), v.c_str(), 1);
        std::vector<std::string> storage = {"raplas"};
        storage.insert(storage.end(), args.begin(), args.end());
        std::vector<char*> argv;
        for (auto& s : storage) argv.push_back(s.data());
        argv.push_back(nullptr);
        if (exe) {
            ::execv(exe, argv.data());
            ::_exit(126);
        }
        const int code = raplas::run_cli(int(storage.size()), argv.data());
        std::cout.flush();
        std::cerr.flush();
        std::fflush(nullptr);
        // Ends the child without static destructors or a leak check of the
        // parent's state. The system call, not _exit(): AddressSanitizer
        // warns at any noreturn call after a SystemC simulation (FUZZING.md).
        ::syscall(SYS_exit_group, code);
        std::abort();
    }
    Outcome r;
    int status = 0;
    if (pid < 0 || ::waitpid(pid, &status, 0) != pid) return r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    auto slurp = [](const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    };
    r.out = slurp(out);
    r.err = slurp(err);
    fs::remove(out);
    fs::remove(err);
    return r;
}

}  // namespace raplas_test
