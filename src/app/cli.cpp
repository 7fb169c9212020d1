#include "raplas/app/cli.hpp"

#include "commands.hpp"
#include "frames.hpp"
#include "front_end_thread.hpp"
#include "config.hpp"
#include "memory_checks.hpp"
#include "run_inputs.hpp"
#include "shard.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>

#include "raplas/app/image_io.hpp"
#include "raplas/app/progress.hpp"
#include "raplas/app/processes.hpp"
#include "raplas/app/reports.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/scene/animation.hpp"
#include "raplas/util/atomic_file.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"
#include "raplas/util/memory_budget.hpp"
#include "raplas/util/run_files.hpp"

#ifndef RAPLAS_VERSION
#define RAPLAS_VERSION "unknown"
#endif

namespace raplas {

namespace {

double since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// One frame: the image files asked for, unless quiet the summary, and with
// `report` the JSON report (as an object; else null: the sphere qualities it
// needs, a second sphere build among them, are not computed).
nlohmann::json render_one(const Scene& scene, const SceneOptions& so, double load_s, const std::string& out_png,
                          const std::string& heatmap, const std::string& hits, bool report, PhaseProgress* progress,
                          SphereCache* spheres = nullptr, AnimationWriter* gif = nullptr) {
    const NumFormat fmt = so.parsed_format();
    RenderReport rep;
    rep.load_s = load_s;
    FrameOptions fo;
    fo.format = fmt;
    fo.threads = so.threads;
    fo.cull = !so.no_cull;
    fo.per_ray = !heatmap.empty();
    fo.sphere_cache = spheres;
    check_front_end(FrontEndUse::render, scene, fo);
    if (progress) fo.progress = std::ref(*progress);
    Frame frame = render_frame(scene, fo);
    if (progress) progress->finish();
    auto t0 = std::chrono::steady_clock::now();
    if (!out_png.empty()) write_rgb_image(out_png, frame.width, frame.height, frame.rgb);
    if (gif) gif->add(frame.rgb);
    if (!heatmap.empty()) write_heatmap(heatmap, frame.width, frame.height, frame.work_rt);
    if (!hits.empty()) write_file_atomically(hits, hits_csv(frame));
    rep.write_s = since(t0);
    rep.scene = &scene;
    rep.frame = &frame;
    rep.format = fmt;
    if (!so.quiet) {
        std::cout << render_summary(rep);
        if (!out_png.empty()) std::cout << "  wrote " << out_png << "\n";
    }
    if (!report) return nullptr;
    rep.quality = sphere_quality(frame.spheres);
    rep.naive_quality = sphere_quality(build_spheres(scene.mesh, scene.tris_per_sphere, "file-order", frame.sphere_margin));
    return nlohmann::json::parse(render_json(rep));
}

int cmd_render(const SceneOptions& so_in, std::string out_png, bool out_given, const std::string& heatmap,
               const std::string& hits, const std::string& json, const std::string& frames, const std::string& gif) {
    SceneOptions so = so_in;
    so.animate = !frames.empty();
    if (so.animate && so.frame >= 0) throw UsageError("give either --frame F or --frames, not both");
    (void)so.parsed_format();
    Scene scene;
    double load_s = 0;
    if (!so.load(scene, load_s)) return 0;
    if (!gif.empty() && !so.animate) throw UsageError("--gif writes the frames of --frames as one animated GIF: give --frames");
    if (!gif.empty() && (gif.size() < 4 || gif.substr(gif.size() - 4) != ".gif"))
        throw UsageError("--gif " + gif + ": the name must end in .gif");
    // What the run reads and writes, checked before any work.
    RunFiles files;
    add_scene_inputs(files, so);
    std::optional<FrameRange> range;
    if (so.animate) {
        range = parse_frames(frames, frame_count(scene), scene.name);
        if (!out_given) out_png = "frame_%04d.png";
        check_frame_pattern(out_png, "--out");
        if (!heatmap.empty()) check_frame_pattern(heatmap, "--heatmap");
        if (!hits.empty()) check_frame_pattern(hits, "--hits");
        for (const auto& [option, pattern] : {std::pair<const char*, std::string>{"--out", out_png},
                                              {"--heatmap", heatmap}, {"--hits", hits}}) {
            if (pattern.empty()) continue;
            check_frame_leftovers(pattern, option, *range);
            for (int f = range->first; f <= range->last; ++f) files.output(option, frame_file(pattern, f));
        }
        files.output("--gif", gif);
    } else {
        files.output("--out", out_png);
        files.output("--heatmap", heatmap);
        files.output("--hits", hits);
    }
    files.output("--json", json);
    files.check();
    if (!out_png.empty() || !heatmap.empty() || !gif.empty()) load_image_module();
    if (!so.animate) {
        PhaseProgress progress(so.show_progress(), ::isatty(2));
        nlohmann::json j = render_one(scene, so, load_s, out_png, heatmap, hits, !json.empty(), &progress);
        if (so.frame >= 0) j["frame"] = so.frame;
        if (!json.empty()) write_file_atomically(json, j.dump(2) + "\n");
        return 0;
    }
    // --frames: one image (and heat map, hits) per frame, named by a pattern.
    ProgressLine progress(so.show_progress(), ::isatty(2));
    nlohmann::json all = {{"scene", scene.name},
                          {"animation", {{"frames", frame_count(scene)}, {"fps", scene.animation ? scene.animation->fps : 0.0}}},
                          {"frames", nlohmann::json::array()}};
    const std::size_t n = std::size_t(range->count());
    SphereCache spheres;  // static geometry: the spheres are built once (bit for bit the same)
    std::unique_ptr<AnimationWriter> animation;
    if (!gif.empty())
        animation = std::make_unique<AnimationWriter>(gif, scene.width, scene.height,
                                                      scene.animation ? scene.animation->fps : 24.0);
    for (int f = range->first; f <= range->last; ++f) {
        progress.draw(std::size_t(f - range->first), n, "frames", "", std::size_t(f - range->first), n);
        const Scene at = scene_at_frame(scene, f);
        if (!so.quiet) std::cout << "frame " << f << ": ";
        nlohmann::json j = render_one(at, so, f == range->first ? load_s : 0.0, frame_file(out_png, f),
                                      heatmap.empty() ? "" : frame_file(heatmap, f), hits.empty() ? "" : frame_file(hits, f),
                                      !json.empty(), nullptr, &spheres, animation.get());
        if (json.empty()) continue;
        j["frame"] = f;
        all["frames"].push_back(std::move(j));
    }
    progress.draw(n, n, "frames", "", n, n);
    progress.finish();
    if (animation) {
        animation->finish();
        if (!so.quiet) std::cout << "wrote " << gif << " (" << n << " frames)\n";
    }
    if (!json.empty()) write_file_atomically(json, all.dump(2) + "\n");
    return 0;
}

// Groups the front end of `raplas trace` may trace ahead of the writer.
constexpr std::uint32_t kTraceWindowGroups = 256;

}  // namespace

bool write_streamed_trace(GroupStream& stream, TraceWriter& w, double& waited_s,
                          const std::function<void(std::uint64_t, std::uint64_t)>& written,
                          const std::function<void(const Trace&, const TraceGroup*)>& observe) {
    struct Stopped {};  // the front end stopped: it says why
    auto wait = [&](auto&& ready) {
        const auto w0 = std::chrono::steady_clock::now();
        const bool ok = ready();
        waited_s += since(w0);
        if (!ok) throw Stopped{};
    };
    try {
        const Trace* header = nullptr;
        wait([&] {
            try {
                header = &stream.header();
                return true;
            } catch (...) {
                return false;
            }
        });
        w.header(*header);
        if (observe) observe(*header, nullptr);
        const std::uint64_t primary = header->primary_groups;
        for (std::uint64_t i = 0;; ++i) {
            if (i == primary) {
                wait([&] { return stream.wait_total(); });
                w.total(stream.total_groups());
            }
            if (i >= primary && i == stream.total_groups()) break;
            wait([&] { return stream.wait_for(std::size_t(i + 1)); });
            w.group(stream.group(std::size_t(i)));
            if (observe) observe(*header, &stream.group(std::size_t(i)));
            stream.release(std::size_t(i + 1));
            if (written) written(i + 1, i >= primary || stream.total_known() ? stream.total_groups() : primary);
        }
        w.finish();
    } catch (const Stopped&) {
        return false;
    }
    return true;
}

namespace {

int cmd_trace(const SceneOptions& so, const std::string& out, const std::string& json, const std::string& select) {
    NumFormat fmt = so.parsed_format();
    Scene scene;
    RenderReport rep;
    if (!so.load(scene, rep.load_s)) return 0;
    RunFiles files;
    add_scene_inputs(files, so);
    files.output("--out", out);
    files.output("--json", json);
    files.check();
    FrameOptions fo;
    fo.format = fmt;
    fo.threads = so.threads;
    fo.cull = !so.no_cull;
    fo.record = true;
    fo.pairless = select == "any";
    // The front end hands each group to this thread, which writes it into
    // its block as it comes (docs/TRACE.md): only a window of groups and one
    // block are held, into a temporary file renamed at the END block.
    GroupStream stream(kTraceWindowGroups);
    fo.stream = &stream;
    check_front_end(FrontEndUse::trace_streamed, scene, fo, nullptr, kTraceWindowGroups);
    PhaseProgress progress(so.show_progress(), ::isatty(2));
    fo.progress = std::ref(progress);
    Frame frame;
    FrontEndThread frontend;
    frontend.start(stream, [&frame, &scene, fo] { frame = render_frame(scene, fo); });
    struct Stopped {};  // the front end stopped: it says why
    std::uint64_t bytes = 0, groups = 0;
    auto t0 = std::chrono::steady_clock::now();
    double wait_s = 0;
    try {
        write_atomically(out, [&](const std::string& tmp) {
            std::ofstream f(tmp, std::ios::binary);
            if (!f) throw InputError(out + ": cannot write the trace: " + std::strerror(errno));
            TraceWriter w([&](const char* p, std::size_t n) {
                if (!f.write(p, std::streamsize(n))) throw InputError(out + ": cannot write the trace: " + std::strerror(errno));
            });
            if (!write_streamed_trace(stream, w, wait_s)) throw Stopped{};  // (no file is left)
            f.close();
            if (!f) throw InputError(out + ": cannot write the trace: " + std::strerror(errno));
            bytes = w.bytes();
            groups = w.groups();
        });
    } catch (const Stopped&) {
    }
    frontend.join();
    progress.finish();
    if (!frontend.error().empty()) {
        if (frontend.input_error()) throw InputError(frontend.error());
        throw std::runtime_error(frontend.error());
    }
    rep.write_s = std::max(0.0, since(t0) - wait_s);  // writing, not waiting for the front end
    rep.scene = &scene;
    rep.frame = &frame;
    rep.format = fmt;
    rep.quality = sphere_quality(frame.spheres);
    if (!json.empty()) write_file_atomically(json, render_json(rep));
    if (!so.quiet) {
        std::cout << render_summary(rep);
        std::cout << "  wrote " << out << " (" << bytes << " bytes, " << groups << " ray groups)\n";
    }
    return 0;
}

}  // namespace

void SceneOptions::add_to(CLI::App* cmd, bool with_format) {
    cmd->add_option("--scene", scene,
                    "scene file (TOML, see docs/SCENES.md) or the name of a shipped one (bunny, cornell, ...); "
                    "default: the built-in scene");
    cmd->add_option("--mesh", mesh, "any OBJ file, framed and lit automatically");
    cmd->add_option("--set", sets, "override a scene key, e.g. --set image.width=128 (repeatable)");
    if (with_format)
        cmd->add_option("--format", format, "number format of the intersection tests: float32, float64, fp1-E-M[-rtz][-ftz][-psiunnorm]; "
                        "-wt at the end: watertight ray-triangle test (docs/ACCURACY.md)");
    cmd->add_option("--threads", threads, "worker threads of the front end (default: all cores)")
        ->check(CLI::Range(0u, 1024u));
    cmd->add_flag("--no-cull", no_cull,
                  "front end: test every sphere against every group (results are identical; only slower)");
    cmd->add_option("--frame", frame,
                    "draw frame F of the scene's animation instead of the still scene (the built-in scene: its "
                    "built-in animation; docs/SCENES.md, \"Animation\")")
        ->check(CLI::Range(0, kMaxFrames - 1));
    cmd->add_flag("--dump-scene", dump_scene, "print the resolved scene as TOML and exit");
    cmd->add_flag("-q,--quiet", quiet, "no summary on stdout");
    cmd->add_flag("--progress", progress,
                  "progress with ETA on stderr, one line per update (default: when stderr is a terminal and not -q)");
}

bool SceneOptions::show_progress() const { return progress || (::isatty(2) && !quiet); }

NumFormat SceneOptions::parsed_format() const {
    try {
        return NumFormat::parse(format);
    } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--format: ") + e.what());
    }
}

