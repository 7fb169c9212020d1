// One simulation sharded across processes and nodes (docs/SHARDING.md): the
// partial result of a shard, `raplas merge`, and the job lists of a sharded
// simulation.
#include "shard.hpp"

#include "frames.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "run_inputs.hpp"
#include "raplas/app/processes.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/util/atomic_file.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"
#include "raplas/util/run_files.hpp"
#include "raplas/util/input_file.hpp"

#ifndef RAPLAS_VERSION
#define RAPLAS_VERSION "unknown"
#endif

namespace raplas {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kPartialFormat = 2;  // 2: the inputs that made it
constexpr const char* kAssignment = "pass p belongs to shard p mod shards";

bool all_digits(const std::string& s) {
    return !s.empty() && s.size() <= 9 && s.find_first_not_of("0123456789") == std::string::npos;
}

// ---- the raw figures of a result ---------------------------------------------

// How the shards' values of a figure combine into the whole run's.
enum class Combine { sum, max };

// Every statistic of an ICC, by name (a new statistic must be added here: the
// size check below fails until it is).
static_assert(sizeof(model::IccSnapshot) == 41 * sizeof(std::uint64_t),
              "IccSnapshot changed: list its new statistics in visit_icc");
template <class S, class F>
void visit_icc(S& s, F&& f) {
    f("groups", s.icc.groups, Combine::sum);
    f("pass_cycles", s.icc.pass_cycles, Combine::sum);
    f("idle_cycles", s.icc.idle_cycles, Combine::sum);
    f("sphere_selector.received", s.sphere_selector.received, Combine::sum);
    f("sphere_selector.blocked_link_cycles", s.sphere_selector.blocked_link_cycles, Combine::sum);
    auto fifo = [&](const std::string& name, auto& x) {
        f((name + ".pushes").c_str(), x.pushes, Combine::sum);
        f((name + ".max_occupancy").c_str(), x.max_occupancy, Combine::max);
        f((name + ".full_cycles").c_str(), x.full_cycles, Combine::sum);
    };
    fifo("sphere_fifo", s.sphere_fifo);
    fifo("planeid_fifo", s.planeid_fifo);
    fifo("first_tri_fifo", s.first_tri_fifo);
    fifo("triangle_fifo", s.triangle_fifo);
    f("psi.spheres", s.psi.spheres, Combine::sum);
    f("psi.plane_tests", s.psi.plane_tests, Combine::sum);
    f("psi.busy_cycles", s.psi.busy_cycles, Combine::sum);
    f("psi.stall_cycles", s.psi.stall_cycles, Combine::sum);
    f("psi.starved_cycles", s.psi.starved_cycles, Combine::sum);
    f("decoder.decided", s.decoder.decided, Combine::sum);
    f("decoder.sphere_hits", s.decoder.sphere_hits, Combine::sum);
    f("decoder.pairless", s.decoder.pairless, Combine::sum);
    f("decoder.full_cycles", s.decoder.full_cycles, Combine::sum);
    f("triangle_selector.selected", s.triangle_selector.selected, Combine::sum);
    f("triangle_selector.discarded", s.triangle_selector.discarded, Combine::sum);
    f("triangle_selector.blocked_fifo_full", s.triangle_selector.blocked_fifo_full, Combine::sum);
    f("triangle_selector.blocked_undecided", s.triangle_selector.blocked_undecided, Combine::sum);
    f("triangle_selector.blocked_alone", s.triangle_selector.blocked_alone, Combine::sum);
    f("ray_data_fetcher.triangles", s.ray_data_fetcher.triangles, Combine::sum);
    f("ray_data_fetcher.empty_triangles", s.ray_data_fetcher.empty_triangles, Combine::sum);
    // Each shard's are its ICC's pass cycles less its busy cycles, and a
    // pass's busy cycles lie in the pass: the shards' add up to the run's.
    f("ray_data_fetcher.starved_cycles", s.ray_data_fetcher.starved_cycles, Combine::sum);
    f("rti.tests", s.rti.tests, Combine::sum);
    f("rti.hits", s.rti.hits, Combine::sum);
    f("rti.busy_cycles", s.rti.busy_cycles, Combine::sum);
    f("min_distance.updates", s.min_distance.updates, Combine::sum);
    f("output.groups", s.output.groups, Combine::sum);
    f("output.records", s.output.records, Combine::sum);
    f("output.bytes", s.output.bytes, Combine::sum);
}

template <class L, class F>
void visit_link(L& l, F&& f) {
    f("records_sent", l.records_sent, Combine::sum);
    f("stall_cycles", l.stall_cycles, Combine::sum);
    f("idle_cycles", l.idle_cycles, Combine::sum);
    f("bytes", l.bytes, Combine::sum);
    for (std::size_t b = 0; b < model::StreamLink::Stats::kHeldBins; ++b)
        f(("held_by_" + model::StreamLink::held_bin_name(b)).c_str(), l.held_by[b], Combine::sum);
}

json hit_json(const Hit& h) { return {{"triangle", h.tri}, {"t", h.t}}; }

json result_json(const model::SimResult& r, const WorkloadFacts& w) {
    json j;
    j["pass_index"] = r.pass_index;
    j["pass_cycles"] = r.pass_cycles;
    j["total_cycles"] = r.total_cycles;
    j["estimated"] = r.estimated;
    j["lower_bound"] = r.lower_bound;
    j["host"] = {{"passes", r.host.passes}, {"primary_passes", r.host.primary_passes}, {"groups", r.host.groups}};
    for (const auto& [name, link] : {std::pair<const char*, const model::StreamLink::Stats*>{"sphere_link", &r.sphere_link},
                                     {"triangle_link", &r.triangle_link}}) {
        json l = json::object();
        visit_link(*link, [&](const char* k, const std::uint64_t& v, Combine) { l[k] = v; });
        j[name] = l;
    }
    j["sphere_memory_reads"] = r.sphere_memory.reads;
    j["triangle_memory_reads"] = r.triangle_memory.reads;
    j["iccs"] = json::array();
    for (const model::IccSnapshot& s : r.iccs) {
        json o = json::object();
        visit_icc(s, [&](const char* k, const std::uint64_t& v, Combine) { o[k] = v; });
        j["iccs"].push_back(o);
    }
    j["functional_checked"] = r.functional_checked;
    j["rays_checked"] = r.rays_checked;
    j["rays_mismatched"] = r.rays_mismatched;
    j["first_mismatch"] = nullptr;
    if (r.first_mismatch) {
        const auto& m = *r.first_mismatch;
        j["first_mismatch"] = {{"group", m.group},
                               {"h", m.h},
                               {"v", m.v},
                               {"model", hit_json(m.model)},
                               {"frontend", hit_json(m.frontend)},
                               {"group_primary", w.mismatch_primary},
                               {"group_pixel", {w.mismatch_px, w.mismatch_py}}};
    }
    j["model_wall_s"] = r.model_wall_s;
    return j;
}

// ---- reading a partial result ------------------------------------------------

// Typed access to one part's JSON: a missing or mistyped value is an
// InputError naming the file and the key.
struct Doc {
    std::string file;
    json j;

