// Error kinds and their exit codes: bad input or usage -> 2, internal -> 1.
#pragma once

#include <stdexcept>
#include <string>

namespace raplas {

// Something the user gave us is wrong (file, key, value). The message is one
// line and names the file and line, or the key. Messages quote the input, so
// every control character in them is written as an escape (\n, \xNN): the
// message stays one printable line whatever the input holds.
struct InputError : std::runtime_error {
    explicit InputError(const std::string& what) : std::runtime_error(printable(what)) {}
    explicit InputError(const char* what) : InputError(std::string(what)) {}

    static std::string printable(const std::string& s) {
        static const char hex[] = "0123456789abcdef";
        std::string out;
        out.reserve(s.size());
        for (char ch : s) {
            const auto c = static_cast<unsigned char>(ch);
            if (c >= 0x20 && c != 0x7f) out += ch;
            else if (c == '\n') out += "\\n";
            else if (c == '\r') out += "\\r";
            else if (c == '\t') out += "\\t";
            else {
                out += "\\x";
                out += hex[c >> 4];
                out += hex[c & 15];
            }
        }
        return out;
    }
};

// A command line that cannot be right whatever the files hold: an option's
// value, or options that do not go together. The command line adds where to
// read the subcommand's options ("see raplas simulate --help").
struct UsageError : InputError {
    using InputError::InputError;
};

constexpr int kExitInputError = 2;
constexpr int kExitInternalError = 1;

}  // namespace raplas
