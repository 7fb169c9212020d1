#include "frames.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>

#include "run_inputs.hpp"
#include "shard.hpp"

#include "raplas/app/processes.hpp"
#include "raplas/app/progress.hpp"
#include "raplas/app/sim_report.hpp"
#include "raplas/scene/animation.hpp"
#include "raplas/util/atomic_file.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"
#include "raplas/util/run_files.hpp"
#include "raplas/util/input_file.hpp"

namespace raplas {

namespace fs = std::filesystem;

namespace {

// A whole number 0..kMaxFrames written as digits only; -1 otherwise.
long frame_number_text(const std::string& t) {
    if (t.empty() || t.size() > 6 || t.find_first_not_of("0123456789") != std::string::npos) return -1;
    const long v = std::strtol(t.c_str(), nullptr, 10);
    return v <= kMaxFrames ? v : -1;
}

// The fields every frame of one run shares: written once, at the top.
const char* const kFrameCommonKeys[] = {"scene",  "config",         "overrides",   "config_hash", "resolved_config",
                               "iccs",   "fifo_depth",     "format",      "triangle_select",
                               "rdf_empty_cycles", "overlap_passes", "clock_mhz", "animation"};

}  // namespace

std::string scene_frames_text(const std::string& scene_name, int frames) {
    return "the scene '" + scene_name + "' has " + std::to_string(frames) +
           (frames == 1 ? " frame (it is not animated: docs/SCENES.md, \"Animation\")"
                        : " frames (0 to " + std::to_string(frames - 1) + ")");
}

FrameRange parse_frames(const std::string& spec, int frames, const std::string& scene_name) {
    const std::string head = "--frames '" + spec + "': ";
    const std::string has = scene_frames_text(scene_name, frames);
    FrameRange r;
    if (spec == "all") {
        r.last = frames - 1;
        return r;
    }
    const std::size_t colon = spec.find(':');
    if (colon == std::string::npos) {
        const long n = frame_number_text(spec);
        if (n < 1) throw InputError(head + "give a frame count N (1.." + std::to_string(kMaxFrames) + "), A:B or all");
        if (n > frames) throw InputError(head + has);
        r.last = int(n) - 1;
        return r;
    }
    const long a = frame_number_text(spec.substr(0, colon)), b = frame_number_text(spec.substr(colon + 1));
    if (a < 0 || b < 0) throw InputError(head + "A:B takes two frame numbers, e.g. 0:7 (both included)");
    if (a > b) throw InputError(head + "the first frame is after the last");
    if (b >= frames) throw InputError(head + has);
    r.first = int(a);
    r.last = int(b);
    return r;
}

void check_frame_pattern(const std::string& pattern, const std::string& option) {
    try {
        (void)sequence_file_name(pattern, 0);
    } catch (const std::invalid_argument& e) {
        throw InputError(option + " '" + pattern + "' " + e.what() + " (one file per frame: e.g. frame_%04d.png)");
    }
}

std::string frame_file(const std::string& pattern, int frame) { return sequence_file_name(pattern, frame); }

void check_frame_leftovers(const std::string& pattern, const std::string& option, const FrameRange& range) {
    // The frame number's place: a number wider than any padding, found again.
    constexpr long long kMark = 987654321;
    const std::string marked = sequence_file_name(pattern, kMark);
    const std::size_t at = marked.find(std::to_string(kMark));
    if (at == std::string::npos) return;
    const std::string suffix = marked.substr(at + 9);
    if (suffix.find('/') != std::string::npos) return;  // the number names a folder: not looked into
    const std::size_t slash = marked.rfind('/', at);
    const std::string dir = slash == std::string::npos ? "." : marked.substr(0, slash + 1);
    const std::string prefix = slash == std::string::npos ? marked.substr(0, at) : marked.substr(slash + 1, at - slash - 1);
    std::vector<std::string> other;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string n = e.path().filename().string();
        if (n.size() <= prefix.size() + suffix.size() || n.compare(0, prefix.size(), prefix) != 0 ||
            n.compare(n.size() - suffix.size(), suffix.size(), suffix) != 0)
            continue;
        const std::string digits = n.substr(prefix.size(), n.size() - prefix.size() - suffix.size());
        if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
        const long long f = std::stoll(digits);
        if (fs::path(frame_file(pattern, int(f))).filename() != n) continue;  // another padding
        if (f < range.first || f > range.last) other.push_back(n);
    }
    if (other.empty()) return;
    std::sort(other.begin(), other.end());
    std::string list;
    for (std::size_t k = 0; k < other.size() && k < 3; ++k) list += (k ? ", " : "") + other[k];
    if (other.size() > 3) list += ", ... (" + std::to_string(other.size()) + " files)";
    throw InputError(option + " " + pattern + ": " + list + (other.size() == 1 ? " is a frame" : " are frames") +
                     " of another run (this one writes frames " + std::to_string(range.first) + " to " +
                     std::to_string(range.last) + "); remove " + (other.size() == 1 ? "it" : "them") +
                     " or choose another pattern, so that the folder holds one run's frames");
}

