// Small file helpers shared across layers: is a path a regular file, read a
// whole file, hash one, make a path absolute, the executable's folder.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace raplas {

bool is_file(const std::string& path);  // a regular file (following links)
// The whole file; InputError "PATH: cannot read: REASON".
std::string read_file(const std::string& path);
// FNV-1a, 64 bits, of some bytes / of a file's content; as 16 hex digits.
// (inline: the trace writer and the workload hash feed it a few bytes at a time)
inline std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h = 0xcbf29ce484222325ull) {
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 0x100000001b3ull;
    }
    return h;
}
std::string hex64(std::uint64_t h);
std::string file_hash(const std::string& path);
std::string absolute_path(const std::string& path);  // absolute and normalised
// Removes the files of folder `dir` whose names `which` accepts; returns how many.
std::size_t remove_files(const std::string& dir, const std::function<bool(const std::string& name)>& which);
// The running executable's folder with a trailing '/' ("" when unknown).
std::string executable_dir();

}  // namespace raplas
