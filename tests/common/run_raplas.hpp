// The `raplas` executable in tests: run it in a directory, capture its exit
// code, stdout and stderr; temporary directories; small file helpers.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "temp_dir.hpp"

#ifndef RAPLAS_BINARY
#error "RAPLAS_BINARY must name the raplas executable (tests/CMakeLists.txt)"
#endif

namespace raplas_test {

namespace fs = std::filesystem;

struct RunResult {
    int code = -1;
    std::string out, err;
};

inline std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// `s` as one word for /bin/sh.
inline std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) {
        if (c == '\'') q += "'\\''";
        else q += c;
    }
    return q + "'";
}

inline std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> v;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) v.push_back(line);
    return v;
}

inline std::vector<std::string> plus(std::vector<std::string> a, const std::vector<std::string>& more) {
    a.insert(a.end(), more.begin(), more.end());
    return a;
}

// Runs `raplas ARGS...` in `where`, capturing stdout and stderr.
inline RunResult run_raplas(const fs::path& where, const std::vector<std::string>& args) {
    std::string cmd = "cd " + quoted(where.string()) + " && " + quoted(RAPLAS_BINARY);
    for (const auto& a : args) cmd += " " + quoted(a);
    cmd += " >" + quoted((where / ".stdout").string()) + " 2>" + quoted((where / ".stderr").string());
    RunResult r;
    const int status = std::system(cmd.c_str());
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(where / ".stdout");
    r.err = slurp(where / ".stderr");
    fs::remove(where / ".stdout");
    fs::remove(where / ".stderr");
    return r;
}

// A test with its own temporary directory `dir`, removed afterwards, in which
// run() starts raplas.
class TempDirTest : public TempDirFixture {
protected:
    TempDirTest() : TempDirFixture("raplas_test") {}
    void SetUp() override {
        ASSERT_TRUE(fs::exists(RAPLAS_BINARY)) << RAPLAS_BINARY;
        TempDirFixture::SetUp();
    }
    RunResult run(const std::vector<std::string>& args) const { return run_raplas(dir, args); }
};

}  // namespace raplas_test