nlohmann::json frames_json(const std::vector<nlohmann::json>& per_frame, const nlohmann::json& t) {
    nlohmann::json j;
    const nlohmann::json& first = per_frame.at(0);
    for (const char* k : kFrameCommonKeys)
        if (first.contains(k)) j[k] = first[k];
    nlohmann::json frames = nlohmann::json::array();
    std::size_t worst = 0;
    for (std::size_t i = 0; i < per_frame.size(); ++i) {
        const nlohmann::json& f = per_frame[i];
        nlohmann::json e;
        e["frame"] = f.at("frame");
        for (const auto& [k, v] : f.items()) {
            bool common = k == "frame" || k == "iccs_detail" || k == "inputs";
            for (const char* c : kFrameCommonKeys) common = common || k == c;
            if (!common) e[k] = v;
        }
        e["fps_at_clock"] = fps_at_clock(f.at("time_ms").get<double>());
        if (f.at("total_cycles").get<std::uint64_t>() > per_frame[worst].at("total_cycles").get<std::uint64_t>()) worst = i;
        frames.push_back(std::move(e));
    }
    const double time_ms = t.at("time_ms").get<double>();
    const double worst_ms = per_frame[worst].at("time_ms").get<double>();
    const double rate = first.contains("animation") ? first["animation"].value("fps", 0.0) : 0.0;
    j["frames"] = std::move(frames);
    j["totals"] = {{"frames", per_frame.size()},
                   {"total_cycles", t.at("total_cycles")},
                   {"time_ms", time_ms},
                   {"fps_at_clock", time_ms > 0 ? 1e3 * double(per_frame.size()) / time_ms : 0.0},
                   {"worst_frame", per_frame[worst].at("frame")},
                   {"worst_frame_cycles", per_frame[worst].at("total_cycles")},
                   {"worst_frame_time_ms", worst_ms},
                   {"worst_fps_at_clock", fps_at_clock(worst_ms)},
                   {"keeps_animation_rate", worst_ms > 0 && 1e3 / worst_ms >= rate},
                   {"passes", t.at("passes")},
                   {"ray_groups", t.at("ray_groups")},
                   {"estimated", t.contains("estimate")},
                   {"functional_checked", t.at("functional_checked")},
                   {"functional_match", t.at("functional_match")},
                   {"rays_checked", t.at("rays_checked")},
                   {"rays_mismatched", t.at("rays_mismatched")},
                   {"wall", {{"frontend_s", t.at("wall").at("frontend_s")}, {"model_s", t.at("wall").at("model_s")}}}};
    return j;
}

