// Results are written to a temporary file beside the target and renamed into
// place, so a reader never sees a half-written file.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace raplas {

// Temporary name in the target's directory that keeps the target's extension
// (image writers choose the format from it): ".NAME.raplas-tmp-PID.EXT".
// Before it answers, the target's temporary files left by processes that no
// longer exist (a killed run) are removed.
std::string temp_path_for(const std::string& target);

// Removes the temporary files in `dir` of target `base` (of any target when
// `base` is empty) whose process no longer exists; returns how many.
std::size_t remove_stale_temps(const std::string& dir, const std::string& base = "");

// Calls write(tmp) and renames tmp to target; removes tmp and rethrows on error.
void write_atomically(const std::string& target, const std::function<void(const std::string& tmp)>& write);

// Convenience: whole-file text or binary contents.
void write_file_atomically(const std::string& target, const std::string& contents);

}  // namespace raplas
