// The bad-input table (tests/bad_input/cases.toml, shown in docs/BAD_INPUT.md):
// every case runs the command line in a forked child of this process
// (run_in_child.hpp: without the cost of loading the executable ~150 times) in
// a fresh directory holding the case's files; the test checks the exit code,
// the whole of stderr and that a refused run left no file behind.
// tests/bad_input.py generates the page from the same table and checks it.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <toml++/toml.h>
#include <vector>

#include "raplas/app/cli.hpp"
#include "run_in_child.hpp"
#include "temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using raplas_test::Outcome;
using raplas_test::run_in_child;

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::vector<std::string> expected_lines(const toml::table& c) {
    std::vector<std::string> v;
    if (auto s = c["message"].value<std::string>()) v.push_back(*s);
    else if (auto* a = c["message"].as_array())
        for (const auto& e : *a) v.push_back(e.value_or(std::string()));
    return v;
}

// "..." in an expected line stands for any text.
bool line_matches(const std::string& want, const std::string& got) {
    std::vector<std::string> parts;
    for (std::size_t start = 0;;) {
        const std::size_t dots = want.find("...", start);
        parts.push_back(want.substr(start, dots == std::string::npos ? std::string::npos : dots - start));
        if (dots == std::string::npos) break;
        start = dots + 3;
    }
    if (parts.size() == 1) return got == want;
    if (got.compare(0, parts[0].size(), parts[0]) != 0) return false;
    std::size_t pos = parts[0].size();
    for (std::size_t k = 1; k + 1 < parts.size(); ++k) {
        pos = got.find(parts[k], pos);
        if (pos == std::string::npos) return false;
        pos += parts[k].size();
    }
    const std::string& last = parts.back();
    return got.size() >= pos + last.size() && got.compare(got.size() - last.size(), last.size(), last) == 0;
}

class BadInputTable : public raplas_test::TempDirFixture {
protected:
    std::string valid_trace, both_trace;  // the default (any-plane) trace and one for the row-and-column reading

    BadInputTable() : TempDirFixture("raplas_bad_input") {}
    void SetUp() override {
        TempDirFixture::SetUp();
        if (HasFatalFailure()) return;
        const fs::path d = dir / "trace";
        fs::create_directory(d);
        const Outcome r = run_in_child(d, {"trace", "-q", "-o", "valid.trace", "--set", "image.width=8", "--set",
                                           "image.height=8", "--set", "builtin_detail=0"}, {});
        ASSERT_EQ(r.code, 0) << r.err;
        valid_trace = slurp(d / "valid.trace");
        ASSERT_GT(valid_trace.size(), 32u);
        const Outcome b = run_in_child(d, {"trace", "-q", "-o", "both.trace", "--triangle-select", "both", "--set",
                                           "image.width=8", "--set", "image.height=8", "--set", "builtin_detail=0"},
                                       {});
        ASSERT_EQ(b.code, 0) << b.err;
        both_trace = slurp(d / "both.trace");
        const Outcome o = run_in_child(d, {"trace", "-q", "-o", "other.trace", "--set", "image.width=16", "--set",
                                           "image.height=8", "--set", "builtin_detail=0"}, {});
        ASSERT_EQ(o.code, 0) << o.err;
    }

    // A case's input file (see tests/bad_input.py for the kinds).
    void make_file(const fs::path& p, const toml::node& spec) const {
        if (auto text = spec.value<std::string>()) {
            std::ofstream(p, std::ios::binary) << *text;
            return;
        }
        const toml::table& t = *spec.as_table();
        if (t["dir"].value_or(false)) {
            fs::create_directory(p);
            return;
        }
        if (auto target = t["link"].value<std::string>()) {  // a symbolic link to another of the case's files
            fs::create_symlink(*target, p);
            return;
        }
        std::string data;
        if (auto shard = t["result"].value<std::string>()) {
            // simulate's --json on the valid trace (workload = "other": another
            // scene's): the whole run's, or shard I/N's partial result.
            const fs::path d = dir / "trace";
            const std::string trace = t["workload"].value_or(std::string()) == "other" ? "other.trace" : "valid.trace";
            std::vector<std::string> args{"simulate", "-q", "--trace", (d / trace).string(), "--json", p.string()};
            if (*shard != "whole") args.insert(args.end(), {"--shard", *shard});
            if (const toml::array* more = t["args"].as_array())
                for (const auto& x : *more) args.push_back(x.value_or(std::string()));
            const Outcome r = run_in_child(d, args, {});
            ASSERT_EQ(r.code, 0) << r.err;
            data = slurp(p);
            const std::string edit = t["edit"].value_or(std::string());
            if (edit == "version") {  // written by another raplas
                const std::string key = "\"raplas_version\": \"";
                const std::size_t at = data.find(key);
                ASSERT_NE(at, std::string::npos);
                const std::size_t end = data.find('"', at + key.size());
                data.replace(at + key.size(), end - at - key.size(), "0.0.1");
            } else if (edit == "truncated") {
                data.resize(data.size() / 2);
            } else if (edit == "model") {  // made by a build of other sources
                const std::string key = "\"model\": \"";
                const std::size_t at = data.find(key);
                ASSERT_NE(at, std::string::npos);
                data.replace(at + key.size(), 16, "0123456789abcdef");
            } else {
                ASSERT_EQ(edit, "") << "unknown edit";
            }
        } else if (auto n = t["garbage"].value<std::int64_t>()) {
            std::mt19937 rng(7);
            for (std::int64_t i = 0; i < *n; ++i) data.push_back(char(rng() & 0xff));
            data.push_back('\0');
        } else {
            data = valid_trace;
            const std::string kind = t["trace"].value_or(std::string());
            if (kind == "version") data[8] = 99, data[9] = data[10] = data[11] = 0;
            else if (kind == "edited") data[data.size() / 2] = char(data[data.size() / 2] ^ 1);
            else if (kind == "truncated") data.resize(data.size() / 2);
            else if (kind == "appended") data += "\n";
            else if (kind == "both") data = both_trace;
            else ASSERT_EQ(kind, "valid") << "unknown trace kind";
        }
        std::ofstream(p, std::ios::binary) << data;
    }
};