nlohmann::json animation_totals_json(const std::vector<nlohmann::json>& per_frame) {
    using ptr = nlohmann::json::json_pointer;
    nlohmann::json t = per_frame.at(0);
    t.erase("iccs_detail");
    t.erase("pass_cycles");
    t.erase("first_mismatch");
    t.erase("frame");
    t.erase("inputs");
    static const char* const sums[] = {
        "/total_cycles", "/time_ms", "/passes", "/primary_passes", "/ray_groups", "/primary_groups",
        "/workload/plane_sphere_tests", "/workload/sphere_hits", "/workload/ray_triangle_tests",
        "/workload/pairless_spheres", "/links/sphere/records_sent", "/links/sphere/stall_cycles",
        "/links/sphere/idle_cycles", "/links/sphere/bytes", "/links/triangle/records_sent",
        "/links/triangle/stall_cycles", "/links/triangle/idle_cycles", "/links/triangle/bytes", "/links/output/bytes",
        "/icc_totals/rti_busy_cycles", "/icc_totals/blocked_triangle_fifo_full", "/icc_totals/blocked_undecided",
        "/icc_totals/blocked_sphere_fifo_full", "/memory/sphere_records_read", "/memory/triangle_records_read",
        "/memory/memory_bound_cycles", "/memory/pe_bound_cycles", "/rays_checked", "/rays_mismatched",
        "/wall/frontend_s", "/wall/model_s"};
    static const char* const maxima[] = {"/icc_totals/max_triangle_fifo_occupancy",
                                         "/icc_totals/max_sphere_fifo_occupancy",
                                         "/icc_totals/max_planeid_fifo_occupancy"};
    std::string hashes;
    double active = 0;  // ICC pass cycles, for the RTI utilisation
    bool match = true, checked = true;
    for (std::size_t i = 0; i < per_frame.size(); ++i) {
        const nlohmann::json& f = per_frame[i];
        hashes += f.value("workload_hash", "") + ";";
        match = match && f.at("functional_match").get<bool>();
        checked = checked && f.at("functional_checked").get<bool>();
        if (f.contains("iccs_detail"))
            for (const auto& k : f["iccs_detail"]) active += k.value("active_cycles", 0.0);
        if (f.contains("estimate") && !t.contains("estimate")) t["estimate"] = f["estimate"];
        if (i == 0) continue;
        for (const char* p : sums) {
            const ptr q(p);
            if (!t.contains(q) || !f.contains(q)) continue;
            if (t[q].is_number_float() || f[q].is_number_float()) t[q] = t[q].get<double>() + f[q].get<double>();
            else t[q] = t[q].get<std::uint64_t>() + f[q].get<std::uint64_t>();
        }
        for (const char* p : maxima) {
            const ptr q(p);
            if (t.contains(q) && f.contains(q)) t[q] = std::max(t[q].get<std::uint64_t>(), f[q].get<std::uint64_t>());
        }
    }
    t["functional_match"] = match;
    t["functional_checked"] = checked;
    t["workload_hash"] = hex64(fnv1a64(hashes));
    const double seconds = t["time_ms"].get<double>() / 1e3;
    for (const char* link : {"sphere", "triangle"})
        if (t.contains(ptr(std::string("/links/") + link + "/bytes")))
            t["links"][link]["average_bandwidth_gbps"] =
                seconds > 0 ? t["links"][link]["bytes"].get<double>() / seconds / 1e9 : 0.0;
    if (active > 0) t["icc_totals"]["rti_utilisation"] = t["icc_totals"]["rti_busy_cycles"].get<double>() / active;
    if (t.contains(ptr("/area/total"))) t["area_time"] = t["area"]["total"].get<double>() * t["total_cycles"].get<double>();
    return t;
}

std::string animation_row_csv(const nlohmann::json& totals, std::uint64_t frames, int worst_frame,
                              std::uint64_t worst_cycles, double worst_ms) {
    std::string header = sim_csv_header(), row = sim_csv_row(totals);
    header.pop_back();
    row.pop_back();
    char buf[128];
    std::snprintf(buf, sizeof buf, ",%llu,%d,%llu,%.10g\n", (unsigned long long)frames, worst_frame,
                  (unsigned long long)worst_cycles, fps_at_clock(worst_ms));
    return header + ",frames,worst_frame,worst_frame_cycles,worst_fps_at_clock\n" + row + buf;
}

