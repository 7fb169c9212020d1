// `raplas sweep`: every scene x ICC count x FIFO depth, each point simulated by
// its own `raplas simulate` process (SystemC allows one simulation per
// process). Results live in a work dir, one CSV per point, so a sweep that is
// killed resumes where it stopped (docs/SWEEPS.md).
#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "commands.hpp"
#include "config.hpp"
#include "raplas/app/processes.hpp"
#include "raplas/app/progress.hpp"
#include "raplas/app/sim_report.hpp"
#include "raplas/util/atomic_file.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"

#ifndef RAPLAS_VERSION
#define RAPLAS_VERSION "unknown"
#endif

namespace raplas {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kSpecVersion = 1;

// ---- the sweep -------------------------------------------------------------

struct Input {
    std::string kind;  // "scene", "mesh" or "builtin"
    std::string path;  // as given
    std::string label() const { return kind == "builtin" ? std::string("built-in scene") : path; }
};

struct Point {
    std::size_t input;
    std::uint32_t iccs, fifo;  // 0: the config's value
};

struct Sweep {
    std::vector<Input> inputs;
    std::string config;                                 // as given ("" = defaults)
    std::vector<std::string> scene_sets, config_sets;   // --set, split by what they name
    std::vector<std::string> trace_sets;                // scene sets, then the config's workload
    std::string format;                                 // numerics.format of the config
    std::string triangle_select;                        // icc.triangle_select of the config
    std::vector<std::uint32_t> iccs{0}, fifo{0};
    std::string wd;                                     // absolute
    json spec;

    std::size_t points() const { return inputs.size() * iccs.size() * fifo.size(); }
    Point point(std::size_t i) const {
        return {i / (iccs.size() * fifo.size()), iccs[i / fifo.size() % iccs.size()], fifo[i % fifo.size()]};
    }
    std::string trace_file(std::size_t s) const { return wd + "/trace-" + std::to_string(s) + ".trace"; }
    std::string trace_log(std::size_t s) const { return wd + "/trace-" + std::to_string(s) + ".log"; }
    std::string point_csv(std::size_t i) const { return wd + "/point-" + std::to_string(i) + ".csv"; }
    std::string point_log(std::size_t i) const { return wd + "/point-" + std::to_string(i) + ".log"; }