    [[noreturn]] void corrupt(const std::string& what) const {
        throw InputError(file + ": corrupt partial result: " + what);
    }
    const json& at(const json& o, const std::string& key, const std::string& where) const {
        if (!o.is_object() || !o.contains(key)) corrupt(where + key + " is missing");
        return o[key];
    }
    std::uint64_t u64(const json& o, const std::string& key, const std::string& where = "") const {
        const json& v = at(o, key, where);
        if (!v.is_number_unsigned()) corrupt(where + key + " is not a count");
        return v.get<std::uint64_t>();
    }
    std::int64_t i64(const json& o, const std::string& key, const std::string& where = "") const {
        const json& v = at(o, key, where);
        if (!v.is_number_integer()) corrupt(where + key + " is not an integer");
        return v.get<std::int64_t>();
    }
    double real(const json& o, const std::string& key, const std::string& where = "") const {
        const json& v = at(o, key, where);
        if (!v.is_number()) corrupt(where + key + " is not a number");
        return v.get<double>();
    }
    bool boolean(const json& o, const std::string& key, const std::string& where = "") const {
        const json& v = at(o, key, where);
        if (!v.is_boolean()) corrupt(where + key + " is not true or false");
        return v.get<bool>();
    }
    std::string str(const json& o, const std::string& key, const std::string& where = "") const {
        const json& v = at(o, key, where);
        if (!v.is_string()) corrupt(where + key + " is not a string");
        return v.get<std::string>();
    }
    const json& obj(const json& o, const std::string& key, const std::string& where = "") const {
        const json& v = at(o, key, where);
        if (!v.is_object()) corrupt(where + key + " is not an object");
        return v;
    }
    const json& arr(const json& o, const std::string& key, const std::string& where = "") const {
        const json& v = at(o, key, where);
        if (!v.is_array()) corrupt(where + key + " is not a list");
        return v;
    }
};

struct Part {
    Doc doc;
    std::uint32_t shard = 0, shards = 0;
};

Part read_part(const std::string& file) {
    Part p;
    p.doc.file = file;
    // Parsed, a document takes several times its text (docs/MEMORY.md).
    const std::string text = read_text_input(file, {"partial result", "a", "JSON text and its parse", 8.0});
    const std::string not_partial = file + ": not a partial result of raplas simulate --shard";
    try {
        p.doc.j = json::parse(text);
    } catch (const json::parse_error& e) {
        throw InputError(not_partial + (e.byte > text.size() ? " (not JSON: it ends early, at byte " + std::to_string(text.size()) + ")"
                                                             : " (not JSON: syntax error at byte " + std::to_string(e.byte) + ")"));
    }
    const json& j = p.doc.j;
    if (!j.is_object()) throw InputError(not_partial + " (not a JSON object)");
    if (!j.contains("raplas_partial")) {
        if (j.contains("total_cycles") && j.contains("config_hash"))
            throw InputError(file + ": a whole result of raplas simulate, not a partial one: merge takes the --json "
                                    "files of simulate --shard I/N");
        throw InputError(not_partial + " (no raplas_partial key)");
    }
    const json& f = j["raplas_partial"];
    if (!f.is_number_integer() || f.get<std::int64_t>() != kPartialFormat)
        throw InputError(file + ": partial result format " + f.dump() + "; this raplas reads format " +
                         std::to_string(kPartialFormat));
    const std::string version = p.doc.str(j, "raplas_version");
    if (version != RAPLAS_VERSION)
        throw InputError(file + ": written by raplas " + version + ", this is raplas " + RAPLAS_VERSION +
                         ": merge with the raplas that simulated the shards");
    const std::uint64_t n = p.doc.u64(j, "shards"), i = p.doc.u64(j, "shard");
    if (n < 1 || n > kMaxShards || i >= n)
        p.doc.corrupt("shard " + std::to_string(i) + " of " + std::to_string(n) + " is out of range");
    p.shard = std::uint32_t(i);
    p.shards = std::uint32_t(n);
    return p;
}

std::string shard_name(std::uint32_t i, std::uint32_t n) {
    return "shard " + std::to_string(i) + " of " + std::to_string(n);
}

std::string list_of(const std::vector<std::uint32_t>& v) {
    std::string s;
    for (std::size_t k = 0; k < v.size() && k < 5; ++k)
        s += (k ? (k + 1 == v.size() ? " and " : ", ") : "") + std::to_string(v[k]);
    if (v.size() > 5) s += ", ... (" + std::to_string(v.size()) + " in all)";
    return s;
}

// Checks that the parts are every shard of one run, once each; returns them in shard order.
std::vector<const Part*> check_parts(const std::vector<Part>& parts) {
    const Part& a = parts[0];
    for (const Part& b : parts) {
        if (b.shards != a.shards)
            throw InputError(b.doc.file + ": " + shard_name(b.shard, b.shards) + ", but " + a.doc.file + " is " +
                             shard_name(a.shard, a.shards) + ": merge the shards of one run");
        for (const char* key : {"config_hash", "workload_hash"}) {
            const std::string x = a.doc.str(a.doc.j, key), y = b.doc.str(b.doc.j, key);
            if (x != y)
                throw InputError(b.doc.file + ": another " +
                                 (std::string(key) == "config_hash" ? "machine config" : "workload") + " (" + key +
                                 " " + y + ") than " + a.doc.file + " (" + x + "): merge the shards of one run");
        }
        // What made each part: the model, the config file, the --set keys, the trace.
        const json& ia = a.doc.at(a.doc.j, "inputs", "");
        const json& ib = b.doc.at(b.doc.j, "inputs", "");
        if (ia != ib)
            throw InputError(b.doc.file + ": made from other inputs than " + a.doc.file + " (" + inputs_change(ia, ib) +
                             "): merge the shards of one run");
        // What every shard reports of the whole run (the hashes leave out the names).
        for (const char* key : {"scene", "config", "passes", "overrides", "resolved_config", "machine_config", "workload"}) {
            b.doc.at(b.doc.j, key, "");
            if (a.doc.at(a.doc.j, key, "") != b.doc.j[key])
                throw InputError(b.doc.file + ": its " + key + " differs from " + a.doc.file +
                                 "'s: merge the shards of one run");
        }
    }
    std::vector<const Part*> by_shard(a.shards, nullptr);
    for (const Part& b : parts) {
        if (by_shard[b.shard])
            throw InputError(b.doc.file + ": " + shard_name(b.shard, b.shards) + " again (" + by_shard[b.shard]->doc.file +
                             " is that shard too)");
        by_shard[b.shard] = &b;
    }
    std::vector<std::uint32_t> missing;
    for (std::uint32_t i = 0; i < a.shards; ++i)
        if (!by_shard[i]) missing.push_back(i);
    if (!missing.empty())
        throw InputError("merge: " + std::string(missing.size() == 1 ? "shard " : "shards ") + list_of(missing) + " of " +
                         std::to_string(a.shards) + (missing.size() == 1 ? " is" : " are") +
                         " missing: give every shard's partial result");
    return by_shard;
}

}  // namespace

