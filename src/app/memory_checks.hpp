// Internal to the app layer: the memory budget at each step of a command
// (docs/MEMORY.md). Each check adds what the process holds now to what the
// step will allocate until its peak, and refuses the run (InputError) when
// that exceeds the limit.
#pragma once

#include <string>

#include "config.hpp"
#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/scene/scene.hpp"

namespace raplas {

// simulate_streamed: `raplas simulate` with the groups streamed to the model
// (FrameOptions::stream), which runs alongside.
// trace_streamed: `raplas trace` writing each group as it is traced, with
// a window of `window_passes` groups (no model).
enum class FrontEndUse { render, trace_file, simulate, simulate_streamed, trace_streamed };

// Before render_frame; installs in `fo` the check before the shadow rays,
// which also counts the trace (and its file buffer) the command will build.
// simulate_streamed: also the model (`model`) and a window of `window_passes`
// passes of groups instead of the trace.
void check_front_end(FrontEndUse use, const Scene& s, FrameOptions& fo, const model::SimConfig* model = nullptr,
                     std::uint32_t window_passes = 0);

// `raplas simulate` before the front end: the model for the scene's shape
// without its shadow groups (a lower bound).
void check_model_up_front(const model::SimConfig& c, const Scene& s);

// Before reading a trace file of `bytes` bytes.
void check_trace_read(const std::string& path, std::uint64_t bytes);

// `raplas simulate --trace` read as a stream: the trace's header, the model
// and a window of `window_passes` passes of groups (their sphere hits from
// the file's blocks when it is a regular file, else none known).
void check_trace_streamed(const model::SimConfig& c, const std::string& path, const Trace& header,
                          std::uint32_t window_passes);

// Before the timing model, with the trace in memory.
void check_model(const model::SimConfig& c, const Trace& t);

// `raplas simulate --vcd PATH`: refuses a waveform that cannot fit on PATH's
// disk. Every pass broadcasts every sphere and every triangle, one a cycle at
// most, so the primary passes alone take at least passes x max(spheres,
// triangles) cycles, and the clock alone writes at least 14 bytes a cycle
// (two edges, each a time stamp and a value). Before the front end, from the
// scene's shape; or from a trace's header.
void check_waveform_up_front(const std::string& path, const model::SimConfig& c, const Scene& s);
void check_waveform(const std::string& path, const model::SimConfig& c, const Trace& header);

}  // namespace raplas