    std::vector<std::string> trace_argv(std::size_t s) const {
        std::vector<std::string> v{"trace"};
        const Input& in = inputs[s];
        if (in.kind != "builtin") v.insert(v.end(), {"--" + in.kind, in.path});
        for (const auto& x : trace_sets) v.insert(v.end(), {"--set", x});
        v.insert(v.end(), {"--format", format, "--triangle-select", triangle_select, "--out", trace_file(s), "-q"});
        return v;
    }
    std::vector<std::string> point_argv(std::size_t i) const {
        const Point p = point(i);
        std::vector<std::string> v{"simulate", "--trace", trace_file(p.input)};
        if (!config.empty()) v.insert(v.end(), {"--config", config});
        for (const auto& x : config_sets) v.insert(v.end(), {"--set", x});
        if (p.iccs) v.insert(v.end(), {"--iccs", std::to_string(p.iccs)});
        if (p.fifo) v.insert(v.end(), {"--fifo", std::to_string(p.fifo)});
        v.insert(v.end(), {"--csv", point_csv(i), "-q"});
        return v;
    }
    std::string describe(std::size_t i) const {
        const Point p = point(i);
        std::string d = "point " + std::to_string(i) + " (" + inputs[p.input].label();
        d += p.iccs ? ", " + std::to_string(p.iccs) + " ICCs" : std::string(", config ICCs");
        d += p.fifo ? ", FIFO " + std::to_string(p.fifo) : std::string(", config FIFO");
        return d + ")";
    }
};

// The values of --iccs or --fifo (each in range: count_check), each once.
std::vector<std::uint32_t> checked_list(const std::vector<std::uint32_t>& v, const char* opt) {
    if (v.empty()) return {0};
    for (std::size_t i = 0; i < v.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (v[j] == v[i]) throw UsageError(std::string(opt) + ": " + std::to_string(v[i]) + " is given twice");
    return v;
}

// --scene and --mesh in the order they were given.
std::vector<Input> ordered_inputs(const SweepArgs& a) {
    std::vector<Input> in;
    std::size_t si = 0, mi = 0;
    if (a.cmd) {
        const CLI::Option* so = a.cmd->get_option("--scene");
        const CLI::Option* mo = a.cmd->get_option("--mesh");
        for (const CLI::Option* o : a.cmd->parse_order()) {
            if (o == so && si < a.scenes.size()) in.push_back({"scene", a.scenes[si++]});
            else if (o == mo && mi < a.meshes.size()) in.push_back({"mesh", a.meshes[mi++]});
        }
    }
    while (si < a.scenes.size()) in.push_back({"scene", a.scenes[si++]});
    while (mi < a.meshes.size()) in.push_back({"mesh", a.meshes[mi++]});
    if (in.empty()) in.push_back({"builtin", ""});
    return in;
}

// Validates everything a child would reject, so that bad input fails at once.
Sweep make_sweep(const SweepArgs& a, const std::string& wd) {
    Sweep sw;
    sw.inputs = ordered_inputs(a);
    sw.config = a.config;
    sw.iccs = checked_list(a.iccs, "--iccs");
    sw.fifo = checked_list(a.fifo, "--fifo");
    sw.wd = wd;

    ParamSet mp = model::machine_params();
    json config_spec = nullptr;
    if (!a.config.empty()) {
        const std::string path = resolve_config(a.config);
        mp.load_file(path);
        config_spec = {{"path", absolute_path(path)}, {"hash", file_hash(path)}};
    }
    ParamSet sp = scene_params();
    for (const auto& s : a.sets) {
        // The children get whole keys: a last part may name another key in a set alone.
        const auto [set, assignment] = route_assignment(s, {&mp, &sp});
        if (set == 0) {
            mp.set(assignment);
            sw.config_sets.push_back(assignment);
        } else {
            sp.set(assignment);
            sw.scene_sets.push_back(assignment);
        }
    }
    const model::SimConfig cfg = model::config_from_params(mp);
    sw.format = cfg.format.name();
    sw.triangle_select = model::triangle_select_name(cfg.icc.decoder.select);
    sw.trace_sets = sw.scene_sets;
    if (cfg.group_size) sw.trace_sets.push_back("groups.size=" + std::to_string(cfg.group_size));
    if (cfg.shadow_group_size) sw.trace_sets.push_back("groups.shadow_size=" + std::to_string(cfg.shadow_group_size));
    if (cfg.triangles_per_sphere)
        sw.trace_sets.push_back("spheres.triangles_per_sphere=" + std::to_string(cfg.triangles_per_sphere));

    json inputs = json::array();
    for (Input& in : sw.inputs) {
        if (in.kind == "builtin") {
            inputs.push_back({{"kind", "builtin"}});
            continue;
        }
        if (in.kind == "scene") in.path = find_scene_file(in.path);
        if (!is_file(in.path)) throw InputError(in.path + ": no such file");
        if (in.kind == "scene") {
            ParamSet check = scene_params();
            check.load_file(in.path);
        }
        inputs.push_back({{"kind", in.kind}, {"path", absolute_path(in.path)}, {"hash", file_hash(in.path)}});
    }
    sw.spec = {{"sweep_format", kSpecVersion},
               {"raplas", RAPLAS_VERSION},
               {"inputs", inputs},
               {"config", config_spec},
               {"sets", a.sets},
               {"iccs", a.iccs},
               {"fifo", a.fifo},
               {"points", sw.points()}};
    return sw;
}

// ---- the work dir ------------------------------------------------------------

std::string spec_path(const std::string& wd) { return wd + "/sweep.json"; }

json read_spec(const std::string& wd) {
    const std::string path = spec_path(wd);
    if (!is_file(path)) throw InputError(wd + ": not a sweep work dir (no sweep.json)");
    json j;
    try {
        j = json::parse(read_file(path));
    } catch (const json::exception&) {
        throw InputError(path + ": not a sweep description (invalid JSON)");
    }
    if (!j.is_object() || !j.contains("points") || !j["points"].is_number_unsigned() || !j.contains("sweep_format"))
        throw InputError(path + ": not a sweep description");
    if (j["sweep_format"] != kSpecVersion)
        throw InputError(path + ": written by another raplas version (sweep_format " + j["sweep_format"].dump() + ")");
    return j;
}

void check_same_sweep(const json& there, const json& here, const std::string& wd) {
    if (there == here) return;
    const std::string lead = spec_path(wd) + ": the work dir holds a different sweep (";
    const std::string tail = "); use another --work-dir or remove it";
    // A file that changed since the sweep started.
    auto changed = [&](const json& a, const json& b) {
        if (a.is_object() && b.is_object() && a.value("path", "") == b.value("path", "") &&
            a.value("hash", "") != b.value("hash", ""))
            throw InputError(lead + a.value("path", "") + " changed since it started" + tail);
    };
    const json ia = there.value("inputs", json::array()), ib = here.value("inputs", json::array());
    if (ia.is_array() && ib.is_array() && ia.size() == ib.size())
        for (std::size_t k = 0; k < ia.size(); ++k) changed(ia[k], ib[k]);
    changed(there.value("config", json()), here.value("config", json()));
    for (const char* key : {"raplas", "inputs", "config", "sets", "iccs", "fifo"}) {
        const json a = there.value(key, json()), b = here.value(key, json());
        if (a != b) throw InputError(lead + key + " " + a.dump() + " there, " + b.dump() + " here" + tail);
    }
    throw InputError(lead.substr(0, lead.size() - 2) + tail.substr(1));
}

// Holds an exclusive lock on the work dir for the life of the process.
struct WorkDirLock {
    int fd = -1;
    explicit WorkDirLock(const std::string& wd) {
        fd = ::open((wd + "/.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0) throw InputError(wd + "/.lock: cannot open: " + std::strerror(errno));
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            ::close(fd);
            throw InputError(wd + ": another raplas sweep is running in this work dir");
        }
    }
    ~WorkDirLock() {
        if (fd >= 0) ::close(fd);
    }
    WorkDirLock(const WorkDirLock&) = delete;
    WorkDirLock& operator=(const WorkDirLock&) = delete;
};

std::vector<std::string> list_dir(const std::string& dir) {
    std::vector<std::string> names;
    if (DIR* d = ::opendir(dir.c_str())) {
        while (const dirent* e = ::readdir(d)) {
            std::string n = e->d_name;
            if (n != "." && n != "..") names.push_back(n);
        }
        ::closedir(d);
    }
    return names;
}

// Removes temporary files ".NAME.tmpPID[.EXT]" (see atomic_file.hpp) that
// start with `prefix` and belong to processes that no longer exist, e.g.
// children of a killed sweep.
void remove_stale_temps(const std::string& dir, const std::string& prefix) {
    for (const auto& n : list_dir(dir)) {
        if (n.size() < 2 || n[0] != '.' || n.rfind(prefix, 0) != 0) continue;
        const auto t = n.rfind(".tmp");
        if (t == std::string::npos || t < 1) continue;
        const char* digits = n.c_str() + t + 4;
        char* end = nullptr;
        const long pid = std::strtol(digits, &end, 10);
        if (end == digits || pid <= 0 || (*end != '\0' && *end != '.')) continue;
        if (::kill(pid_t(pid), 0) != 0 && errno == ESRCH) std::remove((dir + "/" + n).c_str());
    }
}

// Creates or reopens the work dir of `sw` and locks it.
std::unique_ptr<WorkDirLock> open_work_dir(const Sweep& sw) {
    std::error_code ec;
    fs::create_directories(sw.wd, ec);
    if (ec || !fs::is_directory(sw.wd)) throw InputError(sw.wd + ": cannot create the work dir: " + ec.message());
    auto lock = std::make_unique<WorkDirLock>(sw.wd);
    if (is_file(spec_path(sw.wd))) {
        check_same_sweep(read_spec(sw.wd), sw.spec, sw.wd);
    } else {
        for (const auto& n : list_dir(sw.wd))
            if (n != ".lock")
                throw InputError(sw.wd + ": not empty and holds no sweep.json; give a new or empty --work-dir");
        write_file_atomically(spec_path(sw.wd), sw.spec.dump(2) + "\n");
    }
    remove_stale_temps(sw.wd, ".");
    return lock;
}

// ---- results -----------------------------------------------------------------

// Point results in point order; --out is made from them alone.
class Results {
public:
    Results(std::string wd, std::size_t n) : wd_(std::move(wd)), rows_(n) {}

    std::string file(std::size_t i) const { return wd_ + "/point-" + std::to_string(i) + ".csv"; }

    // Reads point i's CSV if it exists; returns whether it does.
    bool load(std::size_t i) {
        const std::string path = file(i);
        if (!is_file(path)) return false;
        const std::string text = read_file(path);
        const auto nl = text.find('\n');
        if (nl == std::string::npos || nl + 1 >= text.size() || text.back() != '\n' ||
            text.find('\n', nl + 1) != text.size() - 1)
            throw InputError(path + ": not a point result (a header and one row); remove it to run the point again");
        const std::string header = text.substr(0, nl + 1);
        if (header_from_ == npos) {
            header_ = header;
            header_from_ = i;
        } else if (header != header_) {
            throw InputError(path + ": columns differ from " + file(header_from_) +
                             " (made by another raplas version?); remove the work dir's point files to redo them");
        }
        rows_[i] = text.substr(nl + 1);
        return true;
    }
    bool has(std::size_t i) const { return rows_[i].has_value(); }
    std::size_t count() const {
        std::size_t n = 0;
        for (const auto& r : rows_) n += r.has_value();
        return n;
    }
    std::string csv() const {
        std::string s = header_from_ == npos ? sim_csv_header() : header_;
        for (const auto& r : rows_)
            if (r) s += *r;
        return s;
    }

private:
    static constexpr std::size_t npos = std::size_t(-1);
    std::string wd_;
    std::vector<std::optional<std::string>> rows_;
    std::string header_;
    std::size_t header_from_ = npos;
};

void check_out_path(const std::string& out) {
    if (out.empty()) throw UsageError("--out: give the result CSV");
    if (fs::is_directory(out)) throw InputError(out + ": is a directory");
    const fs::path parent = fs::absolute(out).parent_path();
    if (!fs::is_directory(parent)) throw InputError(out + ": directory " + parent.string() + " does not exist");
}

void write_out(const std::string& out, const Results& r) { write_file_atomically(out, r.csv()); }

// ---- child processes -----------------------------------------------------------

struct Child {
    pid_t pid = -1;
    bool trace = false;
    std::size_t index = 0;
    std::vector<std::string> argv;
    std::string log;
};

// ---- progress ------------------------------------------------------------------

// The sweep's counts on one ProgressLine.
struct Progress {
    ProgressLine line;
    std::size_t total = 0, done = 0, failed = 0;
    std::size_t traces_total = 0, traces_done = 0;
    std::size_t to_run = 0, run_done = 0;  // points simulated by this run

    Progress(bool on, bool tty) : line(on, tty) {}
    void draw() {
        std::string extra;
        if (traces_done < traces_total)
            extra += ", traces " + std::to_string(traces_done) + "/" + std::to_string(traces_total);
        if (failed) extra += ", " + std::to_string(failed) + " failed";
        line.draw(done, total, "points", extra, run_done, to_run);
    }
    void message(const std::string& m) { line.message(m); }
};

// ---- modes ---------------------------------------------------------------------

int run_sweep(const Sweep& sw, const SweepArgs& a) {
    const auto lock = open_work_dir(sw);
    const std::string out = a.out;
    remove_stale_temps(fs::absolute(out).parent_path().string(), "." + fs::path(out).filename().string() + ".tmp");
    const std::size_t n = sw.points();
    const std::size_t ns = sw.inputs.size();
    Results results(sw.wd, n);

    enum class St { pending, running, done, failed };
    std::vector<St> point(n, St::pending), trace(ns, St::done);
    for (std::size_t i = 0; i < n; ++i)
        if (results.load(i)) {
            point[i] = St::done;
            ::unlink(sw.point_log(i).c_str());
        }
    write_out(out, results);

    Progress pr(a.progress || (::isatty(2) && !a.quiet), ::isatty(2));
    pr.total = n;
    pr.done = results.count();
    for (std::size_t s = 0; s < ns; ++s) {
        bool needed = false;
        for (std::size_t i = 0; i < n; ++i) needed = needed || (point[i] == St::pending && sw.point(i).input == s);
        if (needed && !is_file(sw.trace_file(s))) {
            trace[s] = St::pending;
            ++pr.traces_total;
        }
    }
    pr.to_run = n - pr.done;
    const std::size_t already = pr.done;
    const unsigned jobs = a.jobs ? a.jobs : core_count();

    sigset_t chld, old_mask;
    sigemptyset(&chld);
    sigaddset(&chld, SIGCHLD);
    ::sigprocmask(SIG_BLOCK, &chld, &old_mask);

    const std::string exe = self_exe();
    std::vector<Child> running;
    bool input_failure = false, internal_failure = false;
    auto fail = [&](bool input, const std::string& what, const std::vector<std::string>& argv, const std::string& why,
                    const std::string& log) {
        (input ? input_failure : internal_failure) = true;
        std::vector<std::string> cmd{exe};
        cmd.insert(cmd.end(), argv.begin(), argv.end());
        std::string m = "raplas: " + what + " failed (" + why + "): " + shell_join(cmd) + "\n";
        const std::string line = last_line(log);
        if (!line.empty()) m += "  " + line + "\n";
        m += "  (stderr: " + log + ")\n";
        pr.message(m);
    };
    auto next_task = [&]() -> std::optional<std::pair<bool, std::size_t>> {
        for (std::size_t s = 0; s < ns; ++s)
            if (trace[s] == St::pending) return std::make_pair(true, s);
        for (std::size_t i = 0; i < n; ++i)
            if (point[i] == St::pending && trace[sw.point(i).input] == St::done) return std::make_pair(false, i);
        return std::nullopt;
    };

    pr.draw();
    for (;;) {
        while (running.size() < jobs) {
            const auto t = next_task();
            if (!t) break;
            Child c;
            c.trace = t->first;
            c.index = t->second;
            if (c.trace) {
                c.argv = sw.trace_argv(c.index);
                c.log = sw.trace_log(c.index);
                trace[c.index] = St::running;
            } else {
                c.argv = sw.point_argv(c.index);
                c.log = sw.point_log(c.index);
                point[c.index] = St::running;
            }
            c.pid = spawn_self(c.argv, c.log);
            running.push_back(std::move(c));
        }
        if (running.empty()) break;

        int status = 0;
        const pid_t pid = ::waitpid(-1, &status, WNOHANG);
        if (pid == 0 || (pid < 0 && errno == EINTR)) {
            timespec ts{0, 500000000};
            ::sigtimedwait(&chld, nullptr, &ts);
            pr.draw();
            continue;
        }
        if (pid < 0) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
        auto it = std::find_if(running.begin(), running.end(), [&](const Child& c) { return c.pid == pid; });
        if (it == running.end()) continue;
        Child c = std::move(*it);
        running.erase(it);
        const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
        const bool input = WIFEXITED(status) && WEXITSTATUS(status) == kExitInputError;
        const std::string why = WIFEXITED(status) ? "exit " + std::to_string(WEXITSTATUS(status))
                                                  : "killed by signal " + std::to_string(WTERMSIG(status));
        if (c.trace) {
            if (ok && is_file(sw.trace_file(c.index))) {
                trace[c.index] = St::done;
                ::unlink(c.log.c_str());
            } else {
                trace[c.index] = St::failed;
                std::size_t skipped = 0;
                for (std::size_t i = 0; i < n; ++i)
                    if (point[i] == St::pending && sw.point(i).input == c.index) {
                        point[i] = St::failed;
                        ++skipped;
                    }
                pr.failed += skipped;
                fail(input, "trace of " + sw.inputs[c.index].label() + " (" + std::to_string(skipped) + " points)",
                     c.argv, ok ? "no trace written" : why, c.log);
            }
            ++pr.traces_done;
        } else {
            const bool have = results.load(c.index);
            ++pr.run_done;
            if (have) {
                ++pr.done;
                write_out(out, results);
            }
            if (ok && have) {
                point[c.index] = St::done;
                ::unlink(c.log.c_str());
            } else {
                point[c.index] = St::failed;
                ++pr.failed;
                fail(input, sw.describe(c.index), c.argv, ok ? "no CSV written" : why, c.log);
            }
        }
        pr.draw();
    }
    ::sigprocmask(SIG_SETMASK, &old_mask, nullptr);
    write_out(out, results);
    pr.draw();
    pr.line.finish();

    const double wall = pr.line.elapsed();
    if (!a.quiet) {
        std::printf("sweep: %zu points (%zu simulated, %zu already done, %zu failed) in %.1f s; wrote %s\n", n,
                    pr.run_done, already, pr.failed, wall, out.c_str());
        std::fflush(stdout);
    }
    if (input_failure || internal_failure) {
        std::fprintf(stderr,
                     "raplas: error: %zu of %zu points failed; %s holds %zu rows; run the same command again to retry "
                     "the points without a result\n",
                     pr.failed, n, out.c_str(), results.count());
        return internal_failure ? kExitInternalError : kExitInputError;
    }
    return 0;
}

int emit_jobs(const Sweep& sw, const SweepArgs& a) {
    {
        const auto lock = open_work_dir(sw);
    }
    const std::string exe = self_exe();
    const std::string cd = "cd " + shell_quote(fs::current_path().string()) + " && ";
    auto line = [&](const std::string& product, const std::vector<std::string>& argv) {
        return cd + "{ test -f " + shell_quote(product) + " || " + shell_quote(exe) + " " + shell_join(argv) + "; }\n";
    };
    std::string traces, points;
    for (std::size_t s = 0; s < sw.inputs.size(); ++s) traces += line(sw.trace_file(s), sw.trace_argv(s));
    for (std::size_t i = 0; i < sw.points(); ++i) points += line(sw.point_csv(i), sw.point_argv(i));
    const std::string traces_file = a.emit_jobs + ".traces";
    write_file_atomically(traces_file, traces);
    write_file_atomically(a.emit_jobs, points);
    if (!a.quiet) {
        auto lines = [](std::size_t k) { return std::to_string(k) + (k == 1 ? " command" : " commands"); };
        std::printf("wrote %s (%s) and %s (%s); run the traces first, e.g.\n"
                    "  parallel < %s && parallel < %s\n"
                    "then gather the results (docs/SWEEPS.md):\n"
                    "  %s sweep --merge --work-dir %s --out %s\n",
                    traces_file.c_str(), lines(sw.inputs.size()).c_str(), a.emit_jobs.c_str(),
                    lines(sw.points()).c_str(),
                    shell_quote(traces_file).c_str(), shell_quote(a.emit_jobs).c_str(), shell_quote(exe).c_str(),
                    shell_quote(sw.wd).c_str(), shell_quote(a.out).c_str());
    }
    return 0;
}

int merge(const std::string& wd, const SweepArgs& a, const Sweep* sw) {
    const json spec = read_spec(wd);
    if (sw) check_same_sweep(spec, sw->spec, wd);
    const std::size_t n = spec["points"].get<std::size_t>();
    Results results(wd, n);
    std::vector<std::size_t> missing;
    for (std::size_t i = 0; i < n; ++i)
        if (!results.load(i)) missing.push_back(i);
    write_out(a.out, results);
    if (!missing.empty()) {
        std::string list;
        for (std::size_t k = 0; k < missing.size() && k < 5; ++k)
            list += (k ? ", " : "") + std::string("point-") + std::to_string(missing[k]) + ".csv";
        if (missing.size() > 5) list += ", ...";
        std::fprintf(stderr,
                     "raplas: error: %s: %zu of %zu points have no result (%s); %s holds the %zu finished ones\n",
                     wd.c_str(), missing.size(), n, list.c_str(), a.out.c_str(), n - missing.size());
        return kExitInputError;
    }
    if (!a.quiet) std::printf("merged %zu points from %s into %s\n", n, wd.c_str(), a.out.c_str());
    return 0;
}

}  // namespace

void add_sweep_options(CLI::App* cmd, SweepArgs& a) {
    a.cmd = cmd;
    cmd->add_option("--scene", a.scenes, "scene file (repeatable: a sweep over scenes); default: the built-in scene");
    cmd->add_option("--mesh", a.meshes, "any OBJ file, framed and lit automatically (repeatable)");
    cmd->add_option("--config,-c", a.config, "machine config: a TOML file or the name of a shipped one (paper, fpga)");
    cmd->add_option("--set", a.sets,
                    "override a config or scene key for every point, or by its last part when one key ends in it "
                    "(repeatable)");
    cmd->add_option_function<std::vector<std::string>>(
           "--iccs,-k", [&a](const std::vector<std::string>& v) { a.iccs = count_list(v); },
           "ICC counts, e.g. 1,4,16,32,48 (default: the config's)")
        ->type_name("UINT")
        ->check(count_check(4096, true));
    cmd->add_option_function<std::vector<std::string>>(
           "--fifo,-d", [&a](const std::vector<std::string>& v) { a.fifo = count_list(v); },
           "Sphere and Triangle FIFO depths, e.g. 10,100,1000 (default: the config's)")
        ->type_name("UINT")
        ->check(count_check(100000000, true));
    cmd->add_option("-o,--out", a.out, "result CSV, one row per point in point order")->required();
    cmd->add_option("-j,--jobs", a.jobs, "points simulated at a time (default: number of cores)")
        ->check(CLI::Range(1u, 4096u));
    cmd->add_option("--work-dir", a.work_dir, "traces and per-point results (default: OUT.d)");
    cmd->add_option("--emit-jobs", a.emit_jobs,
                    "write the commands to FILE.traces and FILE (one per line, for GNU parallel or a Slurm array) "
                    "instead of running them");
    cmd->add_flag("--merge", a.merge, "gather the work dir's point results into --out and exit");
    cmd->add_flag("--progress", a.progress, "progress on stderr (default: when stderr is a terminal)");
    cmd->add_flag("-q,--quiet", a.quiet, "no summary on stdout");
}

int cmd_sweep(const SweepArgs& a) {
    check_out_path(a.out);
    const std::string wd = absolute_path(a.work_dir.empty() ? a.out + ".d" : a.work_dir);
    if (a.merge) {
        if (!a.emit_jobs.empty()) throw UsageError("give either --merge or --emit-jobs, not both");
        const bool defines = !a.scenes.empty() || !a.meshes.empty() || !a.config.empty() || !a.sets.empty() ||
                             !a.iccs.empty() || !a.fifo.empty();
        if (!defines) return merge(wd, a, nullptr);
        const Sweep sw = make_sweep(a, wd);
        return merge(wd, a, &sw);
    }
    const Sweep sw = make_sweep(a, wd);
    if (!a.emit_jobs.empty()) return emit_jobs(sw, a);
    return run_sweep(sw, a);
}

}  // namespace raplas