void check_result_path(const std::string& option, const std::string& out, const std::vector<std::string>& parts) {
    if (out.empty()) return;
    std::error_code ec;
    if (fs::is_directory(out, ec)) throw InputError(option + " " + out + ": is a directory");
    const fs::path parent = fs::absolute(out, ec).parent_path();
    if (!fs::is_directory(parent, ec))
        throw InputError(option + " " + out + ": directory " + parent.string() + " does not exist");
    for (const auto& p : parts)
        if (fs::equivalent(p, out, ec)) throw InputError(option + " " + out + ": is one of the partial results");
}

// ---- simulate --shard ------------------------------------------------------------

ShardSpec parse_shard(const std::string& text) {
    const auto slash = text.find('/');
    const std::string usage = "--shard " + text + ": expected I/N, shard I of N with 0 <= I < N (e.g. --shard 0/4)";
    if (slash == std::string::npos) throw InputError(usage);
    const std::string i = text.substr(0, slash), n = text.substr(slash + 1);
    if (!all_digits(i) || !all_digits(n)) throw InputError(usage);
    ShardSpec s;
    const unsigned long iv = std::stoul(i), nv = std::stoul(n);
    if (nv < 1) throw InputError("--shard " + text + ": the shard count must be at least 1");
    if (nv > kMaxShards)
        throw InputError("--shard " + text + ": at most " + std::to_string(kMaxShards) + " shards");
    if (iv >= nv)
        throw InputError("--shard " + text + ": shard " + i + " is not below the shard count " + n +
                         " (shards are numbered 0 to " + std::to_string(nv - 1) + ")");
    s.index = std::uint32_t(iv);
    s.count = std::uint32_t(nv);
    return s;
}

