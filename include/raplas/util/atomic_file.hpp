// Results are written to a temporary file beside the target and renamed into
// place, so a reader never sees a half-written file.
#pragma once

#include <functional>
#include <string>

namespace raplas {

// Temporary name in the target's directory that keeps the target's extension
// (image writers choose the format from it).
std::string temp_path_for(const std::string& target);

// Calls write(tmp) and renames tmp to target; removes tmp and rethrows on error.
void write_atomically(const std::string& target, const std::function<void(const std::string& tmp)>& write);

// Convenience: whole-file text or binary contents.
void write_file_atomically(const std::string& target, const std::string& contents);

}  // namespace raplas