std::string frames_csv(const std::vector<nlohmann::json>& per_frame) {
    std::string out = "frame,fps_at_clock," + sim_csv_header();
    for (const auto& f : per_frame) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%d,%.10g,", f.at("frame").get<int>(), fps_at_clock(f.at("time_ms").get<double>()));
        out += buf + sim_csv_row(f);
    }
    return out;
}

std::string frames_summary(const nlohmann::json& j) {
    std::string o;
    char buf[512];
    const double mhz = j.at("clock_mhz").get<double>();
    for (const auto& f : j.at("frames")) {
        std::snprintf(buf, sizeof buf, "frame %d: %llu cycles = %.4g ms at %.0f MHz = %.4g frames/s, %llu passes, %llu ray groups%s\n",
                      f.at("frame").get<int>(), (unsigned long long)f.at("total_cycles").get<std::uint64_t>(),
                      f.at("time_ms").get<double>(), mhz, f.at("fps_at_clock").get<double>(),
                      (unsigned long long)f.at("passes").get<std::uint64_t>(),
                      (unsigned long long)f.at("ray_groups").get<std::uint64_t>(),
                      f.contains("estimate") ? " (estimate)" : "");
        o += buf;
    }
    const nlohmann::json& t = j.at("totals");
    std::snprintf(buf, sizeof buf,
                  "%s on %s: %u ICCs, %llu frames: %llu cycles = %.4g ms, %.4g frames/s on average; worst frame %d: "
                  "%.4g frames/s (the animation: %.4g frames/s)\n",
                  j.at("config").get<std::string>().c_str(), j.at("scene").get<std::string>().c_str(),
                  j.at("iccs").get<unsigned>(), (unsigned long long)t.at("frames").get<std::uint64_t>(),
                  (unsigned long long)t.at("total_cycles").get<std::uint64_t>(), t.at("time_ms").get<double>(),
                  t.at("fps_at_clock").get<double>(), t.at("worst_frame").get<int>(),
                  t.at("worst_fps_at_clock").get<double>(), j.at("animation").at("fps").get<double>());
    o += buf;
    return o;
}