void check_shardable(const model::SimConfig& cfg, const std::string& option) {
    if (cfg.overlap_passes)
        throw InputError(option + ": host.overlap_passes = true starts each pass while the previous one drains, so no "
                                  "pass can be simulated without the passes before it; simulate the run whole");
    if (cfg.estimate == model::Estimate::sample_passes)
        throw InputError(option + ": sim.estimate = sample_passes simulates a sample of the passes already; shard an "
                                  "exact or fifo_bound run");
    if (cfg.memory.system != model::MemorySystem::streaming)
        throw InputError(option + ": memory.system = " + model::memory_system_name(cfg.memory.system) +
                         " is computed in closed form from the whole workload; there are no passes to share out");
}

json partial_json(const PartialInput& in) {
    const SimReportInput& r = in.report;
    const Provenance& p = *r.provenance;
    const WorkloadFacts& w = *r.workload;
    const model::MemoryStats& m = *r.memory;
    json j;
    j["raplas_partial"] = kPartialFormat;
    j["raplas_version"] = RAPLAS_VERSION;
    j["shard"] = in.shard.index;
    j["shards"] = in.shard.count;
    j["assignment"] = kAssignment;
    j["passes"] = r.result->host.passes;
    j["scene"] = r.scene_name;
    j["config"] = r.config_name;
    j["overrides"] = json::object();
    for (const auto& [k, v] : p.overrides) j["overrides"][k] = p.resolved_config[k];
    j["config_hash"] = p.config_hash;
    j["workload_hash"] = p.workload_hash;
    j["resolved_config"] = p.resolved_config;
    j["machine_config"] = in.machine_config;
    j["inputs"] = in.inputs;
    j["workload"] = {{"ray_groups", w.ray_groups},
                     {"primary_groups", w.primary_groups},
                     {"spheres", w.spheres},
                     {"triangles", w.triangles},
                     {"group_size", w.group_size},
                     {"shadow_group_size", w.shadow_group_size},
                     {"triangles_per_sphere", w.triangles_per_sphere},
                     {"plane_sphere_tests", w.counts.plane_tests},
                     {"sphere_hits", w.counts.sphere_hits},
                     {"ray_triangle_tests", w.counts.rt_tests},
                     {"pairless_spheres", w.counts.pairless}};
    j["result"] = result_json(*r.result, w);
    j["memory"] = {{"system", model::memory_system_name(m.system)},
                   {"sphere_records_read", m.sphere_records_read},
                   {"triangle_records_read", m.triangle_records_read},
                   {"memory_bound_cycles", m.memory_bound_cycles},
                   {"pe_bound_cycles", m.pe_bound_cycles}};
    j["wall"] = {{"frontend_s", r.frontend_wall_s}, {"model_s", r.result->model_wall_s}};
    return j;
}

std::string shard_summary(const PartialInput& in, const std::string& json_path) {
    const model::SimResult& r = *in.report.result;
    char buf[512];
    std::snprintf(buf, sizeof buf, "%s on %s, shard %u/%u: %zu of %llu passes, %llu cycles; partial result %s (raplas merge adds up the shards)\n",
                  in.report.config_name.c_str(), in.report.scene_name.c_str(), in.shard.index, in.shard.count, r.pass_cycles.size(),
                  (unsigned long long)r.host.passes, (unsigned long long)r.total_cycles, json_path.c_str());
    return buf;
}

// ---- raplas merge --------------------------------------------------------------

void add_merge_options(CLI::App* cmd, MergeArgs& a) {
    cmd->add_option("parts", a.parts, "the partial results (--json) of simulate --shard I/N, every shard once, any order");
    cmd->add_option("--json", a.json, "the whole run's statistics as JSON (as simulate --json writes them)");
    cmd->add_option("--csv", a.csv, "the whole run's CSV row with a header (as simulate --csv writes it)");
    cmd->add_flag("-q,--quiet", a.quiet, "no summary on stdout");
}

