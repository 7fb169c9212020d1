// `raplas simulate`: front end (or a trace file) + the SystemC model.
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <memory>
#include <thread>

#include "baseline_memory.hpp"
#include "commands.hpp"
#include "frames.hpp"
#include "front_end_thread.hpp"
#include "config.hpp"
#include "memory_checks.hpp"
#include "raplas/app/progress.hpp"
#include "raplas/app/sim_report.hpp"
#include "run_inputs.hpp"
#include "shard.hpp"
#include "raplas/frontend/group_source.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/util/atomic_file.hpp"
#include "raplas/util/cpu_time.hpp"
#include "raplas/util/data_dir.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"
#include "raplas/util/run_files.hpp"

namespace raplas {

std::string resolve_config(const std::string& c) {
    return find_named_file(c, {"config", "configs", "machine configs", "raplas simulate --dump-config"});
}

void add_simulate_options(CLI::App* cmd, SimulateArgs& a) {
    a.so.add_to(cmd, false);
    cmd->add_option("--config,-c", a.config, "machine config: a TOML file or the name of a shipped one (paper, fpga)");
    cmd->add_option("--trace", a.trace, "simulate a trace file written by 'raplas trace' instead of a scene");
    cmd->add_option("--iccs,-k", a.iccs, "ICC count (sets machine.iccs; not with --set of it)")->check(count_check(4096, false));
    cmd->add_option("--fifo,-d", a.fifo, "Sphere and Triangle FIFO depth (sets fifo.sphere_depth and fifo.triangle_depth; not with --set of either)")
        ->check(count_check(100000000, false));
    cmd->add_option("--json", a.json, "all statistics as JSON");
    cmd->add_option("--csv", a.csv, "the main figures as one CSV row with a header");
    cmd->add_option("--vcd", a.vcd, "VCD waveform of every signal, port and FIFO of the netlist (GTKWave; runs sim.mode = netlist)");
    cmd->add_option("--shard", a.shard,
                    "I/N: simulate only shard I of N, the passes p with p mod N = I, and write its partial result to "
                    "--json for raplas merge (docs/SHARDING.md)");
    // (A shard process of --jobs: the process that feeds it the trace folds
    // the workload hash once for all shards; the partial result leaves it empty.)
    cmd->add_flag("--no-workload-hash", a.no_workload_hash)->group("");
    // (A sweep's point: the sweep folds the workload hash of each trace once
    // for all its points, as HASH@CONTENT, CONTENT the trace's content hash;
    // the point takes HASH when the trace it reads has that content.)
    cmd->add_option("--workload-hash", a.workload_hash)->group("");
    cmd->add_option("--shards", a.shards, "with --emit-jobs: the number of shards of the job lists")
        ->check(CLI::Range(1u, kMaxShards));
    cmd->add_option("--emit-jobs", a.emit_jobs,
                    "write the commands of a sharded run to FILE.traces (the trace, for a scene), FILE (one per shard) "
                    "and FILE.merge, for GNU parallel or a Slurm array, instead of simulating");
    cmd->add_option("--work-dir", a.work_dir, "with --emit-jobs: the trace and the shards' results (default: OUT.d)");
    cmd->add_flag("--fresh", a.fresh,
                  "with --emit-jobs: when the work dir holds results made from other inputs (scene, meshes, config, "
                  "--set keys, trace, or another build of raplas), remove them instead of refusing");
    cmd->add_option("--window", a.window,
                    "passes of ray groups the front end may trace ahead of the model (the groups in memory at once: "
                    "this many times the ICC count; docs/MEMORY.md)")
        ->check(CLI::Range(2u, 1000u))
        ->capture_default_str();
    cmd->add_flag("--whole-frame", a.whole_frame,
                  "trace the whole frame before the model starts instead of streaming its groups (the same results; "
                  "memory grows with the image)");
    cmd->add_flag("--sample-front-end", a.sample_front_end,
                  "with sim.estimate = sample_passes on a scene: the front end traces only the shadow groups of the "
                  "sampled passes (the same estimate, far sooner on big frames; the workload figures and "
                  "workload_hash then cover the traced groups, untraced_groups says how many were left)");
    cmd->add_option("--frames", a.frames,
                    "simulate frames of the scene's animation, each in its own process: N (frames 0 to N-1), A:B "
                    "(both included) or all; the JSON gets a frames array and totals, the CSV a row per frame "
                    "(docs/ANIMATION.md)");
    cmd->add_option("--jobs,-j", a.jobs,
                    "with --frames: frames simulated at once (default: the number of cores); on one frame: N shard "
                    "processes simulate its passes at once, fed by one front end, and their results are merged into "
                    "exactly the whole run's (default 1; docs/SHARDING.md)")
        ->check(CLI::Range(1u, 1024u));
    cmd->add_flag("--animation-row", a.animation_row,
                  "--csv writes one row with the columns frames, worst_frame, worst_frame_cycles and "
                  "worst_fps_at_clock added; with --frames the row of the totals (what a sweep of animated scenes "
                  "reads: docs/ANIMATION.md)");
    cmd->add_flag("--dump-config", a.dump_config, "print the resolved machine config as TOML and exit");
    // --set goes to the machine config when it names a config key, else to the scene.
    cmd->remove_option(cmd->get_option("--set"));
    cmd->add_option("--set", a.config_sets,
                    "override a config or scene key, e.g. --set fifo.planeid_depth=4, or by its last part when "
                    "one key ends in it: --set rti_pipes=2 (repeatable)");
}

void check_keys_apply(const ParamSet& mp, const std::vector<std::string>& config_keys,
                      const std::vector<std::string>& scene_sets, const std::string& trace) {
    for (const auto& k : config_keys)
        if (const std::string why = model::inert_config_key(mp, k); !why.empty())
            throw InputError("--set " + k + ": " + why + ", so it would change nothing");
    for (const auto& s : scene_sets) {
        const std::string k = s.substr(0, s.find('='));
        if (!trace.empty()) {
            // What the trace fixes: its header (read up to its HEAD block) says the value.
            const Trace h = TraceReader(trace).take_header();
            const std::pair<const char*, std::uint32_t> fixed[] = {
                {"image.width", h.width},  {"image.height", h.height}, {"groups.size", h.group_size},
                {"groups.shadow_size", h.shadow_group_size}, {"spheres.triangles_per_sphere", h.tris_per_sphere}};
            std::string there = "its scene '" + h.scene_name + "', " + std::to_string(h.width) + "x" +
                                std::to_string(h.height);
            for (const auto& [key, v] : fixed)
                if (k == key) there = k + " = " + std::to_string(v);
            throw InputError("--set " + s + ": a scene key, but the trace " + trace + " was made already (" + there +
                             " there); make a trace with it (raplas trace ... --set " + s + ") and simulate that");
        }
        if (const std::string why = model::inert_scene_key(mp, k); !why.empty())
            throw InputError("--set " + k + ": " + why + ", so it would change nothing");
    }
}

void check_trace_workload(const Trace& t, const ParamSet& mp, const std::string& name) {
    const std::uint32_t has[3] = {t.group_size, t.shadow_group_size, t.tris_per_sphere};
    for (int i = 0; i < 3; ++i) {
        const model::WorkloadKey& w = model::kWorkloadKeys[i];
        const auto want = std::uint32_t(mp.get_int(w.config_key));
        if (want == 0 || want == has[i]) continue;
        throw InputError(name + ": made with " + w.scene_key + " = " + std::to_string(has[i]) + ", but " +
                         mp.origin(w.config_key) + " gives " + w.config_key + " = " + std::to_string(want) +
                         "; simulate a trace made with " + w.scene_key + " = " + std::to_string(want) + ", or set " +
                         w.config_key + "=0 to follow the trace");
    }
}

int cmd_simulate(const SimulateArgs& a) {
    using clock = std::chrono::steady_clock;
    ParamSet mp = model::machine_params();
    std::string config_name = "default";
    if (!a.config.empty()) {
        std::string path = resolve_config(a.config);
        mp.load_file(path);
        config_name = mp.is_given("name") ? mp.get_string("name") : a.config;
    }
    const ParamSet named = mp;  // what the reports call config_name
    SceneOptions so = a.so;
    const ParamSet sp = scene_params();
    std::vector<std::string> config_args;  // the machine config's options, for shard processes (--jobs)
    if (!a.config.empty()) config_args.insert(config_args.end(), {"--config", a.config});
    std::vector<std::string> config_keys;  // the config keys and scene keys given with --set
    for (const auto& s : a.config_sets) {
        const auto [set, assignment] = route_assignment(s, {&mp, &sp});
        if (set == 0) {
            mp.set(assignment), config_args.insert(config_args.end(), {"--set", assignment});
            config_keys.push_back(assignment.substr(0, assignment.find('=')));
        } else {
            so.sets.push_back(assignment);
        }
    }
    for (const auto& k : config_keys) check_not_set_by_option(k, a.iccs != 0, a.fifo != 0);
    if (a.iccs) config_args.insert(config_args.end(), {"--iccs", std::to_string(a.iccs)});
    if (a.fifo) config_args.insert(config_args.end(), {"--fifo", std::to_string(a.fifo)});
    config_args.insert(config_args.end(), {"--window", std::to_string(a.window)});
    if (a.iccs) mp.set("machine.iccs=" + std::to_string(a.iccs));
    if (a.fifo) {
        mp.set("fifo.sphere_depth=" + std::to_string(a.fifo));
        mp.set("fifo.triangle_depth=" + std::to_string(a.fifo));
    }
    if (a.dump_config) {
        model::resolve_numerics(mp);
        std::cout << mp.dump();
        return 0;
    }
    model::SimConfig cfg = model::config_from_params(mp);
    if (!a.vcd.empty() && cfg.estimate != model::Estimate::fifo_bound)
        cfg.mode = model::SimMode::netlist;  // a waveform is the netlist's (its memory counted so)
    // A key given that cannot change the run is refused (docs/BAD_INPUT.md, "Rules").
    check_keys_apply(mp, config_keys, so.sets, a.trace);
    {  // What the run reads and writes, checked before any work.
        RunFiles files;
        if (a.trace.empty()) add_scene_inputs(files, so);
        files.input("--trace", a.trace);
        if (!a.config.empty()) files.input("--config", resolve_config(a.config));
        files.output("--json", a.json);
        files.output("--csv", a.csv);
        files.output("--vcd", a.vcd);
        if (!a.emit_jobs.empty())
            for (const char* ext : {"", ".traces", ".merge"}) files.output("--emit-jobs", a.emit_jobs + ext);
        files.check();
    }
    if (!a.frames.empty()) return simulate_frames(a, so);
    if (a.shards || !a.emit_jobs.empty()) return emit_shard_jobs(a, mp, cfg);
    if (a.sample_front_end) {
        if (!a.trace.empty()) throw UsageError("--sample-front-end: a trace file holds every group already (give a scene)");
        if (cfg.estimate != model::Estimate::sample_passes)
            throw UsageError("--sample-front-end needs sim.estimate = sample_passes");
        if (a.whole_frame) throw UsageError("--sample-front-end needs a streamed run: not with --whole-frame");
        if (cfg.group_order != model::GroupOrder::pixel)
            throw UsageError("--sample-front-end needs a streamed run: not with workload.group_order = " +
                             std::string(model::group_order_name(cfg.group_order)) + " (it needs every group first)");
        if (cfg.memory.system != model::MemorySystem::streaming)
            throw UsageError("--sample-front-end needs memory.system = streaming (a baseline reads every group)");
    }
    // --jobs N on one frame: N shard processes fed by this one's front end.
    const std::uint32_t local_jobs = a.frames.empty() ? a.jobs : 0;
    if (local_jobs > 1) {
        const std::string option = "--jobs " + std::to_string(local_jobs);
        if (!a.shard.empty()) throw InputError(option + ": runs every shard itself; not with --shard");
        if (!a.vcd.empty()) throw InputError(option + ": no --vcd (a waveform covers a whole run: simulate it whole)");
        if (a.whole_frame) throw InputError(option + ": streams the trace to its shards; not with --whole-frame");
        if (so.frame >= 0) throw InputError(option + ": not with --frame (simulate the frame whole, or its animation with --frames)");
        if (a.animation_row) throw InputError(option + ": not with --animation-row (a row of an animation: use --frames)");
        check_shardable(cfg, option);
        check_result_path("--json", a.json, {});
        check_result_path("--csv", a.csv, {});
    }
    const bool sharded = !a.shard.empty();
    ShardSpec shard;
    if (sharded) {
        shard = parse_shard(a.shard);
        if (!a.vcd.empty()) throw InputError("--shard: no --vcd (a waveform covers a whole run: simulate it whole)");
        if (!a.csv.empty())
            throw InputError("--shard: no --csv (a shard's figures are partial: raplas merge writes the run's CSV row)");
        if (a.json.empty()) throw InputError("--shard needs --json FILE: the partial result raplas merge reads");
        check_shardable(cfg, "--shard " + a.shard);
    }
    if (a.no_workload_hash && !sharded) throw InputError("--no-workload-hash is for the shards of --jobs");
    std::string given_hash, given_content;  // --workload-hash
    if (!a.workload_hash.empty()) {
        const auto at = a.workload_hash.find('@');
        auto hex16 = [](const std::string& x) {
            return x.size() == 16 && x.find_first_not_of("0123456789abcdef") == std::string::npos;
        };
        if (at == std::string::npos || !hex16(a.workload_hash.substr(0, at)) || !hex16(a.workload_hash.substr(at + 1)))
            throw UsageError("--workload-hash wants HASH@CONTENT, two 16-digit hex numbers; got '" + a.workload_hash + "'");
        if (a.trace.empty() || sharded || local_jobs > 1 || !a.frames.empty())
            throw UsageError("--workload-hash is for a sweep's points: one process simulating a --trace");
        given_hash = a.workload_hash.substr(0, at);
        given_content = a.workload_hash.substr(at + 1);
    }

    auto t0 = clock::now();
    Trace trace;  // the whole trace, or (streamed) the header, moved to the stream
    std::string scene_name;
    std::unique_ptr<GroupSource> source;
    GroupStream* stream = nullptr;
    std::unique_ptr<StreamProgress> stream_progress;
    Scene streamed_scene;     // the scene the streaming front end draws (outlives its thread)
    FrontEndThread frontend;  // (joined before the stream and the progress line go)
    ProgressLine model_progress(so.show_progress(), ::isatty(2));
    double frontend_s = 0;
    nlohmann::json animation;  // with --frame: the animation's frame count and rate
    std::shared_ptr<TraceReader> trace_reader;  // a trace read as a stream (outlives its thread)
    // The streaming machine takes the groups as the front end makes them (or
    // as a trace's blocks are read), a window of passes ahead of the model;
    // the baselines need the whole trace.
    // A group order other than the trace's needs every group at hand (the
    // shards of --jobs each take the whole stream and permute it themselves).
    const bool permuted = cfg.group_order != model::GroupOrder::pixel;
    const bool streamed = !a.whole_frame && cfg.memory.system == model::MemorySystem::streaming &&
                          (!permuted || local_jobs > 1);
    auto open_stream = [&] {
        auto owned = std::make_unique<GroupStream>(std::size_t(a.window) * cfg.iccs);
        stream = owned.get();
        source = std::move(owned);
    };
    if (!a.trace.empty()) {
        if (so.frame >= 0) throw UsageError("--frame F draws a frame of a scene; a trace holds one frame already");
        if (!so.scene.empty() || !so.mesh.empty()) throw UsageError("give either --trace or --scene/--mesh, not both");
        struct stat st{};
        if (!streamed && ::stat(a.trace.c_str(), &st) == 0 && S_ISREG(st.st_mode))
            check_trace_read(a.trace, std::uint64_t(st.st_size));
        if (streamed) {
            trace_reader = std::make_shared<TraceReader>(a.trace);  // the file header and the HEAD block
            trace = trace_reader->take_header();
        } else {
            trace = read_trace(a.trace);
        }
        model::check_trace_reading(trace, cfg, a.trace);
        check_trace_workload(trace, mp, a.trace);
        if (!a.vcd.empty()) check_waveform(a.vcd, cfg, trace);
        scene_name = trace.scene_name;
        if (cfg.functional == model::FunctionalMode::compute && !(trace.format == cfg.format))
            throw InputError(a.trace + ": trace was made in " + trace.format.name() + " but numerics.format is " +
                             cfg.format.name());
        if (streamed) {
            check_trace_streamed(cfg, a.trace, trace, a.window);
            open_stream();
            stream->set_header(std::move(trace));
            frontend.start(*stream, [reader = trace_reader, stream, t0, &frontend_s] {
                TraceGroup g;
                for (std::size_t i = 0; reader->next(g); ++i) {
                    if (!stream->total_known() && reader->total_known()) stream->set_total(reader->total());
                    stream->acquire(i);
                    stream->put(i, std::move(g));
                }
                if (!stream->total_known()) stream->set_total(reader->total());
                frontend_s = std::chrono::duration<double>(clock::now() - t0).count();
            });
        }
    } else {
        Scene scene;
        double load_s = 0;
        auto adjust = [&](ParamSet& p) {
            if (cfg.group_size) p.set("groups.size=" + std::to_string(cfg.group_size));
            if (cfg.shadow_group_size) p.set("groups.shadow_size=" + std::to_string(cfg.shadow_group_size));
            if (cfg.triangles_per_sphere) p.set("spheres.triangles_per_sphere=" + std::to_string(cfg.triangles_per_sphere));
        };
        if (!so.load(scene, load_s, adjust)) return 0;
        if (so.frame >= 0) animation = {{"frames", so.frames_in_animation}, {"fps", so.animation_fps}};
        FrameOptions fo;
        fo.format = cfg.format;
        fo.threads = so.threads;
        fo.cull = !so.no_cull;
        fo.record = true;
        fo.pairless = cfg.icc.decoder.select == model::TriangleSelect::any;
        if (!a.vcd.empty()) check_waveform_up_front(a.vcd, cfg, scene);
        check_model_up_front(cfg, scene);
        if (streamed) {
            open_stream();
            fo.stream = stream;
            // fo.before_shadow, called on the front end's thread, keeps a pointer to the scene.
            streamed_scene = std::move(scene);
            check_front_end(FrontEndUse::simulate_streamed, streamed_scene, fo, &cfg, a.window);
            if (so.show_progress() && local_jobs <= 1) {  // (--jobs draws its own)
                stream_progress = std::make_unique<StreamProgress>(::isatty(2));
                fo.progress = [p = stream_progress.get()](const char* phase, std::size_t done, std::size_t total) {
                    p->front_end(phase, done, total);
                };
            }
            if (a.sample_front_end) {
                model::SimOptions plan;
                fo.groups_read = [cfg, plan](std::size_t primary, std::size_t total) {
                    return model::simulated_groups(cfg, plan, std::uint32_t(primary), std::uint32_t(total));
                };
            }
            scene_name = streamed_scene.name;
            frontend.start(*stream, [&streamed_scene, fo, t0, &frontend_s] {
                render_frame(streamed_scene, fo);
                frontend_s = std::chrono::duration<double>(clock::now() - t0).count();
            });
        } else {
            check_front_end(FrontEndUse::simulate, scene, fo);
            PhaseProgress progress(so.show_progress(), ::isatty(2));
            fo.progress = std::ref(progress);
            Frame frame = render_frame(scene, fo);
            progress.finish();
            trace = make_trace(scene, std::move(frame), cfg.format, fo.pairless);
            scene_name = scene.name;
        }
    }
    std::unique_ptr<GroupSource> trace_order;  // with workload.group_order: the trace's order, observed
    if (!source) {
        frontend_s = std::chrono::duration<double>(clock::now() - t0).count();
        check_model(cfg, trace);
        source = std::make_unique<TraceSource>(trace);
        if (permuted) {
            trace_order = std::move(source);
            source = std::make_unique<PermutedSource>(trace, model::issue_order(trace, cfg.group_order, cfg.group_seed,
                                                                                cfg.iccs));
        }
    }
    // The front end failed: what it says, and (a trace damaged late in the
    // stream) what was done before it.
    auto report_front_end = [&] {
        const std::string done = trace_reader ? " (stopped after " + std::to_string(trace_reader->groups_read()) +
                                                    " ray groups were read; no result written)"
                                              : "";
        std::cerr << "raplas: " << (frontend.input_error() ? "error: " : "internal error: ") << frontend.error()
                  << done << "\n";
        return frontend.input_error() ? kExitInputError : kExitInternalError;
    };
    if (local_jobs > 1) {
        LocalShards run;
        run.jobs = local_jobs;
        run.child_args = config_args;
        run.json = a.json;
        run.csv = a.csv;
        run.quiet = so.quiet;
        run.progress = so.show_progress();
        run.tty = ::isatty(2);
        run.pairless = cfg.icc.decoder.select == model::TriangleSelect::any;
        const int rc = simulate_local_shards(run, *stream, frontend);
        return rc == kFrontEndFailed ? report_front_end() : rc;
    }
    const Trace& header = source->header();

    model::SimOptions opt;
    opt.vcd_path = a.vcd;
    opt.shard = shard.index;
    opt.shards = shard.count;
    if (stream_progress) {
        opt.progress = [&](std::size_t done, std::size_t total, std::uint64_t cycles) {
            stream_progress->model(done, total, cycles);
        };
    } else if (so.show_progress()) {
        opt.progress = [&](std::size_t done, std::size_t total, std::uint64_t cycles) {
            model_progress.draw(done, total, "model passes", ", " + std::to_string(cycles) + " cycles", done, total);
        };
    }
    const bool pairless = cfg.icc.decoder.select == model::TriangleSelect::any;
    WorkloadTally tally(header, pairless, !a.no_workload_hash && given_hash.empty());
    // The workload's figures and hash fold the trace in its own order.
    (trace_order ? trace_order : source)->observers.push_back(tally.observer());
    model::MemoryStats memory;
    model::SimResult result = model::simulate_system(*source, cfg, memory, opt);
    if (trace_order) {
        trace_order->release(trace_order->total_groups());
        if (result.first_mismatch)  // named by its place in the trace
            result.first_mismatch->group = static_cast<PermutedSource&>(*source).trace_index(result.first_mismatch->group);
    }
    if (stream_progress) stream_progress->finish();
    model_progress.finish();
    if (stream) {
        // The front end has handed over every group when the model ends well;
        // else it is stopped. Its own failure is the one to report.
        if (!result.error.empty()) stream->cancel();
        frontend.join();
        if (!frontend.error().empty()) return report_front_end();
    }
    if (!result.error.empty()) {  // printed, not thrown: see SimResult::error
        const bool watchdog = result.error.rfind("watchdog", 0) == 0;
        std::cerr << (watchdog ? "raplas: error: " : "raplas: internal error: ") << InputError::printable(result.error)
                  << "\n";
        return watchdog ? kExitInputError : kExitInternalError;
    }
    // The result reports the workload simulated: a workload key of 0
    // ("follow the scene or trace") is reported as the value it followed.
    ParamSet named_resolved = named, resolved = mp;
    for (ParamSet* p : {&named_resolved, &resolved})
        model::resolve_workload(*p, header.group_size, header.shadow_group_size, header.tris_per_sphere);
    // The trace's content, as read (from a file or a pipe).
    const std::string content = trace_reader ? hex64(trace_reader->content_hash())
                                : !a.trace.empty() ? hex64(header.content_hash)
                                                   : std::string();
    if (!given_hash.empty() && content != given_content) {
        std::cerr << "raplas: internal error: --workload-hash was folded over a trace of content " << given_content
                  << ", but " << a.trace << " has content " << content << "\n";
        return kExitInternalError;
    }
    const Provenance provenance = make_provenance(named_resolved, resolved,
                                                  !given_hash.empty() ? given_hash
                                                  : tally.hasher      ? tally.hasher->value()
                                                                      : "");
    const WorkloadFacts facts = workload_facts(header, tally, result);
    SimReportInput in;
    in.provenance = &provenance;
    in.result = &result;
    in.config = &cfg;
    in.workload = &facts;
    in.config_name = config_name;
    in.scene_name = scene_name;
    in.frontend_wall_s = frontend_s;
    in.cpu_s = process_cpu_s();
    if (stream) in.frontend_waits_s = stream->frontend_waits_s();
    in.memory = &memory;
    // What made the result (a shard's or a frame's: merge compares them).
    auto result_inputs = [&] { return hash_inputs(simulate_inputs(a), false, content); };
    if (sharded) {
        const PartialInput pi{shard, in, resolved.dump(), result_inputs()};
        write_file_atomically(a.json, partial_json(pi).dump(2) + "\n");
        if (!so.quiet) std::cout << shard_summary(pi, a.json);
        if (result.functional_checked && !result.functional_match) {
            // The same line as a whole run's, from the same report of the mismatch.
            const nlohmann::json j = sim_json(in);
            std::cerr << "raplas: error: functional mismatch in shard " << shard.index << "/" << shard.count << ": "
                      << result.rays_mismatched << " of " << result.rays_checked
                      << " rays differ from the front end; first: " << describe_mismatch(j["first_mismatch"]) << "\n";
            return kExitInternalError;
        }
        return 0;
    }
    nlohmann::json j = sim_json(in);
    if (so.frame >= 0) j["frame"] = so.frame, j["animation"] = animation, j["inputs"] = result_inputs();
    if (!a.json.empty()) write_file_atomically(a.json, j.dump(2) + "\n");
    if (!a.csv.empty())
        write_file_atomically(a.csv, a.animation_row ? animation_row_csv(j, 1, std::max(so.frame, 0), result.total_cycles,
                                                                         j["time_ms"].get<double>())
                                                     : sim_csv_header() + sim_csv_row(j));
    if (!so.quiet) std::cout << sim_summary(j);
    if (result.functional_checked && !result.functional_match) {
        std::cerr << "raplas: error: functional mismatch: " << result.rays_mismatched << " of " << result.rays_checked
                  << " rays differ from the front end; first: " << describe_mismatch(j["first_mismatch"]) << "\n";
        return kExitInternalError;
    }
    return 0;
}

}  // namespace raplas