bool SceneOptions::load(Scene& out, double& load_s, const std::function<void(ParamSet&)>& adjust) const {
    auto t0 = std::chrono::steady_clock::now();
    if (!scene.empty() && !mesh.empty()) throw UsageError("give either --scene or --mesh, not both");
    ParamSet p = scene_params();
    if (!scene.empty()) p.load_file(find_scene_file(scene));
    for (const auto& s : sets) {
        try {
            p.set(s);
        } catch (const InputError&) {
            // simulate and sweep route machine keys away before this; render and trace take none.
            const ParamSet machine = model::machine_params();
            const std::string key = s.substr(0, s.find('='));
            const std::vector<std::string> leaf = key.find('.') == std::string::npos ? machine.keys_with_leaf(key)
                                                                                    : std::vector<std::string>{};
            if (machine.has(key) || leaf.size() == 1)
                throw UsageError("--set " + (leaf.size() == 1 ? leaf[0] : key) +
                                 ": a machine config key; render and trace take scene keys only (raplas simulate "
                                 "and raplas sweep take both)");
            throw;
        }
    }
    if ((frame >= 0 || animate) && scene.empty() && mesh.empty() && !animation_keys_given(p))
        p.set("animation.builtin=default");
    if (adjust) adjust(p);
    out = scene_from_params(p, mesh);
    if (dump_scene) {  // what was chosen automatically, as values that can be pasted into a scene file
        resolve_scene_params(p, out, mesh.empty() ? mesh : absolute_path(mesh));
        std::cout << p.dump();
        return false;
    }
    for (const auto& w : out.mesh.warnings) std::cerr << "raplas: warning: " << InputError::printable(w) << "\n";
    frames_in_animation = frame_count(out);
    animation_fps = out.animation ? out.animation->fps : 0.0;
    if (frame >= 0) {
        if (frame >= frame_count(out))
            throw InputError("--frame " + std::to_string(frame) + ": " + scene_frames_text(out.name, frame_count(out)));
        out = scene_at_frame(out, frame);
    }
    load_s = since(t0);
    return true;
}