int cmd_merge(const MergeArgs& a) {
    if (a.parts.empty()) throw InputError("merge: give the partial results of simulate --shard I/N, every shard's --json");
    if (is_frame_result(a.parts[0])) return merge_frames(a);
    if (a.json.empty() && a.csv.empty() && !a.summary_only)
        throw InputError("merge: give --json OUT.json, --csv OUT.csv or both");
    check_result_path("--json", a.json, a.parts);
    check_result_path("--csv", a.csv, a.parts);
    if (same_file(a.json, a.csv))
        throw InputError("--csv " + a.csv + ": is also the output --json " + a.json + "; give each output its own file");
    std::vector<Part> parts;
    for (const auto& f : a.parts) parts.push_back(read_part(f));
    const std::vector<const Part*> shards = check_parts(parts);
    const Doc& first = shards[0]->doc;
    const json& top = first.j;

    // The machine config, rebuilt from its text and checked against its hash.
    ParamSet mp = model::machine_params();
    mp.load_text(first.str(top, "machine_config"), first.file + ": machine_config");
    if (config_hash(mp) != first.str(top, "config_hash")) first.corrupt("machine_config does not give config_hash");
    const model::SimConfig cfg = model::config_from_params(mp);
    check_shardable(cfg, first.file);

    // The whole run's result: every count summed, every maximum the largest,
    // the passes in their order, the first mismatch the earliest.
    const std::uint64_t passes = first.u64(top, "passes");
    model::SimResult r;
    r.pass_cycles.assign(passes, 0);
    r.pass_index.resize(passes);
    for (std::uint32_t p = 0; p < passes; ++p) r.pass_index[p] = p;
    std::optional<json> mismatch;
    double frontend_s = 0, model_max_s = 0;
    const std::uint32_t n = shards[0]->shards;
    for (std::uint32_t i = 0; i < n; ++i) {
        const Doc& d = shards[i]->doc;
        const json& res = d.obj(d.j, "result");
        const json& idx = d.arr(res, "pass_index", "result.");
        const json& cyc = d.arr(res, "pass_cycles", "result.");
        std::vector<std::uint64_t> want;
        for (std::uint64_t p = i; p < passes; p += n) want.push_back(p);
        if (idx.size() != want.size() || cyc.size() != want.size())
            d.corrupt("result.pass_index does not hold the passes of " + shard_name(i, n) + " of " +
                      std::to_string(passes) + " passes");
        for (std::size_t k = 0; k < want.size(); ++k) {
            if (!idx[k].is_number_unsigned() || idx[k].get<std::uint64_t>() != want[k] || !cyc[k].is_number_unsigned())
                d.corrupt("result.pass_index does not hold the passes of " + shard_name(i, n) + " of " +
                          std::to_string(passes) + " passes");
            r.pass_cycles[want[k]] = cyc[k].get<std::uint64_t>();
        }
        r.total_cycles += d.u64(res, "total_cycles", "result.");
        const bool estimated = d.boolean(res, "estimated", "result."), lower = d.boolean(res, "lower_bound", "result.");
        const bool checked = d.boolean(res, "functional_checked", "result.");
        const json& host = d.obj(res, "host", "result.");
        const model::Host::Stats hs{d.u64(host, "passes", "result.host."), d.u64(host, "primary_passes", "result.host."),
                                    d.u64(host, "groups", "result.host.")};
        if (i == 0) {
            r.estimated = estimated;
            r.lower_bound = lower;
            r.functional_checked = checked;
            r.host = hs;
        } else if (estimated != r.estimated || lower != r.lower_bound || checked != r.functional_checked ||
                   hs.passes != r.host.passes || hs.primary_passes != r.host.primary_passes || hs.groups != r.host.groups) {
            d.corrupt("its run (estimate, functional check or passes) differs from " + shards[0]->doc.file + "'s");
        }
        if (hs.passes != passes) d.corrupt("result.host.passes is not passes");
        for (auto [name, link] : {std::pair<const char*, model::StreamLink::Stats*>{"sphere_link", &r.sphere_link},
                                  {"triangle_link", &r.triangle_link}}) {
            const json& l = d.obj(res, name, "result.");
            const std::string where = std::string("result.") + name + ".";
            visit_link(*link, [&](const char* k, std::uint64_t& v, Combine) { v += d.u64(l, k, where); });
        }
        r.sphere_memory.reads += d.u64(res, "sphere_memory_reads", "result.");
        r.triangle_memory.reads += d.u64(res, "triangle_memory_reads", "result.");
        const json& iccs = d.arr(res, "iccs", "result.");
        if (iccs.size() != cfg.iccs) d.corrupt("result.iccs does not hold machine.iccs ICCs");
        r.iccs.resize(cfg.iccs);
        for (std::size_t k = 0; k < iccs.size(); ++k) {
            const std::string where = "result.iccs[" + std::to_string(k) + "].";
            visit_icc(r.iccs[k], [&](const char* key, std::uint64_t& v, Combine c) {
                const std::uint64_t x = d.u64(iccs[k], key, where);
                v = c == Combine::sum ? v + x : std::max(v, x);
            });
        }
        r.rays_checked += d.u64(res, "rays_checked", "result.");
        r.rays_mismatched += d.u64(res, "rays_mismatched", "result.");
        const json& fm = d.at(res, "first_mismatch", "result.");
        if (!fm.is_null()) {
            const std::uint64_t g = d.u64(fm, "group", "result.first_mismatch.");
            if (!mismatch || g < (*mismatch)["group"].get<std::uint64_t>()) {
                mismatch = fm;
                (*mismatch)["file"] = d.file;
            }
        }
        const double model_s = d.real(res, "model_wall_s", "result.");
        r.model_wall_s += model_s;
        model_max_s = std::max(model_max_s, model_s);
        frontend_s += d.real(d.obj(d.j, "wall"), "frontend_s", "wall.");
    }
    r.functional_match = r.functional_checked && r.rays_mismatched == 0;

    // The workload's figures and the group of the first mismatch.
    const json& wj = first.obj(top, "workload");
    WorkloadFacts w;
    w.ray_groups = first.u64(wj, "ray_groups", "workload.");
    w.primary_groups = first.u64(wj, "primary_groups", "workload.");
    w.spheres = first.u64(wj, "spheres", "workload.");
    w.triangles = first.u64(wj, "triangles", "workload.");
    w.group_size = std::uint32_t(first.u64(wj, "group_size", "workload."));
    w.shadow_group_size = std::uint32_t(first.u64(wj, "shadow_group_size", "workload."));
    w.triangles_per_sphere = std::uint32_t(first.u64(wj, "triangles_per_sphere", "workload."));
    w.counts.plane_tests = first.u64(wj, "plane_sphere_tests", "workload.");
    w.counts.sphere_hits = first.u64(wj, "sphere_hits", "workload.");
    w.counts.rt_tests = first.u64(wj, "ray_triangle_tests", "workload.");
    w.counts.pairless = first.u64(wj, "pairless_spheres", "workload.");
    if (mismatch) {
        Doc d{(*mismatch)["file"].get<std::string>(), {}};
        const json& m = *mismatch;
        const std::string where = "result.first_mismatch.";
        model::SimResult::Mismatch x;
        x.group = d.u64(m, "group", where);
        x.h = std::uint32_t(d.u64(m, "h", where));
        x.v = std::uint32_t(d.u64(m, "v", where));
        for (auto [key, hit] : {std::pair<const char*, Hit*>{"model", &x.model}, {"frontend", &x.frontend}}) {
            const json& h = d.obj(m, key, where);
            hit->tri = std::int32_t(d.i64(h, "triangle", where + key + "."));
            hit->t = d.real(h, "t", where + key + ".");
        }
        r.first_mismatch = x;
        w.mismatch_primary = d.boolean(m, "group_primary", where);
        const json& px = d.arr(m, "group_pixel", where);
        if (px.size() != 2 || !px[0].is_number_integer() || !px[1].is_number_integer())
            d.corrupt(where + "group_pixel is not two integers");
        w.mismatch_px = px[0].get<std::int32_t>();
        w.mismatch_py = px[1].get<std::int32_t>();
    }

    // Memory figures: reads summed, the whole run's bounds the same in every shard.
    model::MemoryStats ms;
    ms.system = cfg.memory.system;
    for (std::uint32_t i = 0; i < n; ++i) {
        const Doc& d = shards[i]->doc;
        const json& m = d.obj(d.j, "memory");
        ms.sphere_records_read += d.u64(m, "sphere_records_read", "memory.");
        ms.triangle_records_read += d.u64(m, "triangle_records_read", "memory.");
        const std::uint64_t mb = d.u64(m, "memory_bound_cycles", "memory."), pb = d.u64(m, "pe_bound_cycles", "memory.");
        if (i == 0) {
            ms.memory_bound_cycles = mb;
            ms.pe_bound_cycles = pb;
        } else if (mb != ms.memory_bound_cycles || pb != ms.pe_bound_cycles) {
            d.corrupt("memory bounds differ from " + first.file + "'s");
        }
    }

    // The area follows from the config and the workload, as in the run itself.
    ms.area = model::machine_area(cfg, model::area_workload(w.spheres, w.triangles, w.group_size,
                                                             w.shadow_group_size, cfg));

    Provenance prov;
    for (const auto& [k, v] : first.obj(top, "overrides").items()) prov.overrides.emplace_back(k, v.dump());
    prov.config_hash = first.str(top, "config_hash");
    // (the shards of simulate --jobs leave it to the process that fed them)
    prov.workload_hash = first.str(top, "workload_hash");
    if (prov.workload_hash.empty() != !a.workload_hash.empty())
        first.corrupt(prov.workload_hash.empty() ? "workload_hash is empty" : "workload_hash given twice");
    if (prov.workload_hash.empty()) prov.workload_hash = a.workload_hash;
    prov.resolved_config = first.obj(top, "resolved_config");
    for (const auto& [k, v] : prov.overrides)
        if (!prov.resolved_config.contains(k)) first.corrupt("overrides names " + k + ", which resolved_config lacks");

    SimReportInput in;
    in.result = &r;
    in.config = &cfg;
    in.workload = &w;
    in.provenance = &prov;
    in.config_name = first.str(top, "config");
    in.scene_name = first.str(top, "scene");
    in.frontend_wall_s = frontend_s;
    in.memory = &ms;
    in.shards = n;
    in.model_wall_max_s = model_max_s;
    const json j = sim_json(in);
    if (!a.json.empty()) write_file_atomically(a.json, j.dump(2) + "\n");
    if (!a.csv.empty()) write_file_atomically(a.csv, sim_csv_header() + sim_csv_row(j));
    if (!a.quiet) {
        std::printf("merged %u shards (%llu passes)%s%s%s%s\n", n, (unsigned long long)passes, a.json.empty() ? "" : " into ",
                    a.json.c_str(), a.csv.empty() ? "" : (a.json.empty() ? " into " : " and "), a.csv.c_str());
        std::cout << sim_summary(j);
    }
    if (r.functional_checked && !r.functional_match) {
        std::cerr << "raplas: error: functional mismatch: " << r.rays_mismatched << " of " << r.rays_checked
                  << " rays differ from the front end; first: " << describe_mismatch(j["first_mismatch"]) << "\n";
        return kExitInternalError;
    }
    return 0;
}

