#include "raplas/app/sim_report.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <string_view>

#include "config.hpp"
#include "raplas/app/csv_table.hpp"
#include "raplas/util/files.hpp"

namespace raplas {

namespace {

nlohmann::json fifo_json(const model::FifoStats& f, std::uint32_t depth) {
    return {{"depth", depth}, {"pushes", f.pushes}, {"max_occupancy", f.max_occupancy}, {"full_cycles", f.full_cycles}};
}

// The area block (docs/MODEL.md §6): under the blocks model each block of one
// ICC, the same summed over the ICCs, the scene memories and the total.
nlohmann::json area_json(const model::AreaBreakdown& b, const model::AreaParams& a) {
    const nlohmann::json note = b.note.empty() ? nlohmann::json(nullptr) : nlohmann::json(b.note);
    if (b.model == model::AreaModel::pe_units)
        return {{"model", model::area_model_name(b.model)},
                {"unit", "PE"},
                {"iccs", b.iccs},
                {"pe", a.pe},
                {"memory", a.memory},
                {"icc_fifos", a.icc_fifos},
                {"total", b.total},
                {"note", note}};
    const double k = b.iccs;
    return {{"model", model::area_model_name(b.model)},
            {"unit", "slice-equivalents"},
            {"iccs", b.iccs},
            {"per_icc",
             {{"psi", b.psi},
              {"rti", b.rti},
              {"fixed",
               {{"triangle_selector", b.triangle_selector},
                {"ray_data_fetcher", b.ray_data_fetcher},
                {"decoders", b.decoders},
                {"sphere_selector", b.sphere_selector},
                {"total", b.fixed()}}},
              {"fifos",
               {{"sphere", b.sphere_fifo},
                {"triangle", b.triangle_fifo},
                {"planeid", b.planeid_fifo},
                {"first_tri", b.first_tri_fifo},
                {"total", b.fifos()}}},
              {"ray_memories", {{"ray", b.ray_memory}, {"min_distance", b.min_distance_memory}, {"total", b.ray_memories()}}},
              {"total", b.icc()}}},
            {"scene_memories",
             {{"sphere", b.sphere_memory},
              {"triangle", b.triangle_memory},
              {"copies", b.scene_copies},
              {"total", b.scene_copies * b.scene_memory()}}},
            {"totals",
             {{"psi", k * b.psi},
              {"rti", k * b.rti},
              {"fixed", k * b.fixed()},
              {"fifos", k * b.fifos()},
              {"ray_memories", k * b.ray_memories()},
              {"iccs", k * b.icc()},
              {"scene_memories", b.scene_copies * b.scene_memory()}}},
            {"total", b.total},
            {"note", note}};
}

// The flat columns: (CSV name, JSON pointer).
const std::vector<std::pair<const char*, const char*>>& columns() {
    static const std::vector<std::pair<const char*, const char*>> c = {
        {"scene", "/scene"},
        {"config", "/config"},
        {"overrides", "/overrides"},
        {"iccs", "/iccs"},
        {"fifo_depth", "/fifo_depth/triangle"},
        {"sphere_fifo_depth", "/fifo_depth/sphere"},
        {"planeid_fifo_depth", "/fifo_depth/planeid"},
        {"format", "/format"},
        {"triangle_select", "/triangle_select"},
        {"rdf_empty_cycles", "/rdf_empty_cycles"},
        {"overlap_passes", "/overlap_passes"},
        {"total_cycles", "/total_cycles"},
        {"time_ms", "/time_ms"},
        {"passes", "/passes"},
        {"ray_groups", "/ray_groups"},
        {"primary_groups", "/primary_groups"},
        {"spheres", "/spheres"},
        {"triangles", "/triangles"},
        {"group_size", "/group_size"},
        {"shadow_group_size", "/shadow_group_size"},
        {"triangles_per_sphere", "/triangles_per_sphere"},
        {"sphere_hits", "/workload/sphere_hits"},
        {"ray_triangle_tests", "/workload/ray_triangle_tests"},
        {"pairless_spheres", "/workload/pairless_spheres"},
        {"sphere_link_records", "/links/sphere/records_sent"},
        {"sphere_link_stall_cycles", "/links/sphere/stall_cycles"},
        {"sphere_link_bytes", "/links/sphere/bytes"},
        {"triangle_link_records", "/links/triangle/records_sent"},
        {"triangle_link_stall_cycles", "/links/triangle/stall_cycles"},
        {"triangle_link_bytes", "/links/triangle/bytes"},
        {"sphere_link_peak_gbps", "/links/sphere/peak_bandwidth_gbps"},
        {"triangle_link_peak_gbps", "/links/triangle/peak_bandwidth_gbps"},
        {"triangle_link_avg_gbps", "/links/triangle/average_bandwidth_gbps"},
        {"rti_busy_cycles", "/icc_totals/rti_busy_cycles"},
        {"rti_utilisation", "/icc_totals/rti_utilisation"},
        {"blocked_triangle_fifo_full", "/icc_totals/blocked_triangle_fifo_full"},
        {"blocked_undecided", "/icc_totals/blocked_undecided"},
        {"blocked_sphere_fifo_full", "/icc_totals/blocked_sphere_fifo_full"},
        {"max_triangle_fifo_occupancy", "/icc_totals/max_triangle_fifo_occupancy"},
        {"triangle_link_fifo_held_cycles", "/stall_anatomy/fifo_held_cycles"},
        {"triangle_link_held_alone_cycles", "/stall_anatomy/alone_cycles"},
        {"functional_checked", "/functional_checked"},
        {"functional_match", "/functional_match"},
        {"memory_system", "/memory/system"},
        {"area", "/area/total"},
        {"area_time", "/area_time"},
        {"sphere_records_read", "/memory/sphere_records_read"},
        {"triangle_records_read", "/memory/triangle_records_read"},
        {"memory_bound_cycles", "/memory/memory_bound_cycles"},
        {"pe_bound_cycles", "/memory/pe_bound_cycles"},
        {"engine", "/engine"},
        {"estimate", "/estimate/mode"},  // "exact" when the JSON has no estimate block
        {"config_hash", "/config_hash"},
        {"workload_hash", "/workload_hash"},
    };
    return c;
}

nlohmann::json param_json(const ParamSet& p, const std::string& key) {
    switch (p.type(key)) {
        case ParamSet::Type::Int: return p.get_int(key);
        case ParamSet::Type::Real: return p.get_real(key);
        case ParamSet::Type::Bool: return p.get_bool(key);
        case ParamSet::Type::String: return p.get_string(key);
        case ParamSet::Type::Vec3: {
            const auto v = p.get_vec3(key);
            if (!v) return nullptr;
            return nlohmann::json::array({v->x, v->y, v->z});
        }
        case ParamSet::Type::Tables: return p.value_text(key);
    }
    return nullptr;
}

}  // namespace

Provenance make_provenance(ParamSet named, ParamSet resolved, const std::string& workload_hash) {
    model::resolve_numerics(named);
    model::resolve_numerics(resolved);
    Provenance p;
    p.resolved_config = nlohmann::json::object();
    for (const std::string& k : resolved.keys()) {
        const std::string v = resolved.value_text(k);
        p.resolved_config[k] = param_json(resolved, k);
        if (v != named.value_text(k)) p.overrides.emplace_back(k, v);
    }
    p.config_hash = config_hash(resolved);
    p.workload_hash = workload_hash;
    return p;
}

std::string config_hash(ParamSet resolved) {
    model::resolve_numerics(resolved);
    std::string canonical;
    for (const std::string& k : resolved.keys())
        if (k != "name" && !model::result_neutral_key(k)) canonical += k + "=" + resolved.value_text(k) + "\n";
    return hex64(fnv1a64(canonical));
}

WorkloadFacts workload_facts(const Trace& t, const WorkloadTally& tally, const model::SimResult& r) {
    WorkloadFacts w;
    w.ray_groups = tally.groups;
    w.untraced_groups = tally.untraced;
    w.primary_groups = t.primary_groups;
    w.spheres = t.spheres.size();
    w.triangles = t.triangles.size();
    w.group_size = t.group_size;
    w.shadow_group_size = t.shadow_group_size;
    w.triangles_per_sphere = t.tris_per_sphere;
    w.counts = tally.counts;
    if (r.first_mismatch) {
        w.mismatch_primary = r.first_mismatch->primary;
        w.mismatch_px = r.first_mismatch->px;
        w.mismatch_py = r.first_mismatch->py;
    }
    return w;
}

nlohmann::json sim_json(const SimReportInput& in) {
    const model::SimResult& r = *in.result;
    const model::SimConfig& c = *in.config;
    const WorkloadFacts& t = *in.workload;
    const double seconds = double(r.total_cycles) / (c.clock_mhz * 1e6);
    nlohmann::json j;
    j["scene"] = in.scene_name;
    j["config"] = in.config_name;
    if (in.provenance) {
        const Provenance& p = *in.provenance;
        j["overrides"] = nlohmann::json::object();
        for (const auto& [k, v] : p.overrides) j["overrides"][k] = p.resolved_config[k];
        j["config_hash"] = p.config_hash;
        j["workload_hash"] = p.workload_hash;
        j["resolved_config"] = p.resolved_config;
    } else {
        j["overrides"] = nlohmann::json::object();
        j["config_hash"] = "";
        j["workload_hash"] = "";
    }
    j["iccs"] = c.iccs;
    j["fifo_depth"] = {{"sphere", c.icc.sphere_fifo.depth},
                       {"triangle", c.icc.triangle_fifo.depth},
                       {"planeid", c.icc.planeid_fifo.depth}};
    j["format"] = c.format.name();
    const bool any = c.icc.decoder.select == model::TriangleSelect::any;
    j["triangle_select"] = model::triangle_select_name(c.icc.decoder.select);
    j["rdf_empty_cycles"] = c.icc.fetcher.empty_cycles;
    j["overlap_passes"] = c.overlap_passes;
    j["clock_mhz"] = c.clock_mhz;
    j["engine"] = model::sim_mode_name(c.mode);
    j["total_cycles"] = r.total_cycles;
    if (r.lower_bound)
        j["estimate"] = {{"mode", "fifo_bound"},
                         {"lower_bound", true},
                         {"passes_simulated", 0},
                         {"note", "total_cycles and time_ms are a lower bound of the exact count (every pass timed "
                                  "with unbounded Triangle, PlaneID and First-Triangle-ID FIFOs, in closed form); "
                                  "per-block statistics are not computed"}};
    else if (r.estimated)
        j["estimate"] = {{"mode", "sample_passes"},
                         {"sample_fraction", c.sample_fraction},
                         {"sample_seed", c.sample_seed},
                         {"passes_simulated", r.pass_cycles.size()},
                         {"pass_index", r.pass_index},
                         {"ci95_cycles", r.estimate_ci95},
                         {"note", "total_cycles and time_ms are estimates; other statistics cover the simulated passes"}};
    j["time_ms"] = seconds * 1e3;
    j["passes"] = r.host.passes;
    j["primary_passes"] = r.host.primary_passes;
    j["ray_groups"] = t.ray_groups;
    j["primary_groups"] = t.primary_groups;
    if (t.untraced_groups) j["untraced_groups"] = t.untraced_groups;
    j["spheres"] = t.spheres;
    j["triangles"] = t.triangles;
    j["group_size"] = t.group_size;
    j["shadow_group_size"] = t.shadow_group_size;
    j["triangles_per_sphere"] = t.triangles_per_sphere;
    const GroupCounts& wc = t.counts;
    j["workload"] = {{"plane_sphere_tests", wc.plane_tests},
                     {"sphere_hits", wc.sphere_hits},
                     {"ray_triangle_tests", wc.rt_tests},
                     {"pairless_spheres", any ? wc.pairless : 0}};
    auto link = [&](const model::StreamLink::Stats& s, std::uint32_t bytes) {
        return nlohmann::json{{"records_sent", s.records_sent},
                              {"stall_cycles", s.stall_cycles},
                              {"idle_cycles", s.idle_cycles},
                              {"bytes", s.bytes},
                              {"record_bytes", bytes},
                              {"peak_bandwidth_gbps", bytes * c.clock_mhz * 1e6 / 1e9},
                              {"average_bandwidth_gbps", seconds > 0 ? double(s.bytes) / seconds / 1e9 : 0.0}};
    };
    std::uint64_t out_bytes = 0;
    for (const auto& s : r.iccs) out_bytes += s.output.bytes;
    j["links"] = {{"sphere", link(r.sphere_link, c.sphere_record_bytes)},
                  {"triangle", link(r.triangle_link, c.triangle_record_bytes)},
                  {"output", {{"bytes", out_bytes}}}};
    {
        // The stall anatomy of the Triangle Stream Link (docs/MODEL.md §3):
        // its stalled cycles by how many ICCs' Triangle FIFOs held it.
        const model::StreamLink::Stats& tl = r.triangle_link;
        std::uint64_t held = 0, icc_held = 0, alone = 0;
        nlohmann::json bins = nlohmann::json::array();
        const std::size_t top = model::StreamLink::held_bin(std::max<std::uint64_t>(c.iccs, 1));
        for (std::size_t b = 0; b <= top; ++b) {
            bins.push_back({{"iccs", model::StreamLink::held_bin_name(b)}, {"cycles", tl.held_by[b]}});
            held += tl.held_by[b];
        }
        for (const auto& s : r.iccs) {
            icc_held += s.triangle_selector.blocked_fifo_full;
            alone += s.triangle_selector.blocked_alone;
        }
        j["stall_anatomy"] = {{"triangle_link_stall_cycles", tl.stall_cycles},
                              {"fifo_held_cycles", held},
                              {"undecided_only_cycles", tl.stall_cycles - held},
                              {"icc_held_cycles", icc_held},
                              {"mean_holders", held ? double(icc_held) / double(held) : 0.0},
                              {"alone_cycles", alone},
                              {"held_by", bins}};
    }
    j["pass_cycles"] = r.pass_cycles;
    nlohmann::json iccs = nlohmann::json::array();
    std::uint64_t rti_busy = 0, b_full = 0, b_undec = 0, b_sph = 0, max_tri = 0, max_sph = 0, max_pid = 0, pass_cycles = 0;
    for (std::size_t k = 0; k < r.iccs.size(); ++k) {
        const model::IccSnapshot& s = r.iccs[k];
        rti_busy += s.rti.busy_cycles;
        b_full += s.triangle_selector.blocked_fifo_full;
        b_undec += s.triangle_selector.blocked_undecided;
        b_sph += s.sphere_selector.blocked_link_cycles;
        max_tri = std::max(max_tri, s.triangle_fifo.max_occupancy);
        max_sph = std::max(max_sph, s.sphere_fifo.max_occupancy);
        max_pid = std::max(max_pid, s.planeid_fifo.max_occupancy);
        pass_cycles += s.icc.pass_cycles;
        iccs.push_back({
            {"icc", k},
            {"groups", s.icc.groups},
            {"active_cycles", s.icc.pass_cycles},
            {"idle_cycles", s.icc.idle_cycles},
            {"busy_cycles", s.rti.busy_cycles},
            {"stall_cycles",
             {{"link_blocked_triangle_fifo_full", s.triangle_selector.blocked_fifo_full},
              {"link_blocked_sphere_undecided", s.triangle_selector.blocked_undecided},
              {"link_blocked_triangle_fifo_alone", s.triangle_selector.blocked_alone},
              {"link_blocked_sphere_fifo_full", s.sphere_selector.blocked_link_cycles},
              {"psi_held_decoder_full", s.psi.stall_cycles},
              {"psi_starved", s.psi.starved_cycles},
              {"rti_starved", s.ray_data_fetcher.starved_cycles}}},
            {"sphere_fifo", fifo_json(s.sphere_fifo, c.icc.sphere_fifo.depth)},
            {"planeid_fifo", fifo_json(s.planeid_fifo, c.icc.planeid_fifo.depth)},
            {"first_tri_fifo", fifo_json(s.first_tri_fifo, c.icc.planeid_fifo.depth)},
            {"triangle_fifo", fifo_json(s.triangle_fifo, c.icc.triangle_fifo.depth)},
            {"psi", {{"spheres", s.psi.spheres}, {"plane_tests", s.psi.plane_tests}, {"busy_cycles", s.psi.busy_cycles}}},
            {"decoder", {{"decided", s.decoder.decided}, {"sphere_hits", s.decoder.sphere_hits}, {"pairless", s.decoder.pairless}}},
            {"ray_data_fetcher", {{"triangles", s.ray_data_fetcher.triangles}, {"empty_triangles", s.ray_data_fetcher.empty_triangles}}},
            {"triangle_selector", {{"selected", s.triangle_selector.selected}, {"discarded", s.triangle_selector.discarded}}},
            {"rti", {{"tests", s.rti.tests}, {"hits", s.rti.hits}}},
            {"output_link", {{"records", s.output.records}, {"bytes", s.output.bytes}}},
        });
    }
    j["icc_totals"] = {{"rti_busy_cycles", rti_busy},
                       {"rti_utilisation", pass_cycles ? double(rti_busy) / double(pass_cycles) : 0.0},
                       {"blocked_triangle_fifo_full", b_full},
                       {"blocked_undecided", b_undec},
                       {"blocked_sphere_fifo_full", b_sph},
                       {"max_triangle_fifo_occupancy", max_tri},
                       {"max_sphere_fifo_occupancy", max_sph},
                       {"max_planeid_fifo_occupancy", max_pid}};
    j["iccs_detail"] = iccs;
    model::MemoryStats ms;
    if (in.memory) ms = *in.memory;
    else
        ms.system = c.memory.system,
        ms.area = model::machine_area(c, model::area_workload(t.spheres, t.triangles, t.group_size,
                                                              t.shadow_group_size, c));
    j["memory"] = {{"system", model::memory_system_name(ms.system)},
                   {"pe", c.memory.pe_rti_bound ? "rti" : "ideal"},
                   {"sphere_records_read", ms.sphere_records_read},
                   {"triangle_records_read", ms.triangle_records_read},
                   {"memory_bound_cycles", ms.memory_bound_cycles},
                   {"pe_bound_cycles", ms.pe_bound_cycles}};
    j["area"] = area_json(ms.area, c.area);
    j["area_time"] = ms.area.total * double(r.total_cycles);
    j["functional_checked"] = r.functional_checked;
    j["functional_match"] = r.functional_match;
    j["rays_checked"] = r.rays_checked;
    j["rays_mismatched"] = r.rays_mismatched;
    j["first_mismatch"] = nullptr;
    if (r.first_mismatch) {
        const auto& m = *r.first_mismatch;
        const bool primary = t.mismatch_primary;
        auto hit = [](const Hit& x) {
            return x.tri < 0 ? nlohmann::json(nullptr) : nlohmann::json{{"triangle", x.tri}, {"t", x.t}};
        };
        j["first_mismatch"] = {{"group", m.group},
                               {"kind", primary ? "primary" : "shadow"},
                               {"ray", {m.h, m.v}},
                               {"pixel", {t.mismatch_px + (primary ? std::int32_t(m.h) : 0), t.mismatch_py + (primary ? std::int32_t(m.v) : 0)}},
                               {"model", hit(m.model)},
                               {"frontend", hit(m.frontend)}};
    }
    const double w = r.model_wall_s > 0 ? r.model_wall_s : 1e-9;
    j["wall"] = {{"frontend_s", in.frontend_wall_s},
                 {"model_s", r.model_wall_s},
                 {"sim_cycles_per_second", double(r.total_cycles) / w},
                 {"sim_icc_cycles_per_second", double(r.total_cycles) * c.iccs / w}};
    if (in.cpu_s > 0) {
        // Where the CPU time went; the front end's share is the rest (scene
        // loading, sphere build, tracing, or reading a trace).
        j["wall"]["cpu_s"] = in.cpu_s;
        j["wall"]["model_cpu_s"] = r.model_cpu_s;
        j["wall"]["loads_cpu_s"] = r.loads_cpu_s;
        j["wall"]["observers_cpu_s"] = r.observers_cpu_s;
        j["wall"]["frontend_cpu_s"] = std::max(0.0, in.cpu_s - r.model_cpu_s - r.loads_cpu_s - r.observers_cpu_s);
        j["wall"]["model_waits_s"] = r.model_waits_s;
        j["wall"]["load_waits_s"] = r.load_waits_s;
        j["wall"]["frontend_waits_s"] = in.frontend_waits_s;
    }
    if (in.shards) {
        j["wall"]["shards"] = in.shards;
        j["wall"]["model_s_max"] = in.model_wall_max_s;
    }
    return j;
}

std::string describe_mismatch(const nlohmann::json& m) {
    if (m.is_null()) return "none";
    auto hit = [](const nlohmann::json& x) {
        if (x.is_null()) return std::string("no hit");
        std::ostringstream o;
        o.precision(9);
        o << "triangle " << x["triangle"].get<std::int64_t>() << " at t = " << x["t"].get<double>();
        return o.str();
    };
    std::ostringstream o;
    const auto& ray = m["ray"];
    const auto& px = m["pixel"];
    o << m["kind"].get<std::string>() << " ray (h " << ray[0].get<std::uint32_t>() << ", v " << ray[1].get<std::uint32_t>()
      << ") of group " << m["group"].get<std::size_t>() << ", pixel (" << px[0].get<std::int32_t>() << ", "
      << px[1].get<std::int32_t>() << "): model " << hit(m["model"]) << ", front end " << hit(m["frontend"]);
    return o.str();
}

std::string sim_csv_header() {
    std::string h;
    for (const auto& [name, ptr] : columns()) h += (h.empty() ? "" : ",") + std::string(name);
    return h + "\n";
}

std::string sim_csv_row(const nlohmann::json& j) {
    std::string row;
    for (const auto& [name, ptr] : columns()) {
        const nlohmann::json::json_pointer p(ptr);
        // Only the estimate block may be absent: a run without one is exact.
        if (std::string_view(name) == "estimate" && !j.contains(p)) {
            row += std::string(row.empty() ? "" : ",") + "exact";
            continue;
        }
        const auto& v = j.at(p);
        std::string cell;
        if (std::string_view(name) == "overrides") {  // key=value;key=value
            for (const auto& [k, x] : v.items())
                cell += (cell.empty() ? "" : ";") + k + "=" + (x.is_string() ? x.get<std::string>() : x.dump());
            row += (row.empty() ? "" : ",") + csv_cell(cell);
            continue;
        }
        if (v.is_string()) cell = v.get<std::string>();
        else if (v.is_boolean()) cell = v.get<bool>() ? "true" : "false";
        else if (v.is_number_float()) {
            char buf[64];
            std::snprintf(buf, sizeof buf, "%.10g", v.get<double>());
            cell = buf;
        } else cell = v.dump();
        row += (row.empty() ? "" : ",") + csv_cell(cell);
    }
    return row + "\n";
}

std::string sim_summary(const nlohmann::json& j) {
    std::ostringstream o;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s on %s: %u ICCs, FIFO %u: %llu cycles = %.4g ms at %.0f MHz, %llu passes, %llu ray groups\n",
                  j["config"].get<std::string>().c_str(), j["scene"].get<std::string>().c_str(), j["iccs"].get<unsigned>(),
                  j["fifo_depth"]["triangle"].get<unsigned>(), (unsigned long long)j["total_cycles"].get<std::uint64_t>(),
                  j["time_ms"].get<double>(), j["clock_mhz"].get<double>(),
                  (unsigned long long)j["passes"].get<std::uint64_t>(), (unsigned long long)j["ray_groups"].get<std::uint64_t>());
    o << buf;
    if (j.contains("estimate") && j["estimate"]["mode"] == "fifo_bound") {
        o << "  estimate: lower bound, every FIFO but the Sphere FIFO unbounded (closed form, nothing simulated)\n";
    } else if (j.contains("estimate")) {
        std::snprintf(buf, sizeof buf, "  estimate: %llu of %llu passes simulated, total cycles +/- %.3g (95 %%)\n",
                      (unsigned long long)j["estimate"]["passes_simulated"].get<std::uint64_t>(),
                      (unsigned long long)j["passes"].get<std::uint64_t>(), j["estimate"]["ci95_cycles"].get<double>());
        o << buf;
    }
    if (j.contains("estimate") && j["estimate"]["mode"] == "fifo_bound") {
        // no block statistics to print
    } else if (j["memory"]["system"] == "streaming") {
        std::snprintf(buf, sizeof buf,
                      "  links: sphere %llu records, %llu stall cycles; triangle %llu records, %llu stall cycles; RTI utilisation %.1f %%\n",
                      (unsigned long long)j["links"]["sphere"]["records_sent"].get<std::uint64_t>(),
                      (unsigned long long)j["links"]["sphere"]["stall_cycles"].get<std::uint64_t>(),
                      (unsigned long long)j["links"]["triangle"]["records_sent"].get<std::uint64_t>(),
                      (unsigned long long)j["links"]["triangle"]["stall_cycles"].get<std::uint64_t>(),
                      100.0 * j["icc_totals"]["rti_utilisation"].get<double>());
        o << buf;
    } else {
        std::snprintf(buf, sizeof buf,
                      "  %s memory (closed form, PEs %s): %llu sphere and %llu triangle records read\n",
                      j["memory"]["system"].get<std::string>().c_str(), j["memory"]["pe"].get<std::string>().c_str(),
                      (unsigned long long)j["memory"]["sphere_records_read"].get<std::uint64_t>(),
                      (unsigned long long)j["memory"]["triangle_records_read"].get<std::uint64_t>());
        o << buf;
    }
    const nlohmann::json& area = j["area"];
    if (area["model"] == "pe_units") {
        std::snprintf(buf, sizeof buf, "  area %.6g PE (area.model = pe_units), area x time %.6g\n",
                      area["total"].get<double>(), j["area_time"].get<double>());
    } else {
        const nlohmann::json& per = area["per_icc"];
        std::snprintf(buf, sizeof buf,
                      "  area %.6g slice-equivalents: %u ICCs of %.6g (PSI %.6g, RTI %.6g, fixed %.6g, FIFOs %.6g, "
                      "Ray and Min-distance Memories %.6g) + scene memories %.6g; area x time %.6g\n",
                      area["total"].get<double>(), area["iccs"].get<unsigned>(), per["total"].get<double>(),
                      per["psi"].get<double>(), per["rti"].get<double>(), per["fixed"]["total"].get<double>(),
                      per["fifos"]["total"].get<double>(), per["ray_memories"]["total"].get<double>(),
                      area["scene_memories"]["total"].get<double>(), j["area_time"].get<double>());
    }
    o << buf;
    if (!area["note"].is_null()) o << "  area note: " << area["note"].get<std::string>() << "\n";
    std::string fm = j["functional_checked"].get<bool>() ? (j["functional_match"].get<bool>() ? "true" : "FALSE") : "not checked";
    std::snprintf(buf, sizeof buf, "  functional_match: %s (%llu rays); model %.3f s wall, %.3g ICC-cycles/s\n", fm.c_str(),
                  (unsigned long long)j["rays_checked"].get<std::uint64_t>(), j["wall"]["model_s"].get<double>(),
                  j["wall"]["sim_icc_cycles_per_second"].get<double>());
    o << buf;
    return o.str();
}

}  // namespace raplas