namespace {

// An integer as it is written in a config file: an optional sign and digits.
bool integer_text(const std::string& t) {
    const std::size_t start = !t.empty() && (t[0] == '-' || t[0] == '+') ? 1 : 0;
    return t.size() > start && t.find_first_not_of("0123456789", start) == std::string::npos;
}

// The integer a text that is not one was probably meant to be: 1e3 is
// 1000, and so are 1,000, 1_000, 1'000 and 1 000 (groups of three digits);
// "" when there is none.
std::string integer_meant(const std::string& t) {
    std::vector<std::string> groups(1);
    bool other = false;
    for (const char c : t) {
        if (std::isdigit(static_cast<unsigned char>(c))) groups.back() += c;
        else if (c == ',' || c == '_' || c == '\'' || c == ' ') groups.emplace_back();
        else other = true;
    }
    bool grouped = !other && groups.size() > 1 && !groups[0].empty() && groups[0].size() <= 3;
    std::string digits;
    for (std::size_t i = 0; i < groups.size(); ++i) {
        grouped = grouped && integer_text(groups[i]) && (i == 0 || groups[i].size() == 3);
        digits += groups[i];
    }
    if (grouped) return digits;
    char* end = nullptr;
    const double d = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0' || !std::isfinite(d) || d != std::floor(d) || std::fabs(d) >= 1e18) return "";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f", d);
    return buf;
}

// "" when `item` is an integer in 1..max; else what is wrong, quoting it as `shown`.
std::string count_problem(const std::string& item, const std::string& shown, std::uint32_t max) {
    if (!integer_text(item)) {
        const std::string meant = integer_meant(item);
        if (meant.empty()) return shown + " is not an integer";
        const double v = std::strtod(meant.c_str(), nullptr);
        if (v < 1 || v > max)  // the number meant is out of range too: say so rather than suggest it
            return shown + " is not an integer, and " + meant + " is not in 1.." + std::to_string(max);
        return shown + " is not an integer; write " + meant;
    }
    errno = 0;
    const long long v = std::strtoll(item.c_str(), nullptr, 10);
    if (errno == ERANGE || v < 1 || v > max) return shown + " is not in 1.." + std::to_string(max);
    return "";
}

}  // namespace

