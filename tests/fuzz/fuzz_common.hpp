// Shared by the libFuzzer targets: run one input through a reader and turn
// every outcome the readers do not promise into an abort() the fuzzer
// reports as a crash.
//
//   - raplas::InputError is the expected rejection: its message must be one
//     non-empty line with no control character but tab, as the CLI prints it
//     as is.
//   - Any other exception escaping is a crash (a reader that documents
//     std::invalid_argument converts it to InputError before it gets here).
//   - Sanitizer reports, timeouts and out-of-memory are crashes by libFuzzer.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <typeinfo>

#include "raplas/util/error.hpp"
#include "raplas/util/params.hpp"

namespace raplas::fuzz {

[[noreturn]] inline void fail(const char* target, const std::string& why) {
    std::fprintf(stderr, "\n%s: %s\n", target, why.c_str());
    std::fflush(stderr);
    std::abort();
}

// The message of an InputError: one line, printable, not empty.
inline void check_message(const char* target, const std::string& msg) {
    if (msg.empty()) fail(target, "InputError with an empty message");
    for (unsigned char c : msg)
        if ((c < 0x20 && c != '\t') || c == 0x7f) fail(target, "InputError message is not one printable line: " + msg);
}

// Runs f(); returns true when it completed, false when it threw InputError.
template <class F>
bool guarded(const char* target, F&& f) {
    try {
        f();
        return true;
    } catch (const InputError& e) {
        check_message(target, e.what());
        return false;
    } catch (const std::exception& e) {
        fail(target, std::string("unexpected exception ") + typeid(e).name() + ": " + e.what());
    } catch (...) {
        fail(target, "unexpected non-standard exception");
    }
}

inline std::string as_string(const unsigned char* data, std::size_t size) {
    return std::string(reinterpret_cast<const char*>(data), size);
}

// ParamSet::dump() is documented to print TOML that is valid input again:
// `fresh` (the same kind of set, as built) loads p's dump and dumps the same.
inline void check_dump(const char* target, const ParamSet& p, ParamSet fresh) {
    const std::string first = p.dump();
    try {
        fresh.load_text(first, "dump");
    } catch (const InputError& e) {
        fail(target, std::string("dump() is not valid input: ") + e.what() + "\n" + first);
    }
    if (fresh.dump() != first) fail(target, "dump() does not read back to the same values:\n" + first);
}

}  // namespace raplas::fuzz
