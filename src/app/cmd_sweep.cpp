// `raplas sweep`: every scene x varied key values x ICC count x FIFO depth,
// each point simulated by its own `raplas simulate` process (SystemC allows
// one simulation per process); points that share a workload share one trace.
// Results live in a work dir, one CSV per point, so a sweep that is killed
// resumes where it stopped; the result CSV adds the varied keys, speedup and
// efficiency, and can be checked against a user's reference table
// (docs/SWEEPS.md).
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
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "commands.hpp"
#include "config.hpp"
#include "raplas/app/csv_table.hpp"
#include "raplas/scene/animation.hpp"
#include "sweep_table.hpp"
#include "raplas/app/processes.hpp"
#include "raplas/app/progress.hpp"
#include "raplas/app/sim_report.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/util/atomic_file.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"
#include "raplas/util/input_file.hpp"
#include "raplas/util/run_files.hpp"
#include "model_identity.hpp"

#ifndef RAPLAS_VERSION
#define RAPLAS_VERSION "unknown"
#endif

namespace raplas {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kSpecVersion = 2;  // 2: the model identity and the scenes' mesh files

// ---- the sweep -------------------------------------------------------------

struct Input {
    std::string kind;  // "scene", "mesh" or "builtin"
    std::string path;  // as given
    std::string label() const { return kind == "builtin" ? std::string("built-in scene") : path; }
};

struct TraceJob {
    std::size_t input;
    std::vector<std::string> sets;  // scene --set and --vary values, then the config's workload keys
    std::string format;             // numerics.format
    bool any = false;               // some point needs the pair-less spheres (icc.triangle_select = any)
    bool animated = false;          // an animated scene: its points simulate every frame, with no trace
};

struct Sweep {
    std::vector<Input> inputs;
    std::string config;                                 // as given ("" = defaults)
    std::vector<std::string> scene_sets, config_sets;   // --set, split by what they name
    Layout layout;
    std::vector<TraceJob> traces;
    std::vector<std::size_t> trace_of;                  // per input x combo
    std::vector<char> any_of;                           // per input x combo: icc.triangle_select = any
    std::string wd;                                     // absolute
    std::string trace_dir;                              // where the traces are (wd; --find shares one)
    json spec;
    bool animated = false;                              // some input is animated: rows get the frame columns

    std::size_t points() const { return layout.points(); }
    std::size_t point_trace(std::size_t i) const {
        return trace_of[layout.input(i) * layout.combos() + layout.combo(i)];
    }
    bool point_any(std::size_t i) const { return any_of[layout.input(i) * layout.combos() + layout.combo(i)] != 0; }
    std::string trace_file(std::size_t s) const { return trace_dir + "/trace-" + std::to_string(s) + ".trace"; }
    std::string trace_log(std::size_t s) const { return trace_dir + "/trace-" + std::to_string(s) + ".log"; }
    std::string point_csv(std::size_t i) const { return wd + "/point-" + std::to_string(i) + ".csv"; }
    std::string point_log(std::size_t i) const { return wd + "/point-" + std::to_string(i) + ".log"; }
    std::string failed_csv(std::size_t i) const { return wd + "/point-" + std::to_string(i) + ".failed.csv"; }
    // Written when point i's run failed: "input" or "internal", then why. The
    // point has no result until --retry-failed simulates it again.
    std::string failed_mark(std::size_t i) const { return wd + "/point-" + std::to_string(i) + ".failed"; }