namespace {

// The options of one frame's run (simulate --frame F, without --frame,
// --json and -q): this run's scene, config and model options.
std::vector<std::string> frame_run_args(const SimulateArgs& a, unsigned threads) {
    std::vector<std::string> v;
    if (!a.so.scene.empty()) v.insert(v.end(), {"--scene", a.so.scene});
    if (!a.so.mesh.empty()) v.insert(v.end(), {"--mesh", a.so.mesh});
    if (!a.config.empty()) v.insert(v.end(), {"--config", a.config});
    for (const auto& s : a.config_sets) v.insert(v.end(), {"--set", s});
    if (a.iccs) v.insert(v.end(), {"--iccs", std::to_string(a.iccs)});
    if (a.fifo) v.insert(v.end(), {"--fifo", std::to_string(a.fifo)});
    if (a.so.no_cull) v.push_back("--no-cull");
    v.insert(v.end(), {"--window", std::to_string(a.window)});
    if (a.whole_frame) v.push_back("--whole-frame");
    if (threads) v.insert(v.end(), {"--threads", std::to_string(threads)});
    return v;
}

// simulate --frames --emit-jobs FILE: a line per frame, and the merge.
int emit_frame_jobs(const SimulateArgs& a, const FrameRange& range) {
    if (a.json.empty() && a.csv.empty())
        throw InputError("--emit-jobs: give --json OUT.json, --csv OUT.csv or both: what the merge writes");
    check_result_path("--json", a.json, {});
    check_result_path("--csv", a.csv, {});
    const std::string wd = absolute_path(a.work_dir.empty() ? (a.json.empty() ? a.csv : a.json) + ".d" : a.work_dir);
    std::error_code ec;
    fs::create_directories(wd, ec);
    if (!fs::is_directory(wd)) throw InputError("--work-dir " + wd + ": cannot create the directory");
    const std::vector<std::string> common = frame_run_args(a, a.so.threads);
    // The work dir serves one run: the frames' command and hashes of every
    // input and of the model; frame results made from other inputs are
    // refused, or removed with --fresh.
    const nlohmann::json spec = {{"simulate", common}, {"inputs", hash_inputs(simulate_inputs(a))}};
    const std::string spec_path = wd + "/frames.json";
    bool write_spec = true;
    if (is_file(spec_path)) {
        nlohmann::json old;
        try {
            old = nlohmann::json::parse(read_file(spec_path));
        } catch (const nlohmann::json::parse_error&) {
        }
        write_spec = old != spec;
        if (write_spec) {
            std::string why =
                inputs_change(old.is_object() ? old.value("inputs", nlohmann::json()) : nlohmann::json(), spec["inputs"]);
            if (why.empty() || why == "the inputs differ")
                why = "other commands: another config key, ICC count, FIFO depth or option";
            if (!a.fresh)
                throw InputError(spec_path + ": the work dir holds the frames of another run (" + why +
                                 "); give --fresh to remove its results, or another --work-dir");
            remove_files(wd, [](const std::string& n) { return n.rfind("frame-", 0) == 0; });
        }
    } else {
        const auto is_frame = [](const std::string& n) { return n.rfind("frame-", 0) == 0; };
        if (a.fresh) remove_files(wd, is_frame);
        else
            for (const auto& e : fs::directory_iterator(wd))
                if (is_frame(e.path().filename().string()))
                    throw InputError(wd + ": holds frame results but no frames.json; give --fresh to remove them, or "
                                          "another --work-dir");
    }
    if (write_spec) write_file_atomically(spec_path, spec.dump(2) + "\n");
    const std::string exe = self_exe();
    const std::string cd = "cd " + shell_quote(fs::current_path().string()) + " && ";

    std::string jobs;
    std::vector<std::string> merge{"merge"};
    for (int f = range.first; f <= range.last; ++f) {
        const std::string part = wd + "/frame-" + std::to_string(f) + ".json";
        std::vector<std::string> argv{"simulate", "--frame", std::to_string(f), "--json", part, "-q"};
        argv.insert(argv.end(), common.begin(), common.end());
        jobs += cd + "{ test -f " + shell_quote(part) + " || " + shell_quote(exe) + " " + shell_join(argv) + "; }\n";
        merge.push_back(part);
    }
    if (!a.json.empty()) merge.insert(merge.end(), {"--json", a.json});
    if (!a.csv.empty()) merge.insert(merge.end(), {"--csv", a.csv});
    const std::string merge_file = a.emit_jobs + ".merge";
    write_file_atomically(a.emit_jobs, jobs);
    write_file_atomically(merge_file, cd + shell_quote(exe) + " " + shell_join(merge) + "\n");
    if (!a.so.quiet)
        std::printf("wrote %s (%d commands, one per frame) and %s; run them in that order, e.g.\n  parallel < %s && sh %s\n",
                    a.emit_jobs.c_str(), range.count(), merge_file.c_str(), shell_quote(a.emit_jobs).c_str(),
                    shell_quote(merge_file).c_str());
    return 0;
}

}  // namespace

