#include "run_inputs.hpp"

#include "commands.hpp"
#include "config.hpp"
#include "model_identity.hpp"
#include "raplas/scene/scene.hpp"
#include "raplas/util/files.hpp"
#include "raplas/util/params.hpp"
#include "raplas/util/run_files.hpp"

namespace raplas {

using json = nlohmann::json;

namespace {

json file_entry(const std::string& path) { return {{"path", absolute_path(path)}, {"hash", file_hash(path)}}; }

}  // namespace

void add_scene_inputs(RunFiles& files, const SceneOptions& so) {
    ParamSet p = scene_params();
    if (!so.scene.empty()) {
        const std::string file = find_scene_file(so.scene);
        files.input("--scene", file);
        p.load_file(file);
    }
    files.input("--mesh", so.mesh);
    for (const auto& s : so.sets) p.set(s);
    if (!so.mesh.empty()) return;
    for (const auto& m : scene_mesh_files(p, "")) files.input("the scene's mesh", m);
}

RunInputs simulate_inputs(const SimulateArgs& a) {
    RunInputs in;
    if (!a.so.scene.empty()) in.scene = find_scene_file(a.so.scene);
    in.mesh = a.so.mesh;
    in.trace = a.trace;
    if (!a.config.empty()) in.config = resolve_config(a.config);
    in.scene_sets = a.so.sets;
    ParamSet mp = model::machine_params();
    const ParamSet sp = scene_params();
    for (const auto& s : a.config_sets) {
        const auto [set, assignment] = route_assignment(s, {&mp, &sp});
        (set == 0 ? in.config_sets : in.scene_sets).push_back(assignment);
    }
    if (a.iccs) in.config_sets.push_back("machine.iccs=" + std::to_string(a.iccs));
    if (a.fifo) {
        in.config_sets.push_back("fifo.sphere_depth=" + std::to_string(a.fifo));
        in.config_sets.push_back("fifo.triangle_depth=" + std::to_string(a.fifo));
    }
    return in;
}

json hash_inputs(const RunInputs& in, bool hash_trace_file, const std::string& trace_content) {
    json j;
    j["model"] = model_identity();
    j["scene"] = in.scene.empty() ? json() : file_entry(in.scene);
    json meshes = json::array();
    if (in.trace.empty()) {
        ParamSet p = scene_params();
        if (!in.scene.empty()) p.load_file(in.scene);
        for (const auto& s : in.scene_sets) p.set(s);
        for (const auto& m : scene_mesh_files(p, in.mesh)) meshes.push_back(file_entry(m));
    }
    j["meshes"] = meshes;
    j["config"] = in.config.empty() ? json() : file_entry(in.config);
    j["sets"] = json::object({{"scene", in.scene_sets}, {"config", in.config_sets}});
    if (!in.trace.empty() && hash_trace_file && is_file(in.trace)) j["trace"] = file_entry(in.trace);
    else if (!trace_content.empty()) j["trace"] = {{"content", trace_content}};
    else j["trace"] = json();
    return j;
}

std::string inputs_change(const json& there, const json& here) {
    if (there == here) return "";
    auto get = [](const json& j, const char* k) { return j.is_object() && j.contains(k) ? j[k] : json(); };
    auto path_of = [](const json& e) { return e.is_object() ? e.value("path", std::string("?")) : std::string("?"); };
    if (get(there, "model") != get(here, "model"))
        return "raplas's model changed (model identity " + get(there, "model").dump() + " there, " +
               get(here, "model").dump() + " here: raplas was rebuilt from other sources)";
    for (const char* k : {"scene", "config", "trace"}) {
        const json a = get(there, k), b = get(here, k);
        if (a == b) continue;
        const std::string what = std::string(k) == "config" ? "the machine config" : std::string("the ") + k;
        if (a.is_object() && b.is_object() && path_of(a) == path_of(b))
            return what + " file " + path_of(b) + " changed";
        return what + " differs (" + (a.is_null() ? std::string("none") : path_of(a)) + " there, " +
               (b.is_null() ? std::string("none") : path_of(b)) + " here)";
    }
    const json ma = get(there, "meshes"), mb = get(here, "meshes");
    if (ma != mb) {
        if (ma.is_array() && mb.is_array() && ma.size() == mb.size())
            for (std::size_t i = 0; i < ma.size(); ++i)
                if (ma[i] != mb[i])
                    return path_of(ma[i]) == path_of(mb[i]) ? "the mesh file " + path_of(mb[i]) + " changed"
                                                            : "the scene's mesh differs (" + path_of(ma[i]) +
                                                                  " there, " + path_of(mb[i]) + " here)";
        return "the scene's mesh files differ";
    }
    if (get(there, "sets") != get(here, "sets"))
        return "the --set keys differ (" + get(there, "sets").dump() + " there, " + get(here, "sets").dump() + " here)";
    return "the inputs differ";
}

}  // namespace raplas