CLI::Validator count_check(std::uint32_t max, bool list) {
    auto check = [max, list](std::string& text) -> std::string {
        if (!list) return count_problem(text, integer_text(text) ? text : "'" + text + "'", max);
        std::vector<std::string> items;
        for (std::size_t start = 0;;) {
            const std::size_t comma = text.find(',', start);
            items.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        if (items.size() == 1) return count_problem(text, integer_text(text) ? text : "'" + text + "'", max);
        // 1,000 written for one thousand: every item after the first three digits
        bool thousands = items[0].size() >= 1 && items[0].size() <= 3;
        std::string joined = items[0];
        for (std::size_t i = 0; i < items.size(); ++i) {
            thousands = thousands && integer_text(items[i]) && items[i][0] != '+' && items[i][0] != '-' &&
                        (i == 0 || items[i].size() == 3);
            if (i) joined += items[i];
        }
        for (const auto& item : items) {
            if (item.empty()) return "'" + text + "' has an empty item";
            std::string p = count_problem(item, (integer_text(item) ? item : "'" + item + "'") + " in '" + text + "'", max);
            if (p.empty()) continue;
            if (thousands) p += "; ',' separates list items, so write " + joined + " for the number " + joined;
            return p;
        }
        return "";
    };
    return CLI::Validator(check, list ? "1.." + std::to_string(max) + ",..." : "1.." + std::to_string(max));
}

void check_not_set_by_option(const std::string& key, bool iccs_given, bool fifo_given) {
    const char* option = nullptr;
    if (iccs_given && key == "machine.iccs") option = "--iccs";
    if (fifo_given && (key == "fifo.sphere_depth" || key == "fifo.triangle_depth")) option = "--fifo";
    if (option) throw InputError("--set " + key + ": " + option + " sets it too; give one or the other");
}

std::vector<std::uint32_t> count_list(const std::vector<std::string>& texts) {
    std::vector<std::uint32_t> v;
    for (const auto& t : texts)
        for (std::size_t start = 0;;) {
            const std::size_t comma = t.find(',', start);
            v.push_back(std::uint32_t(std::stoul(t.substr(start, comma == std::string::npos ? std::string::npos : comma - start))));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
    return v;
}

int run_cli(int argc, char** argv) {
    CLI::App app{"raplas: cycle-accurate simulator of the RAPLAS ray-tracing accelerator (Kaeriyama et al., ICCD 2007)"};
    app.set_version_flag("--version", std::string("raplas ") + RAPLAS_VERSION);
    app.require_subcommand(1);

    SceneOptions render_so;
    std::string out_png = "render.png", heatmap, hits, json;
    auto* render = app.add_subcommand("render", "render a scene with the RAPLAS method and write a PNG");
    render_so.add_to(render);
    render->add_option("-o,--out", out_png, "output image (PNG)")->capture_default_str();
    render->add_option("--heatmap", heatmap, "per-pixel work heat map (ray-triangle tests, log scale) PNG");
    render->add_option("--hits", hits, "CSV, one row per primary ray: x,y,ox,oy,oz,dx,dy,dz,tri,t");
    render->add_option("--json", json, "counts and per-phase wall time as JSON");
    std::string render_frames;
    render->add_option("--frames", render_frames,
                       "render frames of the scene's animation: N (frames 0 to N-1), A:B (both included) or all; "
                       "--out (default frame_%04d.png), --heatmap and --hits are then patterns with a %d for the frame");
    std::string render_gif;
    render->add_option("--gif", render_gif,
                       "with --frames: also write the frames as one animated GIF, looping at the animation's rate");

    SceneOptions trace_so;
    std::string trace_out, trace_json, trace_select = "any";
    auto* trace = app.add_subcommand("trace", "write the profile trace the timing model consumes (docs/TRACE.md)");
    trace_so.add_to(trace);
    trace->add_option("-o,--out", trace_out, "trace file")->required();
    trace->add_option("--triangle-select", trace_select,
                      "the Triangle Selector reading the trace serves: any (records the spheres cut by row planes "
                      "only or column planes only too, for icc.triangle_select = any, the default; serves both "
                      "readings) or both (spheres cut by a row and a column plane only: a smaller trace)")
        ->check(CLI::IsMember({"both", "any"}))
        ->capture_default_str();
    trace->add_option("--json", trace_json, "counts and per-phase wall time as JSON");

    SimulateArgs sim;
    auto* simulate = app.add_subcommand("simulate", "run the front end and the cycle-accurate SystemC model");
    add_simulate_options(simulate, sim);

    MergeArgs merge_args;
    auto* merge = app.add_subcommand("merge", "add up the partial results of simulate --shard I/N into the whole run's "
                                              "JSON and CSV (docs/SHARDING.md)");
    add_merge_options(merge, merge_args);

    SweepArgs sweep_args;
    sweep_args.command_line = "raplas";
    for (int i = 1; i < argc; ++i) sweep_args.command_line += " " + shell_quote(argv[i]);
    auto* sweep = app.add_subcommand("sweep", "simulate every scene x varied key x ICC count x FIFO depth (docs/SWEEPS.md)");
    add_sweep_options(sweep, sweep_args);

    // --max-memory: the memory budget of every command (RAPLAS_MAX_MEMORY,
    // so that the processes of a sweep inherit it).
    std::string max_memory;
    for (auto* cmd : {render, trace, simulate, sweep, merge})
        cmd->add_option("--max-memory", max_memory,
                        "refuse runs estimated to need more memory than this, e.g. 4G, or off "
                        "(default: what the machine has available; docs/MEMORY.md)");

    // Where a wrong command line is explained: the help of the subcommand it was for.
    auto help = [&] {
        for (const auto* cmd : {render, trace, simulate, sweep, merge})
            if (cmd->parsed()) return " (see raplas " + cmd->get_name() + " --help)";
        return std::string(" (see raplas --help)");
    };
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "raplas: error: " << e.what() << help() << "\n";
        return kExitInputError;
    }
    try {
        if (!max_memory.empty()) {
            parse_memory_size(max_memory, "--max-memory");
            ::setenv("RAPLAS_MAX_MEMORY", max_memory.c_str(), 1);
        }
        if (render->parsed()) return cmd_render(render_so, out_png, render->count("--out") > 0, heatmap, hits, json, render_frames, render_gif);
        if (trace->parsed()) return cmd_trace(trace_so, trace_out, trace_json, trace_select);
        if (simulate->parsed()) return cmd_simulate(sim);
        if (sweep->parsed()) return cmd_sweep(sweep_args);
        if (merge->parsed()) return cmd_merge(merge_args);
    } catch (const UsageError& e) {
        std::cerr << "raplas: error: " << e.what() << help() << "\n";
        return kExitInputError;
    } catch (const InputError& e) {
        std::cerr << "raplas: error: " << e.what() << "\n";
        return kExitInputError;
    } catch (const std::bad_alloc&) {
        std::cerr << "raplas: error: out of memory\n";
        return kExitInternalError;
    } catch (const std::exception& e) {
        std::cerr << "raplas: internal error: " << e.what() << "\n";
        return kExitInternalError;
    }
    return kExitInputError;
}

}  // namespace raplas
