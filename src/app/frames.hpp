// Internal to the app layer: the frames of an animated scene (docs/SCENES.md,
// "Animation"; docs/ANIMATION.md). `render --frames` draws them one after the
// other in this process; `simulate --frames` simulates each in its own child
// process (`simulate --frame F`: one SystemC elaboration per process) and
// gathers their results into one JSON with a `frames` array and totals.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.hpp"

namespace raplas {

struct FrameRange {
    int first = 0, last = 0;  // both included
    int count() const { return last - first + 1; }
};

// "the scene 'NAME' has N frames (0 to N-1)", for the messages refusing a frame.
std::string scene_frames_text(const std::string& scene_name, int frames);
// The frame rate a frame of `time_ms` sustains (0 for no time).
inline double fps_at_clock(double time_ms) { return time_ms > 0 ? 1e3 / time_ms : 0.0; }

// --frames SPEC of a scene of `frames` frames: "N" (frames 0 .. N-1), "A:B"
// (frames A to B, both included) or "all". InputError naming --frames and
// the scene otherwise.
FrameRange parse_frames(const std::string& spec, int frames, const std::string& scene_name);

// A file name pattern with one %d or %0Nd for the frame number: `option`'s
// value checked (InputError naming it), and the name of frame `frame`.
void check_frame_pattern(const std::string& pattern, const std::string& option);
std::string frame_file(const std::string& pattern, int frame);
// InputError when files named by `pattern` (given to `option`) exist for
// frames outside `range`: the frames of another run, which the files this
// run writes would be mixed with (docs/BAD_INPUT.md, "Rules").
void check_frame_leftovers(const std::string& pattern, const std::string& option, const FrameRange& range);

// The results of `simulate --frame F --json` for consecutive frames, gathered:
// the run's common fields once, a `frames` array (each frame's figures, its
// per-ICC detail and resolved config left out) and `totals`.
// `totals` is animation_totals_json(per_frame).
nlohmann::json frames_json(const std::vector<nlohmann::json>& per_frame, const nlohmann::json& totals);
// The frames of one run as one simulate result (what a sweep's row of an
// animated scene holds): every count, cycle and byte summed over the frames,
// maxima the largest, bandwidths and utilisation over the summed time, the
// workload hash over the frames' hashes; the rest is the first frame's.
nlohmann::json animation_totals_json(const std::vector<nlohmann::json>& per_frame);
// simulate --animation-row: the CSV header and one row, simulate's CSV columns
// of `totals` (a whole run's JSON, or animation_totals_json()) followed by
// frames, worst_frame, worst_frame_cycles and worst_fps_at_clock.
std::string animation_row_csv(const nlohmann::json& totals, std::uint64_t frames, int worst_frame,
                              std::uint64_t worst_cycles, double worst_ms);
// One CSV row per frame: frame, fps_at_clock, then simulate's CSV columns.
std::string frames_csv(const std::vector<nlohmann::json>& per_frame);
// What simulate --frames prints: a line per frame and one for the totals.
std::string frames_summary(const nlohmann::json& frames);

// `raplas simulate --frames SPEC`, `so` the scene options with the scene's
// --set keys routed in. With --emit-jobs FILE it writes the frames' commands
// (one line each) to FILE and the merge of their results to FILE.merge instead.
int simulate_frames(const SimulateArgs& a, const SceneOptions& so);

struct MergeArgs;
// A result of `simulate --frame F --json` (what merge_frames() reads).
bool is_frame_result(const std::string& path);
// `raplas merge` of such results: the frames of one run, each once, with no
// frame missing between the first and the last, gathered as simulate --frames
// writes them. InputError naming the file otherwise.
int merge_frames(const MergeArgs& a);

}  // namespace raplas