// ---- simulate --shards N --emit-jobs FILE --------------------------------------

int emit_shard_jobs(const SimulateArgs& a, const ParamSet& mp, const model::SimConfig& cfg) {
    if (a.emit_jobs.empty()) throw InputError("--shards N writes a job list: give --emit-jobs FILE too");
    if (a.shards == 0) throw InputError("--emit-jobs writes the job list of a sharded run: give --shards N too");
    if (!a.shard.empty()) throw InputError("--shard I/N is one shard's run; --shards N --emit-jobs writes every shard's");
    if (!a.vcd.empty()) throw InputError("--shards: no --vcd (a waveform covers a whole run: simulate it whole)");
    if (a.json.empty() && a.csv.empty())
        throw InputError("--emit-jobs: give --json OUT.json, --csv OUT.csv or both: what the merge writes");
    check_shardable(cfg, "--shards");
    check_result_path("--json", a.json, {});
    check_result_path("--csv", a.csv, {});
    const SceneOptions& so = a.so;
    if (!a.trace.empty() && (!so.scene.empty() || !so.mesh.empty()))
        throw InputError("give either --trace or --scene/--mesh, not both");
    for (const auto& [opt, path] : {std::pair<const char*, std::string>{"--trace", a.trace}, {"--scene", so.scene},
                                    {"--mesh", so.mesh}})
        if (!path.empty() && !is_file(path)) throw InputError(std::string(opt) + " " + path + ": no such file");
    if (!a.trace.empty()) check_trace_workload(TraceReader(a.trace).take_header(), mp, a.trace);

    // The --set keys: config keys go to every shard, scene keys to the trace.
    std::vector<std::string> config_sets, scene_sets;
    for (const auto& s : a.config_sets) {
        const std::string key = s.substr(0, s.find('='));
        (mp.has(key) || !scene_params().has(key) ? config_sets : scene_sets).push_back(s);
    }
    if (a.trace.empty()) {  // the scene keys, checked now rather than on the nodes
        ParamSet sp = scene_params();
        if (!so.scene.empty()) sp.load_file(so.scene);
        for (const auto& s : scene_sets) sp.set(s);
    }

    const std::string wd = absolute_path(a.work_dir.empty() ? (a.json.empty() ? a.csv : a.json) + ".d" : a.work_dir);
    std::error_code ec;
    fs::create_directories(wd, ec);
    if (!fs::is_directory(wd)) throw InputError("--work-dir " + wd + ": cannot create the directory");
    const std::string trace = a.trace.empty() ? wd + "/workload.trace" : a.trace;
    const std::string n = std::to_string(a.shards);
    auto part = [&](std::uint32_t i) { return wd + "/shard-" + std::to_string(i) + "-of-" + n + ".json"; };

    // One shard's command, without --shard and --json.
    std::vector<std::string> sim{"simulate", "--trace", trace};
    if (!a.config.empty()) sim.insert(sim.end(), {"--config", a.config});
    for (const auto& s : config_sets) sim.insert(sim.end(), {"--set", s});
    if (a.iccs) sim.insert(sim.end(), {"--iccs", std::to_string(a.iccs)});
    if (a.fifo) sim.insert(sim.end(), {"--fifo", std::to_string(a.fifo)});
    std::vector<std::string> make_trace;
    if (a.trace.empty()) {
        // The workload as simulate makes it: the scene's --sets, then the
        // config's workload keys, in the config's number format and reading.
        make_trace = {"trace"};
        if (!so.scene.empty()) make_trace.insert(make_trace.end(), {"--scene", so.scene});
        if (!so.mesh.empty()) make_trace.insert(make_trace.end(), {"--mesh", so.mesh});
        for (const auto& s : scene_sets) make_trace.insert(make_trace.end(), {"--set", s});
        if (cfg.group_size) make_trace.insert(make_trace.end(), {"--set", "groups.size=" + std::to_string(cfg.group_size)});
        if (cfg.shadow_group_size)
            make_trace.insert(make_trace.end(), {"--set", "groups.shadow_size=" + std::to_string(cfg.shadow_group_size)});
        if (cfg.triangles_per_sphere)
            make_trace.insert(make_trace.end(),
                              {"--set", "spheres.triangles_per_sphere=" + std::to_string(cfg.triangles_per_sphere)});
        ParamSet resolved = mp;
        model::resolve_numerics(resolved);
        make_trace.insert(make_trace.end(), {"--format", resolved.get_string("numerics.format"), "--triangle-select",
                                             model::triangle_select_name(cfg.icc.decoder.select)});
        if (so.threads) make_trace.insert(make_trace.end(), {"--threads", std::to_string(so.threads)});
        if (so.no_cull) make_trace.push_back("--no-cull");
        make_trace.insert(make_trace.end(), {"--out", trace, "-q"});
    }

    // The work dir serves one run: its spec names the trace, what the shards
    // simulate (any shard count: each count's files have their own names)
    // and hashes of every input and of the model; results made from other
    // inputs are refused, or removed with --fresh.
    const json spec = {{"raplas_version", RAPLAS_VERSION},
                       {"trace", make_trace},
                       {"simulate", sim},
                       {"inputs", hash_inputs(simulate_inputs(a))}};
    const std::string spec_path = wd + "/shards.json";
    bool write_spec = !is_file(spec_path);
    if (!write_spec) {
        json old;
        try {
            old = json::parse(read_file(spec_path));
        } catch (const json::parse_error&) {
        }
        if (old != spec) {
            std::string why = inputs_change(old.is_object() ? old.value("inputs", json()) : json(), spec["inputs"]);
            if (why.empty() || why == "the inputs differ")
                why = old.is_object() && old.value("raplas_version", json()) != spec["raplas_version"]
                          ? "another raplas version"
                          : "other commands: another config key, ICC count, FIFO depth or workload";
            if (!a.fresh)
                throw InputError(spec_path + ": the work dir holds the jobs of another run (" + why +
                                 "); give --fresh to remove its results, or another --work-dir");
            remove_files(wd, [&](const std::string& n) {
                return n.rfind("shard-", 0) == 0 || (a.trace.empty() && n == "workload.trace");
            });
            write_spec = true;
        }
    }
    if (write_spec) write_file_atomically(spec_path, spec.dump(2) + "\n");

    const std::string exe = self_exe();
    const std::string cd = "cd " + shell_quote(fs::current_path().string()) + " && ";
    auto line = [&](const std::string& product, const std::vector<std::string>& argv) {
        return cd + "{ test -f " + shell_quote(product) + " || " + shell_quote(exe) + " " + shell_join(argv) + "; }\n";
    };
    std::string jobs;
    std::vector<std::string> merge{"merge"};
    for (std::uint32_t i = 0; i < a.shards; ++i) {
        std::vector<std::string> argv = sim;
        argv.insert(argv.end(), {"--shard", std::to_string(i) + "/" + n, "--json", part(i), "-q"});
        jobs += line(part(i), argv);
        merge.push_back(part(i));
    }
    if (!a.json.empty()) merge.insert(merge.end(), {"--json", a.json});
    if (!a.csv.empty()) merge.insert(merge.end(), {"--csv", a.csv});
    const std::string traces_file = a.emit_jobs + ".traces", merge_file = a.emit_jobs + ".merge";
    if (!make_trace.empty()) write_file_atomically(traces_file, line(trace, make_trace));
    write_file_atomically(a.emit_jobs, jobs);
    write_file_atomically(merge_file, cd + shell_quote(exe) + " " + shell_join(merge) + "\n");
    if (!a.so.quiet) {
        const std::string shards = n + (a.shards == 1 ? " command" : " commands");
        if (make_trace.empty())
            std::printf("wrote %s (%s, one per shard) and %s; run them in that order, e.g.\n  parallel < %s && sh %s\n",
                        a.emit_jobs.c_str(), shards.c_str(), merge_file.c_str(), shell_quote(a.emit_jobs).c_str(),
                        shell_quote(merge_file).c_str());
        else
            std::printf("wrote %s (1 command: the trace), %s (%s, one per shard) and %s; run them in that order, e.g.\n"
                        "  parallel < %s && parallel < %s && sh %s\n",
                        traces_file.c_str(), a.emit_jobs.c_str(), shards.c_str(), merge_file.c_str(),
                        shell_quote(traces_file).c_str(), shell_quote(a.emit_jobs).c_str(),
                        shell_quote(merge_file).c_str());
    }
    return 0;
}

}  // namespace raplas
