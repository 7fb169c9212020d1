// Reading a text file the user named, whatever it is: a regular file, a pipe
// or FIFO (/dev/stdin, <(...)), a character device, a /proc file.
#pragma once

#include <string>

namespace raplas {

struct TextInput {
    std::string noun;         // "OBJ file", "scene file": used in every message
    std::string article;      // "a" or "an", before the noun
    std::string memory_item;  // what the memory check calls the load
    double memory_factor = 1;  // its peak memory per byte of text (docs/MEMORY.md)
    bool text = true;          // false: binary (a trace), NUL bytes allowed
};

// The whole file, read to its end. Throws InputError, one line each:
//   "PATH: is a directory, not an OBJ file"
//   "PATH: cannot open OBJ file: REASON"
//   "PATH: not a text OBJ file (contains NUL bytes)": stops at the first NUL
//     read, so /dev/zero and /dev/urandom end at once (text inputs only);
//   check_memory's refusal ("loading PATH needs about ..."): memory_factor
//     times the text's size, checked before a regular file is read and each
//     time a stream that never ends has doubled.
std::string read_text_input(const std::string& path, const TextInput& kind);

}  // namespace raplas