TEST_F(BadInputTable, EveryCaseGetsItsExitCodeAndWholeStderr) {
    const toml::table table = toml::parse_file(std::string(RAPLAS_SOURCE_DIR) + "/tests/bad_input/cases.toml");
    const toml::array* cases = table["case"].as_array();
    ASSERT_NE(cases, nullptr);
    ASSERT_GT(cases->size(), 50u);
    std::size_t i = 0;
    for (const auto& node : *cases) {
        const toml::table& c = *node.as_table();
        const std::string name = c["input"].value_or(std::string()) + ": " + c["what"].value_or(std::string());
        SCOPED_TRACE(name);
        // rtl = true (false): the case holds in a build with (without) the RTL
        // co-simulation, which Verilator gives; another build leaves it out.
        if (auto rtl = c["rtl"].value<bool>(); rtl && *rtl != bool(RAPLAS_HAVE_RTL)) {
            std::cout << "(left out in this build: " << name << ")\n";
            ++i;
            continue;
        }
        const fs::path case_dir = dir / ("case" + std::to_string(i++));
        fs::create_directory(case_dir);
        if (const toml::table* files = c["files"].as_table())
            for (const auto& [fname, spec] : *files) make_file(case_dir / std::string(fname.str()), spec);
        std::vector<std::pair<std::string, std::string>> env;
        if (const toml::table* e = c["env"].as_table())
            for (const auto& [k, v] : *e) env.emplace_back(std::string(k.str()), v.value_or(std::string()));
        auto args_of = [](const toml::array& a) {
            std::vector<std::string> v;
            for (const auto& x : a) v.push_back(x.value_or(std::string()));
            return v;
        };
        // Commands run first (each must exit with before_exit, default 0), then
        // the files of `change` written over: the state the case's command meets.
        // exec = true: the raplas executable runs the case (a sweep starts raplas processes).
        const char* exe = c["exec"].value_or(false) ? RAPLAS_BINARY : nullptr;
        if (const toml::array* steps = c["before"].as_array())
            for (const auto& step : *steps) {
                const Outcome b = run_in_child(case_dir, args_of(*step.as_array()), env, exe);
                ASSERT_EQ(b.code, int(c["before_exit"].value_or(std::int64_t(0)))) << "a step before: " << b.err;
            }
        std::map<std::string, std::string> inputs;  // every file the case made: no run may change one
        if (const toml::table* change = c["change"].as_table())
            for (const auto& [fname, text] : *change)
                std::ofstream(case_dir / std::string(fname.str()), std::ios::binary) << text.value_or(std::string());
        for (const char* table : {"files", "change"})
            if (const toml::table* files = c[table].as_table())
                for (const auto& [fname, spec] : *files)
                    if (fs::is_regular_file(case_dir / std::string(fname.str())))
                        inputs[std::string(fname.str())] = slurp(case_dir / std::string(fname.str()));
        std::set<std::string> before;
        for (const auto& e : fs::directory_iterator(case_dir)) before.insert(e.path().filename().string());
        const std::vector<std::string> args = args_of(*c["args"].as_array());

        const Outcome r = run_in_child(case_dir, args, env, exe);

        if (const toml::array* absent = c["absent"].as_array())
            for (const auto& x : *absent) inputs.erase(x.value_or(std::string()));  // (removing it is the point)
        for (const auto& [fname, bytes] : inputs)
            EXPECT_TRUE(slurp(case_dir / fname) == bytes) << fname << ": an input file was changed by the run";
        if (const toml::array* absent = c["absent"].as_array()) {
            for (const auto& x : *absent) {
                EXPECT_FALSE(fs::exists(fs::symlink_status(case_dir / x.value_or(std::string()))))
                    << x.value_or(std::string()) << " is still there";
            }
        }

        const int want_code = int(c["exit"].value_or(std::int64_t(-1)));
        EXPECT_EQ(r.code, want_code) << "stderr: " << r.err;
        std::vector<std::string> got;
        std::istringstream in(r.err);
        for (std::string line; std::getline(in, line);) got.push_back(line);
        EXPECT_TRUE(r.err.empty() || r.err.back() == '\n') << r.err;
        const std::vector<std::string> want = expected_lines(c);
        bool same = got.size() == want.size();
        for (std::size_t k = 0; same && k < want.size(); ++k) same = line_matches(want[k], got[k]);
        EXPECT_TRUE(same) << "stderr:\n" << r.err << "expected:\n" << [&] {
            std::string s;
            for (const auto& w : want) s += w + "\n";
            return s;
        }();
        if (want_code == 2) {  // refused: nothing written (a failure, exit 1, may write what it found)
            std::vector<std::string> left;
            for (const auto& e : fs::directory_iterator(case_dir))
                if (!before.count(e.path().filename().string())) left.push_back(e.path().filename().string());
            EXPECT_TRUE(left.empty()) << "a refused run left " << left.size() << " files, first " << left[0];
        }
    }
}

}  // namespace