int simulate_frames(const SimulateArgs& a, const SceneOptions& so_in) {
    if (!a.trace.empty()) throw UsageError("--frames simulates the frames of a scene; a trace holds one frame");
    if (so_in.frame >= 0) throw UsageError("give either --frame F or --frames, not both");
    if (a.shards) throw UsageError("--frames: no --shards (each frame is one job of --emit-jobs: docs/ANIMATION.md)");
    if (!a.shard.empty()) throw UsageError("--frames: no --shard (frames are shared out as --frame F runs: docs/ANIMATION.md)");
    if (!a.vcd.empty()) throw UsageError("--frames: no --vcd (a waveform covers one frame: simulate it with --frame F)");
    SceneOptions so = so_in;
    so.animate = true;
    Scene scene;
    double load_s = 0;
    if (!so.load(scene, load_s)) return 0;
    const int total = frame_count(scene);
    const FrameRange range = parse_frames(a.frames, total, scene.name);

    if (!a.emit_jobs.empty()) return emit_frame_jobs(a, range);
    const unsigned jobs = std::min<unsigned>(a.jobs ? a.jobs : core_count(), unsigned(range.count()));
    const std::vector<std::string> common = frame_run_args(a, a.so.threads ? a.so.threads : std::max(1u, core_count() / jobs));

    // The frames' results and logs, in a temporary directory removed at the end.
    const TempDir temp("frames", "--frames");
    const std::string& dir = temp.path();
    auto result_of = [&](int f) { return dir + "/frame-" + std::to_string(f) + ".json"; };
    auto log_of = [&](int f) { return dir + "/frame-" + std::to_string(f) + ".log"; };

    ProgressLine progress(so.show_progress(), ::isatty(2));
    const std::size_t n = std::size_t(range.count());
    std::size_t done = 0;
    int next = range.first;
    ProcessPool pool(jobs);
    const std::string exe = self_exe();
    while (done < n) {
        while (!pool.full() && next <= range.last) {
            std::vector<std::string> args{"simulate", "--frame", std::to_string(next), "--json", result_of(next), "-q"};
            args.insert(args.end(), common.begin(), common.end());
            pool.start(std::size_t(next), args, log_of(next));
            ++next;
        }
        progress.draw(done, n, "frames", "", done, n);
        const auto ended = pool.wait(0.5);
        if (!ended) continue;
        const int f = int(ended->tag);
        if (!WIFEXITED(ended->status) || WEXITSTATUS(ended->status) != 0) {
            progress.finish();
            std::string line = last_line(log_of(f));
            for (const char* prefix : {"raplas: error: ", "raplas: internal error: "})
                if (line.rfind(prefix, 0) == 0) line = line.substr(std::string(prefix).size());
            const bool input = WIFEXITED(ended->status) && WEXITSTATUS(ended->status) == kExitInputError;
            std::cerr << "raplas: " << (input ? "error: " : "internal error: ") << "frame " << f << ": "
                      << (line.empty() ? "simulate --frame " + std::to_string(f) + " ended with " + exit_text(ended->status)
                                       : line)
                      << "\n";
            return input ? kExitInputError : kExitInternalError;
        }
        ++done;
    }
    progress.draw(done, n, "frames", "", done, n);
    progress.finish();

    std::vector<nlohmann::json> per_frame;
    for (int f = range.first; f <= range.last; ++f) per_frame.push_back(nlohmann::json::parse(read_file(result_of(f))));
    const nlohmann::json totals = animation_totals_json(per_frame);
    const nlohmann::json j = frames_json(per_frame, totals);
    if (!a.json.empty()) write_file_atomically(a.json, j.dump(2) + "\n");
    if (!a.csv.empty()) {
        const nlohmann::json& t = j["totals"];
        write_file_atomically(a.csv, a.animation_row
                                         ? animation_row_csv(totals, per_frame.size(), t["worst_frame"].get<int>(),
                                                             t["worst_frame_cycles"].get<std::uint64_t>(),
                                                             t["worst_frame_time_ms"].get<double>())
                                         : frames_csv(per_frame));
    }
    if (!so.quiet) std::cout << frames_summary(j);
    return 0;
}

namespace {
const TextInput kFrameResult{"frame result", "a", "frame result", 8.0, true};
}  // namespace

bool is_frame_result(const std::string& path) {
    if (!is_file(path)) return false;  // a pipe is read once: by the merge of shards, which says what it is
    try {
        const nlohmann::json j = nlohmann::json::parse(read_text_input(path, kFrameResult));
        return j.is_object() && j.contains("frame") && !j.contains("shard");
    } catch (const std::exception&) {
        return false;
    }
}

