// Error kinds and their exit codes: bad input or usage -> 2, internal -> 1.
#pragma once

#include <stdexcept>
#include <string>

namespace raplas {

// Something the user gave us is wrong (file, key, value). The message is one
// line and names the file and line, or the key.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

constexpr int kExitInputError = 2;
constexpr int kExitInternalError = 1;

}  // namespace raplas