    std::vector<std::string> trace_argv(std::size_t s) const {
        std::vector<std::string> v{"trace"};
        const TraceJob& t = traces[s];
        const Input& in = inputs[t.input];
        if (in.kind != "builtin") v.insert(v.end(), {"--" + in.kind, in.path});
        for (const auto& x : t.sets) v.insert(v.end(), {"--set", x});
        v.insert(v.end(), {"--format", t.format, "--triangle-select", t.any ? "any" : "both", "--out", trace_file(s), "-q"});
        return v;
    }
    std::vector<std::string> point_argv(std::size_t i) const {
        const auto d = layout.digits(i);
        std::vector<std::string> v{"simulate", "--trace", trace_file(point_trace(i))};
        const TraceJob& t = traces[point_trace(i)];
        if (t.animated) {  // the whole animation, each frame traced by the point itself (docs/ANIMATION.md)
            const Input& in = inputs[t.input];
            v = {"simulate"};
            if (in.kind != "builtin") v.insert(v.end(), {"--" + in.kind, in.path});
            for (const auto& x : t.sets) v.insert(v.end(), {"--set", x});
            v.insert(v.end(), {"--frames", "all", "--jobs", "1"});
        }
        if (!config.empty()) v.insert(v.end(), {"--config", config});
        for (const auto& x : config_sets) v.insert(v.end(), {"--set", x});
        for (std::size_t k = 0; k < layout.vary.size(); ++k)
            if (layout.vary[k].config)
                v.insert(v.end(), {"--set", layout.vary[k].key + "=" + layout.vary[k].values[d[k + 1]]});
        const std::uint32_t iccs = layout.iccs[d[d.size() - 2]], fifo = layout.fifo[d.back()];
        if (iccs) v.insert(v.end(), {"--iccs", std::to_string(iccs)});
        if (fifo) v.insert(v.end(), {"--fifo", std::to_string(fifo)});
        v.insert(v.end(), {"--csv", point_csv(i), "-q"});
        if (animated) v.push_back("--animation-row");
        return v;
    }
    std::string describe(std::size_t i) const {
        const auto d = layout.digits(i);
        std::string s = "point " + std::to_string(i) + " (" + inputs[d[0]].label();
        for (std::size_t k = 0; k < layout.vary.size(); ++k)
            s += ", " + layout.vary[k].key + "=" + layout.vary[k].values[d[k + 1]];
        const std::uint32_t iccs = layout.iccs[d[d.size() - 2]], fifo = layout.fifo[d.back()];
        s += iccs ? ", " + std::to_string(iccs) + " ICCs" : std::string(", config ICCs");
        s += fifo ? ", FIFO " + std::to_string(fifo) : std::string(", config FIFO");
        return s + ")";
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

// "V1,V2,A..B": values split at commas outside brackets and quotes; A..B (integers) is every integer
// from A to B.
std::vector<std::string> vary_values(const std::string& key, const std::string& list) {
    const std::string opt = "--vary " + key;
    std::vector<std::string> items;
    std::string cur;
    int depth = 0;
    char quote = 0;
    for (char c : list) {
        if (quote) {
            if (c == quote) quote = 0;
        } else if (c == '"' || c == '\'') {
            quote = c;
        } else if (c == '[') {
            ++depth;
        } else if (c == ']') {
            --depth;
        } else if (c == ',' && depth == 0) {
            items.push_back(trimmed(cur));
            cur.clear();
            continue;
        }
        cur += c;
    }
    items.push_back(trimmed(cur));
    std::vector<std::string> values;
    for (const auto& it : items) {
        if (it.empty()) throw InputError(opt + ": empty value in '" + list + "'");
        const auto dots = it.find("..");
        long long lo = 0, hi = 0;
        if (dots != std::string::npos && parse_int(it.substr(0, dots), lo) && parse_int(it.substr(dots + 2), hi)) {
            if (hi < lo) throw InputError(opt + ": range " + it + " is empty (write the smaller bound first)");
            if (hi - lo >= 10000) throw InputError(opt + ": range " + it + " has more than 10000 values");
            for (long long x = lo; x <= hi; ++x) values.push_back(std::to_string(x));
        } else {
            values.push_back(it);
        }
    }
    for (std::size_t i = 0; i < values.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (values[i] == values[j]) throw InputError(opt + ": value " + values[i] + " is given twice");
    return values;
}

std::string key_of(const std::string& assignment) { return trimmed(assignment.substr(0, assignment.find('='))); }

// Validates everything a child would reject, so that bad input fails at once.
Sweep make_sweep(const SweepArgs& a, const std::string& wd) {
    Sweep sw;
    sw.inputs = ordered_inputs(a);
    sw.config = a.config;
    sw.layout.inputs = sw.inputs.size();
    sw.layout.iccs = checked_list(a.iccs, "--iccs");
    sw.layout.fifo = checked_list(a.fifo, "--fifo");
    sw.wd = wd;
    sw.trace_dir = wd;

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
            check_not_set_by_option(key_of(assignment), !a.iccs.empty(), !a.fifo.empty());
        } else {
            sp.set(assignment);
            sw.scene_sets.push_back(assignment);
        }
    }
    json vary_spec = json::array();
    for (const auto& v : a.vary) {
        const auto eq = v.find('=');
        if (eq == std::string::npos || eq == 0) throw InputError("--vary '" + v + "': expected KEY=V1,V2,... or KEY=A..B");
        Vary x;
        // The key as --set routes it: a config key, else a scene key; a bare last part names the one key ending in it.
        const auto [set, whole] = route_assignment(v.substr(0, eq) + "=", {&mp, &sp}, "--vary");
        x.key = whole.substr(0, whole.size() - 1);
        x.config = set == 0;
        if (x.key == "machine.iccs") throw InputError("--vary machine.iccs: give the ICC counts with --iccs");
        if ((x.key == "fifo.sphere_depth" || x.key == "fifo.triangle_depth") && !a.fifo.empty())
            throw InputError("--vary " + x.key + ": --fifo sets it for every point; vary one or the other");
        for (const auto& s : sw.config_sets)
            if (key_of(s) == x.key) throw InputError("--vary " + x.key + ": also given with --set");
        for (const auto& s : sw.scene_sets)
            if (key_of(s) == x.key) throw InputError("--vary " + x.key + ": also given with --set");
        for (const auto& y : sw.layout.vary)
            if (y.key == x.key) throw InputError("--vary " + x.key + ": given twice");
        x.values = vary_values(x.key, v.substr(eq + 1));
        ParamSet& target = x.config ? mp : sp;
        for (const auto& val : x.values) {
            ParamSet check = target;
            check.set(x.key + "=" + val, "--vary");
        }
        vary_spec.push_back({{"key", x.key}, {"values", x.values}});
        sw.layout.vary.push_back(std::move(x));
    }

    // A key set or varied that changes nothing at any point is refused
    // (docs/BAD_INPUT.md, "Rules"): the reason it is inert, until a point it applies to.
    std::map<std::string, std::pair<std::string, std::string>> inert;  // key -> (option, reason)
    for (const auto& x : sw.config_sets) inert[key_of(x)] = {"--set", ""};
    for (const auto& x : sw.scene_sets) inert[key_of(x)] = {"--set", ""};
    for (const auto& v : sw.layout.vary) inert[v.key] = {"--vary", ""};
    auto note_inert = [&](const ParamSet& m) {
        for (auto it = inert.begin(); it != inert.end();) {
            const bool config = m.has(it->first);
            const std::string why =
                config ? model::inert_config_key(m, it->first) : model::inert_scene_key(m, it->first);
            if (why.empty()) it = inert.erase(it);
            else it++->second.second = why;
        }
    };

    // One trace per distinct workload: input, scene keys, the config's workload and numerics keys.
    const std::size_t combos = sw.layout.combos();
    std::map<std::tuple<std::size_t, std::vector<std::string>, std::string>, std::size_t> trace_index;
    for (std::size_t s = 0; s < sw.inputs.size(); ++s) {
        for (std::size_t c = 0; c < combos; ++c) {
            const auto vi = sw.layout.combo_values(c);
            ParamSet m = mp;
            std::vector<std::string> sets = sw.scene_sets;
            for (std::size_t k = 0; k < sw.layout.vary.size(); ++k) {
                const std::string as = sw.layout.vary[k].key + "=" + sw.layout.vary[k].values[vi[k]];
                if (sw.layout.vary[k].config) m.set(as, "--vary");
                else sets.push_back(as);
            }
            const model::SimConfig cfg = model::config_from_params(m);
            if (s == 0) note_inert(m);
            if (cfg.group_size) sets.push_back("groups.size=" + std::to_string(cfg.group_size));
            if (cfg.shadow_group_size) sets.push_back("groups.shadow_size=" + std::to_string(cfg.shadow_group_size));
            if (cfg.triangles_per_sphere)
                sets.push_back("spheres.triangles_per_sphere=" + std::to_string(cfg.triangles_per_sphere));
            const std::string format = cfg.format.name();
            const bool any = cfg.icc.decoder.select == model::TriangleSelect::any;
            const auto key = std::make_tuple(s, sets, format);
            auto it = trace_index.find(key);
            if (it == trace_index.end()) {
                it = trace_index.emplace(key, sw.traces.size()).first;
                sw.traces.push_back({s, sets, format, any});
            }
            sw.traces[it->second].any = sw.traces[it->second].any || any;
            sw.trace_of.push_back(it->second);
            sw.any_of.push_back(any ? 1 : 0);
        }
    }

    if (!inert.empty()) {
        const auto& [key, why] = *inert.begin();
        throw InputError(why.first + " " + key + ": " + why.second + " at every point of the sweep, so it would change nothing");
    }

    json inputs = json::array();
    for (Input& in : sw.inputs) {
        if (in.kind == "builtin") {
            inputs.push_back({{"kind", "builtin"}});
            continue;
        }
        if (in.kind == "scene") in.path = find_scene_file(in.path);
        if (in.kind == "mesh") check_mesh_option(in.path);
        if (!is_file(in.path)) throw InputError(in.path + ": no such file");
        if (in.kind == "scene") {
            ParamSet check = scene_params();
            check.load_file(in.path);
        }
        json meshes = json::array();
        ParamSet p = scene_params();
        if (in.kind == "scene") p.load_file(in.path);
        for (const auto& x : sw.scene_sets) p.set(x);
        for (const auto& m : scene_mesh_files(p, in.kind == "mesh" ? in.path : ""))
            if (in.kind != "mesh") meshes.push_back({{"path", absolute_path(m)}, {"hash", file_hash(m)}});
        json entry = {{"kind", in.kind}, {"path", absolute_path(in.path)}, {"hash", file_hash(in.path)}};
        if (!meshes.empty()) entry["meshes"] = meshes;
        inputs.push_back(entry);
    }
    // An animated workload: its scene (file and --set/--vary keys) gives an animation key.
    for (TraceJob& t : sw.traces) {
        const Input& in = sw.inputs[t.input];
        ParamSet p = scene_params();
        if (in.kind == "scene") p.load_file(in.path);
        for (const auto& x : t.sets) p.set(x);
        t.animated = animation_keys_given(p);
        sw.animated = sw.animated || t.animated;
    }
    sw.spec = {{"sweep_format", kSpecVersion},
               {"raplas", RAPLAS_VERSION},
               {"model", model_identity()},
               {"inputs", inputs},
               {"config", config_spec},
               {"sets", a.sets},
               {"iccs", a.iccs},
               {"fifo", a.fifo},
               {"points", sw.points()}};
    if (!vary_spec.empty()) sw.spec["vary"] = vary_spec;
    return sw;
}

// The layout a work dir's sweep.json describes (for --merge without the sweep's options).
Layout layout_of(const json& spec, const std::string& path) {
    Layout l;
    try {
        l.inputs = spec.at("inputs").size();
        if (spec.contains("vary"))
            for (const auto& v : spec.at("vary")) {
                Vary x;
                x.key = v.at("key").get<std::string>();
                x.values = v.at("values").get<std::vector<std::string>>();
                if (x.values.empty()) throw std::runtime_error("no values");
                l.vary.push_back(x);
            }
        const auto iccs = spec.at("iccs").get<std::vector<std::uint32_t>>();
        const auto fifo = spec.at("fifo").get<std::vector<std::uint32_t>>();
        if (!iccs.empty()) l.iccs = iccs;
        if (!fifo.empty()) l.fifo = fifo;
    } catch (const std::exception&) {
        throw InputError(path + ": not a sweep description (inputs, vary, iccs or fifo malformed)");
    }
    if (l.inputs == 0 || l.points() != spec["points"].get<std::size_t>())
        throw InputError(path + ": not a sweep description (points do not match inputs, vary, iccs and fifo)");
    return l;
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
    const std::string tail = "); give --fresh to recompute the points it changes, another --work-dir, or remove it";
    if (there.value("model", json()) != here.value("model", json()))
        throw InputError(lead + "raplas's model changed: identity " + there.value("model", json()).dump() + " there, " +
                         here.value("model", json()).dump() + " here" + tail);
    // A file that changed since the sweep started.
    auto changed = [&](const json& a, const json& b) {
        if (a.is_object() && b.is_object() && a.value("path", "") == b.value("path", "") &&
            a.value("hash", "") != b.value("hash", ""))
            throw InputError(lead + a.value("path", "") + " changed since it started" + tail);
    };
    const json ia = there.value("inputs", json::array()), ib = here.value("inputs", json::array());
    if (ia.is_array() && ib.is_array() && ia.size() == ib.size())
        for (std::size_t k = 0; k < ia.size(); ++k) {
            changed(ia[k], ib[k]);
            const json ma = ia[k].value("meshes", json::array()), mb = ib[k].value("meshes", json::array());
            if (ma.is_array() && mb.is_array() && ma.size() == mb.size())
                for (std::size_t m = 0; m < ma.size(); ++m) changed(ma[m], mb[m]);
        }
    changed(there.value("config", json()), here.value("config", json()));
    for (const char* key : {"raplas", "inputs", "config", "sets", "vary", "iccs", "fifo"}) {
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

// Creates or reopens the work dir of `sw` and locks it.
// With `fresh`, a work dir of another sweep keeps only the results its
// changes leave valid: the points of inputs whose files are unchanged when
// only inputs changed, none otherwise.
std::unique_ptr<WorkDirLock> open_work_dir(const Sweep& sw, bool fresh = false) {
    std::error_code ec;
    fs::create_directories(sw.wd, ec);
    if (ec || !fs::is_directory(sw.wd)) throw InputError(sw.wd + ": cannot create the work dir: " + ec.message());
    auto lock = std::make_unique<WorkDirLock>(sw.wd);
    if (is_file(spec_path(sw.wd))) {
        json there;
        try {
            there = read_spec(sw.wd);
        } catch (const InputError&) {
            if (!fresh) throw;
        }
        if (!fresh) check_same_sweep(there, sw.spec, sw.wd);
        if (there != sw.spec) {
            // Which inputs changed; everything when anything but the inputs' files did.
            json a = there, b = sw.spec;
            const json ia = a.is_object() ? a.value("inputs", json()) : json(), ib = b["inputs"];
            bool all = !ia.is_array() || ia.size() != ib.size();
            std::vector<bool> stale(sw.inputs.size(), all);
            if (!all) {
                a.erase("inputs");
                b.erase("inputs");
                all = a != b;
                for (std::size_t k = 0; k < ib.size(); ++k) stale[k] = all || ia[k] != ib[k];
            }
            std::set<std::size_t> traces;
            for (std::size_t s = 0; s < sw.traces.size(); ++s)
                if (stale[sw.traces[s].input]) traces.insert(s);
            for (std::size_t i = 0; i < sw.points(); ++i)
                if (stale[sw.layout.input(i)]) fs::remove(sw.point_csv(i), ec), fs::remove(sw.point_log(i), ec);
            for (std::size_t s : traces) fs::remove(sw.trace_file(s), ec), fs::remove(sw.trace_log(s), ec);
            if (all)  // another layout: results under other numbers too
                remove_files(sw.wd, [](const std::string& n) {
                    return n.rfind("point-", 0) == 0 || n.rfind("trace-", 0) == 0;
                });
            write_file_atomically(spec_path(sw.wd), sw.spec.dump(2) + "\n");
        }
    } else {
        for (const auto& n : list_dir(sw.wd))
            if (n != ".lock")
                throw InputError(sw.wd + ": not empty and holds no sweep.json; give a new or empty --work-dir");
        write_file_atomically(spec_path(sw.wd), sw.spec.dump(2) + "\n");
    }
    remove_stale_temps(sw.wd);  // of every target: children of a killed sweep
    return lock;
}

// ---- results -----------------------------------------------------------------

void check_out_path(const std::string& out) {
    if (out.empty()) throw UsageError("--out: give the result CSV");
    if (fs::is_directory(out)) throw InputError(out + ": is a directory");
    const fs::path parent = fs::absolute(out).parent_path();
    if (!fs::is_directory(parent)) throw InputError(out + ": directory " + parent.string() + " does not exist");
}

CsvTable write_out(const std::string& out, const Results& r, const Layout& l, const Derived& d) {
    CsvTable t = result_table(r, l, d);
    write_file_atomically(out, to_csv(t));
    return t;
}

// What --check and --update need, checked before anything runs.
struct References {
    std::optional<CsvTable> check;
    std::map<std::string, double> tolerance;
};

References references_of(const SweepArgs& a, const Layout& l) {
    References r;
    if (!a.tolerance.empty() && a.check.empty()) throw InputError("--tolerance: give the reference table with --check");
    r.tolerance = tolerances_of(a.tolerance);
    if (!a.check.empty()) {
        r.check = load_reference(a.check, l);
        for (const auto& [c, x] : r.tolerance)
            if (!r.check->column(c)) throw InputError("--tolerance " + c + ": " + a.check + " has no such column");
    }
    if (!a.update.empty()) {
        if (fs::is_directory(a.update)) throw InputError(a.update + ": is a directory");
        const fs::path parent = fs::absolute(a.update).parent_path();
        if (!fs::is_directory(parent))
            throw InputError(a.update + ": directory " + parent.string() + " does not exist");
    }
    return r;
}

// --update and --check on the finished table; returns the exit code they ask for (0 or 1).
int reference_tables(const CsvTable& t, const SweepArgs& a, const References& refs, const Layout& l,
                     bool update = true) {
    if (update && !a.update.empty()) {
        CsvTable u = t;
        u.comments = {" generated by: " + a.command_line, " raplas " + std::string(RAPLAS_VERSION) +
                                                              "; rerun with --update to regenerate, --check to compare"};
        write_file_atomically(a.update, to_csv(u));
        if (!a.quiet) std::printf("wrote the reference table %s (%zu rows)\n", a.update.c_str(), t.rows.size());
    }
    if (a.check.empty()) return 0;
    const std::size_t diffs = check_reference(t, *refs.check, a.check, l, refs.tolerance, a.quiet);
    if (diffs == 0) return 0;
    std::fprintf(stderr, "raplas: error: %s: the sweep differs from the reference table (%zu difference%s, listed on stdout)\n",
                 a.check.c_str(), diffs, diffs == 1 ? "" : "s");
    return kExitInternalError;
}

// ---- child processes -----------------------------------------------------------

struct Child {
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
    const Derived dv = derived_of(a.base_iccs, a.normalize, sw.layout, a.base_fifo);
    const References refs = references_of(a, sw.layout);
    const auto lock = open_work_dir(sw, a.fresh);
    const std::string out = a.out;
    const std::size_t n = sw.points();
    const std::size_t ns = sw.traces.size();
    Results results(sw.wd, n);

    enum class St { pending, running, done, failed };
    std::vector<St> point(n, St::pending), trace(ns, St::done);
    // A point that failed in an earlier run stays failed (the sweep exits
    // non-zero and names it) until --retry-failed simulates it again; a row
    // whose nearest hits differ from the front end's is such a failure too.
    std::vector<std::size_t> failed_before;
    bool input_before = false, internal_before = false;
    auto mark_failed = [&](std::size_t i, bool input, const std::string& why) {
        if (is_file(sw.point_csv(i))) std::rename(sw.point_csv(i).c_str(), sw.failed_csv(i).c_str());
        write_file_atomically(sw.failed_mark(i), std::string(input ? "input" : "internal") + "\n" + why + "\n");
    };
    for (std::size_t i = 0; i < n; ++i) {
        if (results.load(i) && results.mismatched(i)) {
            results.forget(i);
            mark_failed(i, false, "functional mismatch (functional_match = false)");
        }
        if (is_file(sw.failed_mark(i))) {
            if (a.retry_failed) {
                ::unlink(sw.failed_mark(i).c_str());
                ::unlink(sw.failed_csv(i).c_str());
                continue;
            }
            point[i] = St::failed;
            failed_before.push_back(i);
            (read_file(sw.failed_mark(i)).rfind("input", 0) == 0 ? input_before : internal_before) = true;
        } else if (results.has(i)) {
            point[i] = St::done;
            ::unlink(sw.point_log(i).c_str());
        }
    }
    write_out(out, results, sw.layout, dv);

    Progress pr(a.progress || (::isatty(2) && !a.quiet), ::isatty(2));
    pr.total = n;
    pr.done = results.count();
    for (std::size_t s = 0; s < ns; ++s) {
        bool needed = false;
        for (std::size_t i = 0; i < n; ++i) needed = needed || (point[i] == St::pending && sw.point_trace(i) == s);
        if (needed && !sw.traces[s].animated && !is_file(sw.trace_file(s))) {
            trace[s] = St::pending;
            ++pr.traces_total;
        }
    }
    pr.failed = failed_before.size();
    pr.to_run = n - pr.done - pr.failed;
    const std::size_t already = pr.done;
    const unsigned jobs = a.jobs ? a.jobs : core_count();

    std::optional<ProcessPool> pool;
    pool.emplace(jobs);
    const std::string exe = self_exe();
    std::map<std::size_t, Child> running;  // by pool tag
    std::size_t next_tag = 0;
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
    // The workload hash of each trace under each reading its points take,
    // folded here once for all of them (each point would fold it again over
    // the whole trace), given to them as HASH@CONTENT: none for an animated
    // input, or a trace this cannot read (its points say what is wrong).
    struct Folded {
        bool done = false;
        std::string any, both;
    };
    std::vector<Folded> folded(ns);
    auto workload_hash_of = [&](std::size_t i) -> std::string {
        const std::size_t s = sw.point_trace(i);
        Folded& f = folded[s];
        if (sw.traces[s].animated) return "";
        if (!f.done) {
            f.done = true;
            bool need_any = false, need_both = false;
            for (std::size_t j = 0; j < n; ++j)
                if (sw.point_trace(j) == s) (sw.point_any(j) ? need_any : need_both) = true;
            try {
                TraceReader r(sw.trace_file(s));
                std::optional<WorkloadHasher> ha, hb;
                if (need_any) ha.emplace(r.header(), true);
                if (need_both) hb.emplace(r.header(), false);
                TraceGroup g;
                while (r.next(g)) {
                    if (ha) ha->add(g);
                    if (hb) hb->add(g);
                }
                const std::string at = "@" + hex64(r.content_hash());
                if (ha) f.any = ha->value() + at;
                if (hb) f.both = hb->value() + at;
            } catch (const std::exception&) {
            }
        }
        return sw.point_any(i) ? f.any : f.both;
    };
    auto next_task = [&]() -> std::optional<std::pair<bool, std::size_t>> {
        for (std::size_t s = 0; s < ns; ++s)
            if (trace[s] == St::pending) return std::make_pair(true, s);
        for (std::size_t i = 0; i < n; ++i)
            if (point[i] == St::pending && trace[sw.point_trace(i)] == St::done) return std::make_pair(false, i);
        return std::nullopt;
    };

    pr.draw();
    for (;;) {
        while (!pool->full()) {
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
                if (const std::string h = workload_hash_of(c.index); !h.empty())
                    c.argv.insert(c.argv.end(), {"--workload-hash", h});
                c.log = sw.point_log(c.index);
                point[c.index] = St::running;
            }
            pool->start(next_tag, c.argv, c.log);
            running.emplace(next_tag++, std::move(c));
        }
        if (running.empty()) break;

        const auto ended = pool->wait(0.5);
        if (!ended) {
            pr.draw();
            continue;
        }
        Child c = std::move(running.at(ended->tag));
        running.erase(ended->tag);
        const int status = ended->status;
        const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
        const bool input = WIFEXITED(status) && WEXITSTATUS(status) == kExitInputError;
        const std::string why = exit_text(status);
        if (c.trace) {
            if (ok && is_file(sw.trace_file(c.index))) {
                trace[c.index] = St::done;
                ::unlink(c.log.c_str());
            } else {
                trace[c.index] = St::failed;
                std::size_t skipped = 0;
                for (std::size_t i = 0; i < n; ++i)
                    if (point[i] == St::pending && sw.point_trace(i) == c.index) {
                        point[i] = St::failed;
                        ++skipped;
                    }
                pr.failed += skipped;
                fail(input, "trace " + std::to_string(c.index) + " of " + sw.inputs[sw.traces[c.index].input].label() +
                                " (" + std::to_string(skipped) + " points)",
                     c.argv, ok ? "no trace written" : why, c.log);
            }
            ++pr.traces_done;
        } else {
            // A point whose run failed has no result, even when it wrote its
            // row (a functional mismatch does): the row is kept beside it for
            // a look, and the point stays failed until --retry-failed.
            std::string kept;
            if (!ok) {
                if (is_file(sw.point_csv(c.index))) kept = sw.failed_csv(c.index);
                const std::string line = last_line(c.log);
                mark_failed(c.index, input, why + (line.empty() ? "" : ": " + line));
            }
            const bool have = ok && results.load(c.index);
            ++pr.run_done;
            if (have) {
                ++pr.done;
                write_out(out, results, sw.layout, dv);
            }
            if (ok && have) {
                point[c.index] = St::done;
                ::unlink(c.log.c_str());
            } else {
                point[c.index] = St::failed;
                ++pr.failed;
                fail(input, sw.describe(c.index), c.argv,
                     ok ? "no CSV written" : kept.empty() ? why : why + "; its row: " + kept, c.log);
            }
        }
        pr.draw();
    }
    pool.reset();
    const CsvTable table = write_out(out, results, sw.layout, dv);
    pr.draw();
    pr.line.finish();

    const double wall = pr.line.elapsed();
    if (!a.quiet) {
        std::printf("sweep: %zu points (%zu simulated, %zu already done, %zu failed) in %.1f s; wrote %s\n", n,
                    pr.run_done, already, pr.failed, wall, out.c_str());
        std::fflush(stdout);
    }
    for (std::size_t k = 0; k < failed_before.size() && k < 5; ++k) {
        const std::size_t i = failed_before[k];
        std::string why = read_file(sw.failed_mark(i));
        why = why.substr(why.find('\n') + 1);
        while (!why.empty() && why.back() == '\n') why.pop_back();
        std::fprintf(stderr, "raplas: %s failed in an earlier run (%s)\n", sw.describe(i).c_str(), why.c_str());
    }
    if (failed_before.size() > 5) std::fprintf(stderr, "raplas: ... and %zu more\n", failed_before.size() - 5);
    if (input_failure || internal_failure || !failed_before.empty()) {
        if (!a.check.empty()) reference_tables(table, a, refs, sw.layout, false);
        std::fprintf(stderr,
                     "raplas: error: %zu of %zu points failed; %s holds %zu rows; give --retry-failed to simulate "
                     "the failed points again (a plain rerun simulates only the points never run)%s\n",
                     pr.failed, n, out.c_str(), results.count(),
                     a.update.empty() ? "" : (" (" + a.update + " not updated)").c_str());
        return internal_failure || internal_before ? kExitInternalError : kExitInputError;
    }
    return reference_tables(table, a, refs, sw.layout);
}

int emit_jobs(const Sweep& sw, const SweepArgs& a) {
    {
        const auto lock = open_work_dir(sw, a.fresh);
    }
    const std::string exe = self_exe();
    const std::string cd = "cd " + shell_quote(fs::current_path().string()) + " && ";
    auto line = [&](const std::string& product, const std::vector<std::string>& argv) {
        return cd + "{ test -f " + shell_quote(product) + " || " + shell_quote(exe) + " " + shell_join(argv) + "; }\n";
    };
    std::string traces, points;
    std::size_t trace_jobs = 0;
    for (std::size_t s = 0; s < sw.traces.size(); ++s)
        if (!sw.traces[s].animated) traces += line(sw.trace_file(s), sw.trace_argv(s)), ++trace_jobs;
    for (std::size_t i = 0; i < sw.points(); ++i) {
        // A failed point leaves no result (its row, if written, moves aside), so that a rerun retries it.
        const std::string p = shell_quote(sw.point_csv(i)), f = shell_quote(sw.failed_csv(i)),
                          m = shell_quote(sw.failed_mark(i));
        points += cd + "{ test -f " + p + " || { rm -f " + m + " " + f + "; " + shell_quote(exe) + " " +
                  shell_join(sw.point_argv(i)) + "; } || { mv -f " + p + " " + f + " 2>/dev/null; echo internal > " + m +
                  "; false; }; }\n";
    }
    const std::string traces_file = a.emit_jobs + ".traces";
    write_file_atomically(traces_file, traces);
    write_file_atomically(a.emit_jobs, points);
    if (!a.quiet) {
        auto lines = [](std::size_t k) { return std::to_string(k) + (k == 1 ? " command" : " commands"); };
        std::printf("wrote %s (%s) and %s (%s); run the traces first, e.g.\n"
                    "  parallel < %s && parallel < %s\n"
                    "then gather the results (docs/SWEEPS.md):\n"
                    "  %s sweep --merge --work-dir %s --out %s\n",
                    traces_file.c_str(), lines(trace_jobs).c_str(), a.emit_jobs.c_str(),
                    lines(sw.points()).c_str(),
                    shell_quote(traces_file).c_str(), shell_quote(a.emit_jobs).c_str(), shell_quote(exe).c_str(),
                    shell_quote(sw.wd).c_str(), shell_quote(a.out).c_str());
    }
    return 0;
}

int merge(const std::string& wd, const SweepArgs& a, const Sweep* sw) {
    const json spec = read_spec(wd);
    if (sw) check_same_sweep(spec, sw->spec, wd);
    const Layout layout = layout_of(spec, spec_path(wd));
    const Derived dv = derived_of(a.base_iccs, a.normalize, layout, a.base_fifo);
    const References refs = references_of(a, layout);
    const std::size_t n = spec["points"].get<std::size_t>();
    Results results(wd, n);
    std::vector<std::size_t> missing, failed;
    for (std::size_t i = 0; i < n; ++i) {
        const bool have = results.load(i);
        if (have && results.mismatched(i)) results.forget(i);
        if (!results.has(i)) (have || is_file(wd + "/point-" + std::to_string(i) + ".failed") ? failed : missing).push_back(i);
    }
    const CsvTable table = write_out(a.out, results, layout, dv);
    if (!failed.empty()) {
        std::string list;
        for (std::size_t k = 0; k < failed.size() && k < 5; ++k) list += (k ? ", " : "") + std::to_string(failed[k]);
        if (failed.size() > 5) list += ", ...";
        if (!a.check.empty()) reference_tables(table, a, refs, layout, false);
        std::fprintf(stderr,
                     "raplas: error: %s: %zu of %zu points failed (points %s: point-N.failed and point-N.log say "
                     "why); %s holds the %zu finished ones%s\n",
                     wd.c_str(), failed.size(), n, list.c_str(), a.out.c_str(), results.count(),
                     a.update.empty() ? "" : (" (" + a.update + " not updated)").c_str());
        return kExitInternalError;
    }
    if (!missing.empty()) {
        std::string list;
        for (std::size_t k = 0; k < missing.size() && k < 5; ++k)
            list += (k ? ", " : "") + std::string("point-") + std::to_string(missing[k]) + ".csv";
        if (missing.size() > 5) list += ", ...";
        if (!a.check.empty()) reference_tables(table, a, refs, layout, false);
        std::fprintf(stderr,
                     "raplas: error: %s: %zu of %zu points have no result (%s); %s holds the %zu finished ones%s\n",
                     wd.c_str(), missing.size(), n, list.c_str(), a.out.c_str(), n - missing.size(),
                     a.update.empty() ? "" : (" (" + a.update + " not updated)").c_str());
        return kExitInputError;
    }
    if (!a.quiet) std::printf("merged %zu points from %s into %s\n", n, wd.c_str(), a.out.c_str());
    return reference_tables(table, a, refs, layout);
}

// ---- --find: the smallest value of a key that meets a target ------------------

// METRIC>=VALUE or METRIC<=VALUE; METRIC a column of the result table, or
// speedup_vs=SYSTEM: the streaming machine's speedup over memory.system =
// SYSTEM at the same point (SYSTEM's cycles over the streaming machine's).
struct Target {
    std::string metric, vs;
    bool at_least = true;
    double value = 0;
    std::string text;
    bool met(double x) const { return at_least ? x >= value : x <= value; }
};

Target parse_target(const std::string& t) {
    Target g;
    g.text = t;
    const std::size_t ge = t.find(">="), le = t.find("<=");
    const std::size_t at = ge != std::string::npos ? ge : le;
    if (at == std::string::npos || at == 0 || (ge != std::string::npos && le != std::string::npos))
        throw InputError("--target '" + t + "': expected METRIC>=VALUE or METRIC<=VALUE (e.g. efficiency>=0.9)");
    g.at_least = at == ge;
    g.metric = trimmed(t.substr(0, at));
    const std::string v = trimmed(t.substr(at + 2));
    char* end = nullptr;
    g.value = std::strtod(v.c_str(), &end);
    if (v.empty() || *end || !std::isfinite(g.value))
        throw InputError("--target '" + t + "': '" + v + "' is not a number");
    if (g.metric.rfind("speedup_vs=", 0) == 0) {
        g.vs = g.metric.substr(11);
        if (g.vs != "shared" && g.vs != "distributed")
            throw InputError("--target '" + t + "': speedup_vs= takes shared or distributed (a baseline memory system)");
    } else {
        static const char* const derived[] = {"speedup", "efficiency", "area_time_normalized"};
        bool known = false;
        for (const auto& c : parse_csv(sim_csv_header(), "columns").header) known = known || c == g.metric;
        for (const char* c : derived) known = known || g.metric == c;
        if (!known)
            throw InputError("--target '" + t + "': unknown METRIC '" + g.metric +
                             "' (a column of the sweep's CSV, e.g. efficiency, total_cycles, or speedup_vs=shared)");
    }
    return g;
}

struct Probe {
    std::uint64_t value = 0;
    bool met = false;
    double worst = 0;    // the metric at the row that meets the target least
    std::string where;   // that row
    CsvTable table;
};

int find_value(const SweepArgs& a) {
    const std::string key = a.find;
    const Target target = parse_target(a.target);
    ParamSet mp = model::machine_params();
    const bool dim = key == "fifo" || key == "iccs";
    std::uint64_t lo = 1, hi = key == "fifo" ? 100000 : 4096;
    if (!dim) {
        if (!mp.has(key) || mp.type(key) != ParamSet::Type::Int)
            throw InputError("--find " + key + ": not fifo, iccs or an integer config key (raplas simulate "
                             "--dump-config lists them)");
        const auto [mn, mx] = mp.range(key);
        lo = std::uint64_t(std::max(0.0, mn));
        hi = std::uint64_t(mx);
        for (const auto& x : a.sets)
            if (key_of(x) == key) throw InputError("--find " + key + ": also given with --set");
        for (const auto& v : a.vary)
            if (key_of(v) == key) throw InputError("--find " + key + ": also given with --vary");
    }
    if (key == "fifo" && !a.fifo.empty()) throw InputError("--find fifo: searches the FIFO depth; give no --fifo");
    if (key == "iccs" && a.iccs.size() > 1)
        throw InputError("--find iccs: searches the ICC count; --iccs may give one count, the base of speedup and "
                         "efficiency");
    if (!target.vs.empty())
        for (const auto& v : a.vary)
            if (key_of(v) == "memory.system") throw InputError("--target speedup_vs: varies memory.system itself; give no --vary memory.system");
    if (a.find_limit) hi = std::min<std::uint64_t>(hi, a.find_limit);
    if (hi < lo) throw InputError("--find-limit " + std::to_string(a.find_limit) + ": below the smallest value " + std::to_string(lo));
    if (!a.check.empty() || !a.update.empty() || !a.emit_jobs.empty() || a.merge)
        throw InputError("--find runs its own points: not with --check, --update, --emit-jobs or --merge");
    const std::uint32_t base_iccs = key == "iccs" ? (a.iccs.empty() ? 1 : a.iccs[0]) : 0;

    const std::string root = absolute_path(a.work_dir.empty() ? a.out + ".d" : a.work_dir);
    std::error_code ec;
    fs::create_directories(root + "/traces", ec);
    if (!fs::is_directory(root + "/traces")) throw InputError(root + ": cannot create the work dir");
    // The traces serve every probe unless the key changes the workload.
    const bool share = dim || (key.rfind("workload.", 0) != 0 && key.rfind("numerics.", 0) != 0);

    std::map<std::uint64_t, Probe> seen;
    auto probe = [&](std::uint64_t v) -> const Probe& {
        if (auto it = seen.find(v); it != seen.end()) return it->second;
        SweepArgs b = a;
        b.find.clear();
        b.quiet = true;
        b.progress = false;
        b.out = root + "/probe-" + std::to_string(v) + ".csv";
        b.work_dir = root + "/" + key + "-" + std::to_string(v);
        if (key == "fifo") {
            b.fifo = {std::uint32_t(v)};
            if (a.base_fifo && a.base_fifo != v) b.fifo.push_back(a.base_fifo);
        } else if (key == "iccs") {
            b.iccs = {base_iccs};
            if (v != base_iccs) b.iccs.push_back(std::uint32_t(v));
        } else {
            b.sets.push_back(key + "=" + std::to_string(v));
        }
        if (!target.vs.empty()) b.vary.push_back("memory.system=streaming," + target.vs);
        Sweep sw = make_sweep(b, absolute_path(b.work_dir));
        if (share) sw.trace_dir = root + "/traces";
        if (!a.quiet) std::printf("find: %s = %llu ...\n", key.c_str(), (unsigned long long)v), std::fflush(stdout);
        const int rc = run_sweep(sw, b);
        if (rc != 0) throw InputError("--find " + key + ": the points at " + key + " = " + std::to_string(v) +
                                      " failed (see above); nothing found");
        Probe p;
        p.value = v;
        p.table = parse_csv(read_file(b.out), b.out);
        const auto col = [&](const char* c) { return p.table.column(c); };
        const auto c_metric = target.vs.empty() ? col(target.metric.c_str()) : col("total_cycles");
        const auto c_iccs = col("iccs"), c_fifo = col("fifo_depth"), c_sys = col("memory_system"), c_scene = col("scene");
        if (!c_metric) throw InputError("--target " + target.text + ": the sweep's CSV has no column " + target.metric);
        bool first = true;
        p.met = true;
        for (std::size_t r = 0; r < p.table.rows.size(); ++r) {
            const auto& row = p.table.rows[r];
            if (key == "iccs" && c_iccs && row[*c_iccs] != std::to_string(v)) continue;  // the base's row
            if (key == "fifo" && c_fifo && row[*c_fifo] != std::to_string(v)) continue;
            if (!target.vs.empty() && c_sys && row[*c_sys] != "streaming") continue;
            double x = std::strtod(row[*c_metric].c_str(), nullptr);
            if (row[*c_metric].empty()) throw InputError("--target " + target.text + ": no " + target.metric + " in " + b.out);
            if (!target.vs.empty()) {  // the baseline's row: the next with the same point, memory_system = vs
                double other = 0;
                for (const auto& o : p.table.rows)
                    if (o[*c_sys] == target.vs && o[*c_iccs] == row[*c_iccs] && o[*c_fifo] == row[*c_fifo] &&
                        o[*c_scene] == row[*c_scene])
                        other = std::strtod(o[*c_metric].c_str(), nullptr);
                x = x > 0 ? other / x : 0;
            }
            const bool ok = target.met(x);
            // The row that meets the target least decides.
            const bool worse = first || (target.at_least ? x < p.worst : x > p.worst);
            if (worse) {
                p.worst = x;
                p.where = (c_scene ? row[*c_scene] : std::string("?")) + ", " +
                          (c_iccs ? row[*c_iccs] : std::string("?")) + " ICCs, FIFO " + (c_fifo ? row[*c_fifo] : std::string("?"));
            }
            first = false;
            p.met = p.met && ok;
        }
        if (first) throw InputError("--find: no row of " + b.out + " to judge");
        if (!a.quiet)
            std::printf("find: %s = %llu: %s = %.6g (%s): %s\n", key.c_str(), (unsigned long long)v, target.metric.c_str(),
                        p.worst, p.where.c_str(), p.met ? "meets the target" : "does not"),
                std::fflush(stdout);
        return seen.emplace(v, std::move(p)).first->second;
    };

    // For the FIFO depth, first the limit of deep FIFOs: every point in closed
    // form with unbounded Triangle, PlaneID and First-Triangle-ID FIFOs
    // (sim.estimate = fifo_bound), a lower bound of the cycles at any depth.
    // If it misses the target, no depth meets it: the search stops there.
    std::string cap;
    bool capped = false;
    if (key == "fifo" && target.vs.empty()) {
        SweepArgs b = a;
        b.find.clear();
        b.quiet = true;
        b.progress = false;
        b.fifo = {std::uint32_t(hi)};
        if (a.base_fifo && a.base_fifo != hi) b.fifo.push_back(a.base_fifo);
        b.sets.push_back("sim.estimate=fifo_bound");
        b.out = root + "/bound.csv";
        b.work_dir = root + "/bound";
        Sweep sw = make_sweep(b, absolute_path(b.work_dir));
        sw.trace_dir = root + "/traces";
        if (run_sweep(sw, b) != 0) throw InputError("--find fifo: the closed-form bound failed (see above)");
        const CsvTable t = parse_csv(read_file(b.out), b.out);
        const auto c = t.column(target.metric), c_fifo = t.column("fifo_depth"), c_iccs = t.column("iccs");
        const auto c_pe = t.column("pe_bound_cycles"), c_mem = t.column("memory_bound_cycles");
        bool all = c.has_value();
        double worst = target.at_least ? 1e300 : -1e300;
        std::string why;  // what bounds the worst row: the RTI work or the triangle stream
        for (const auto& row : t.rows) {
            if (!c || row[*c].empty() || (c_fifo && row[*c_fifo] != std::to_string(hi))) continue;
            const double x = std::strtod(row[*c].c_str(), nullptr);
            if (target.at_least ? x < worst : x > worst) {
                worst = x;
                why.clear();
                if (c_pe && c_mem && c_iccs) {
                    const double pe = std::strtod(row[*c_pe].c_str(), nullptr), mem = std::strtod(row[*c_mem].c_str(), nullptr);
                    why = " at " + row[*c_iccs] + " ICCs, where " +
                          (pe >= mem ? "the RTI work of each pass's busiest ICC (pe_bound_cycles " + row[*c_pe] +
                                           ") exceeds the triangle stream's (memory_bound_cycles " + row[*c_mem] + ")"
                                     : "the triangle stream (memory_bound_cycles " + row[*c_mem] +
                                           ") exceeds the RTI work of each pass's busiest ICC (pe_bound_cycles " +
                                           row[*c_pe] + ")");
                }
            }
            all = all && target.met(x);
        }
        if (c) {
            char buf[256];
            std::snprintf(buf, sizeof buf, "with FIFOs unbounded (sim.estimate = fifo_bound, the limit of deep FIFOs) %s is %.6g",
                          target.metric.c_str(), worst);
            cap = buf + why;
            capped = !all;
            if (!a.quiet) std::printf("find: %s: %s\n", cap.c_str(), all ? "the target may be met" : "the target cannot be met"), std::fflush(stdout);
        }
    }
    if (capped) {
        std::fprintf(stderr, "raplas: error: --find fifo: no FIFO depth meets %s: %s; wrote %s\n", target.text.c_str(),
                     cap.c_str(), a.out.c_str());
        write_file_atomically(a.out, read_file(root + "/bound.csv"));
        return kExitInternalError;
    }

    // Gallop up from the smallest value, then bisect: the target is assumed to
    // hold from some value on (checked on the values visited).
    std::optional<std::uint64_t> found, failed;
    for (std::uint64_t v = lo;; v = v == 0 ? 1 : v * 2) {
        if (v > hi) v = hi;
        if (probe(v).met) {
            found = v;
            break;
        }
        failed = v;
        if (v == hi) break;
    }
    std::string why;
    if (found) {
        std::uint64_t l = failed ? *failed : lo, h = *found;  // l fails (unless l = h = lo), h meets
        while (failed && h - l > 1) {
            const std::uint64_t m = l + (h - l) / 2;
            (probe(m).met ? h : l) = m;
        }
        found = h;
        for (const auto& [v, p] : seen)
            if (p.met != (v >= *found)) {
                why = "the target is not monotone in " + key + " on the values visited (" + std::to_string(v) +
                      (p.met ? " meets it" : " does not") + "): the answer is the smallest of a bisection, not proven";
                break;
            }
    }

    // The visited points, in the order of the key's value: the first columns
    // say which value and whether it met the target.
    CsvTable all;
    for (const auto& [v, p] : seen) {
        if (all.header.empty()) {
            all.header = {"find_key", "find_value", "find_meets"};
            all.header.insert(all.header.end(), p.table.header.begin(), p.table.header.end());
        }
        for (const auto& row : p.table.rows) {
            std::vector<std::string> r = {key, std::to_string(v), p.met ? "true" : "false"};
            r.insert(r.end(), row.begin(), row.end());
            all.rows.push_back(std::move(r));
        }
    }
    all.comments = {" raplas sweep --find " + key + " --target " + target.text + ": " +
                    (found ? key + " = " + std::to_string(*found) : "not met up to " + std::to_string(hi))};
    write_file_atomically(a.out, to_csv(all));

    std::string visited;
    for (const auto& [v, p] : seen) visited += (visited.empty() ? "" : ", ") + std::to_string(v) + (p.met ? "+" : "-");
    if (!why.empty()) std::fprintf(stderr, "raplas: warning: --find %s: %s\n", key.c_str(), why.c_str());
    if (found) {
        const Probe& p = seen.at(*found);
        std::string bracket = *found == lo ? "the smallest value" : "bracket [" + std::to_string(*found - 1) + ", " + std::to_string(*found) + "]";
        if (!a.quiet)
            std::printf("found: %s = %llu (%s = %.6g at %s; %s); %zu values visited (%s); wrote %s\n", key.c_str(),
                        (unsigned long long)*found, target.metric.c_str(), p.worst, p.where.c_str(), bracket.c_str(),
                        seen.size(), visited.c_str(), a.out.c_str());
        return 0;
    }
    const Probe& top = seen.at(hi);
    std::fprintf(stderr, "raplas: error: --find %s: no value up to %llu meets %s: at %llu, %s = %.6g (%s)%s; wrote %s\n",
                 key.c_str(), (unsigned long long)hi, target.text.c_str(), (unsigned long long)hi, target.metric.c_str(),
                 top.worst, top.where.c_str(), cap.empty() ? "" : ("; " + cap).c_str(), a.out.c_str());
    return kExitInternalError;
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
    cmd->add_option("--vary", a.vary,
                    "sweep a config or scene key too: KEY=V1,V2,... or KEY=A..B (integers A to B), repeatable; "
                    "points are the cross product, and each varied key is a CSV column (docs/SWEEPS.md)");
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
    cmd->add_flag("--retry-failed", a.retry_failed,
                  "simulate again the points that failed in an earlier run (without it they stay failed: the sweep "
                  "exits non-zero and names them)");
    cmd->add_flag("--fresh", a.fresh,
                  "when the work dir holds a sweep made from other inputs (scene, mesh or config files, keys, "
                  "points, or another build of raplas), recompute the points that changes instead of refusing");
    cmd->add_option("--base-iccs", a.base_iccs,
                    "the ICC count that speedup and efficiency are relative to, in each series (default: the "
                    "smallest ICC count of the series)")
        ->check(CLI::Range(1u, 4096u));
    cmd->add_option("--find", a.find,
                    "KEY: search the smallest value of KEY (fifo, iccs or an integer config key) that meets --target "
                    "at every point of the sweep, galloping then bisecting (docs/SWEEPS.md, \"Finding a value\")");
    cmd->add_option("--target", a.target,
                    "METRIC>=VALUE or METRIC<=VALUE for --find: METRIC a CSV column (efficiency, total_cycles, ...) "
                    "or speedup_vs=shared|distributed");
    cmd->add_option("--find-limit", a.find_limit, "the largest value --find tries (default: the key's range; FIFO 100000)")
        ->check(CLI::Range(1u, 100000000u));
    cmd->add_option("--base-fifo", a.base_fifo,
                    "the FIFO depth that speedup and efficiency are relative to: each point against the base ICC "
                    "count's point at this depth (default: at the point's own depth, which flatters small FIFOs)")
        ->check(CLI::Range(1u, 100000000u));
    cmd->add_option("--normalize", a.normalize,
                    "KEY=VALUE: add area_time_normalized, each point's area x time over that of the point with "
                    "KEY=VALUE and everything else equal (KEY: a --vary key, iccs or fifo)");
    cmd->add_option("--check", a.check,
                    "compare the result with a reference table (CSV): print every differing cell, exit 1 if any");
    cmd->add_option("--tolerance", a.tolerance,
                    "COLUMN=REL: --check accepts a relative difference up to REL in that column (repeatable)");
    cmd->add_option("--update", a.update, "write the result as a reference table for --check (atomically)");
    cmd->add_flag("--progress", a.progress, "progress on stderr (default: when stderr is a terminal)");
    cmd->add_flag("-q,--quiet", a.quiet, "no summary on stdout");
}

// What a sweep reads and writes, checked before any work (docs/BAD_INPUT.md,
// "Rules"): no output is an input (a reference table given to --check
// included) or another output.
void check_sweep_files(const SweepArgs& a, const Sweep* sw) {
    RunFiles files;
    if (sw) {
        for (const Input& in : sw->inputs) {
            if (in.kind == "builtin") continue;
            files.input("--" + in.kind, in.path);
            if (in.kind != "scene") continue;
            ParamSet p = scene_params();
            p.load_file(in.path);
            for (const auto& x : sw->scene_sets) p.set(x);
            for (const auto& m : scene_mesh_files(p, "")) files.input("the mesh of --scene " + in.path, m);
        }
        if (!sw->config.empty()) files.input("--config", resolve_config(sw->config));
    }
    files.input("--check", a.check);
    files.output("--out", a.out);
    files.output("--update", a.update);
    if (!a.emit_jobs.empty())
        for (const char* ext : {"", ".traces"}) files.output("--emit-jobs", a.emit_jobs + ext);
    files.check();
}

int cmd_sweep(const SweepArgs& a) {
    check_out_path(a.out);
    if (!a.find.empty() || !a.target.empty()) {
        if (a.find.empty() || a.target.empty()) throw InputError("--find KEY and --target METRIC>=VALUE go together");
        check_sweep_files(a, nullptr);
        return find_value(a);
    }
    const std::string wd = absolute_path(a.work_dir.empty() ? a.out + ".d" : a.work_dir);
    if (a.merge) {
        if (!a.emit_jobs.empty()) throw UsageError("give either --merge or --emit-jobs, not both");
        const bool defines = !a.scenes.empty() || !a.meshes.empty() || !a.config.empty() || !a.sets.empty() ||
                             !a.vary.empty() || !a.iccs.empty() || !a.fifo.empty();
        if (!defines) {
            check_sweep_files(a, nullptr);
            return merge(wd, a, nullptr);
        }
        const Sweep sw = make_sweep(a, wd);
        check_sweep_files(a, &sw);
        return merge(wd, a, &sw);
    }
    const Sweep sw = make_sweep(a, wd);
    check_sweep_files(a, &sw);
    if (!a.emit_jobs.empty()) {
        if (!a.check.empty() || !a.update.empty())
            throw InputError("--check and --update need the results: give them to --merge after the jobs ran");
        return emit_jobs(sw, a);
    }
    return run_sweep(sw, a);
}

}  // namespace raplas