int merge_frames(const MergeArgs& a) {
    if (a.json.empty() && a.csv.empty()) throw InputError("merge: give --json OUT.json, --csv OUT.csv or both");
    check_result_path("--json", a.json, a.parts);
    check_result_path("--csv", a.csv, a.parts);
    if (same_file(a.json, a.csv))
        throw InputError("--csv " + a.csv + ": is also the output --json " + a.json + "; give each output its own file");
    std::map<int, std::pair<std::string, nlohmann::json>> frames;  // by frame: file, result
    const std::string what = "a result of raplas simulate --frame F --json";
    for (const auto& file : a.parts) {
        nlohmann::json j;
        try {
            j = nlohmann::json::parse(read_text_input(file, kFrameResult));
        } catch (const nlohmann::json::parse_error&) {
            throw InputError(file + ": not JSON (truncated or corrupt); expected " + what);
        }
        // What frames_json() and frames_csv() read, with the right types.
        auto bad = [&](const std::string& key) { return InputError(file + ": '" + key + "' missing or of the wrong type; expected " + what); };
        if (!j.is_object() || !j.contains("frame") || !j["frame"].is_number_unsigned()) throw bad("frame");
        for (const char* k : {"total_cycles", "passes", "ray_groups", "rays_checked", "rays_mismatched"})
            if (!j.contains(k) || !j[k].is_number_unsigned()) throw bad(k);
        for (const char* k : {"time_ms", "clock_mhz"})
            if (!j.contains(k) || !j[k].is_number()) throw bad(k);
        for (const char* k : {"functional_checked", "functional_match"})
            if (!j.contains(k) || !j[k].is_boolean()) throw bad(k);
        for (const char* k : {"scene", "config", "config_hash"})
            if (!j.contains(k) || !j[k].is_string()) throw bad(k);
        if (!j.contains("iccs") || !j["iccs"].is_number_unsigned()) throw bad("iccs");
        if (!j.contains("animation") || !j["animation"].is_object() || !j["animation"].contains("fps") ||
            !j["animation"]["fps"].is_number())
            throw bad("animation");
        if (!j.contains("wall") || !j["wall"].is_object() || !j["wall"].contains("frontend_s") ||
            !j["wall"]["frontend_s"].is_number() || !j["wall"].contains("model_s") || !j["wall"]["model_s"].is_number())
            throw bad("wall");
        try {
            (void)sim_csv_row(j);
        } catch (const std::exception&) {
            throw InputError(file + ": not every figure of a simulate result is there; expected " + what);
        }
        if (!frames.empty()) {
            const auto& [ffile, first] = frames.begin()->second;
            for (const char* k : {"scene", "config_hash", "animation", "iccs"})
                if (j[k] != first[k])
                    throw InputError(file + ": another run than " + ffile + " ('" + k + "' differs): merge the frames of one run");
            if (j.value("inputs", nlohmann::json()) != first.value("inputs", nlohmann::json()))
                throw InputError(file + ": made from other inputs than " + ffile + " (" +
                                 inputs_change(first.value("inputs", nlohmann::json()), j.value("inputs", nlohmann::json())) +
                                 "): merge the frames of one run");
        }
        const int f = j["frame"].get<int>();
        if (const auto it = frames.find(f); it != frames.end())
            throw InputError(file + ": frame " + std::to_string(f) + " is also in " + it->second.first);
        frames.emplace(f, std::make_pair(file, std::move(j)));
    }
    const int first = frames.begin()->first, last = frames.rbegin()->first;
    for (int f = first; f <= last; ++f)
        if (!frames.count(f))
            throw InputError("merge: frame " + std::to_string(f) + " is missing (the parts hold frames " +
                             std::to_string(first) + " to " + std::to_string(last) + ")");
    std::vector<nlohmann::json> per_frame;
    for (auto& [f, fj] : frames) per_frame.push_back(std::move(fj.second));
    const nlohmann::json j = frames_json(per_frame, animation_totals_json(per_frame));
    if (!a.json.empty()) write_file_atomically(a.json, j.dump(2) + "\n");
    if (!a.csv.empty()) write_file_atomically(a.csv, frames_csv(per_frame));
    if (!a.quiet) std::cout << frames_summary(j);
    return 0;
}

}  // namespace raplas
