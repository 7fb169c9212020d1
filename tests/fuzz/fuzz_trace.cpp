// fuzz_trace: the profile trace reader (parse_trace).
//
// Each input is parsed twice: as is (header, version, size and checksum
// checks), and, when it is at least a header long, with its first 32 bytes
// replaced by a valid header for the rest (magic, version, payload size,
// checksum), so that mutations reach the payload parser. A trace that parses
// must serialize to exactly the bytes it was read from, but for the number
// format's name, which is written in its canonical spelling ("fp1-8-15-rne"
// is read as, and written as, "fp1-8-15").
#include <cstdint>
#include <cstring>
#include <string>

#include "fuzz_common.hpp"
#include "raplas/frontend/trace_io.hpp"

namespace {

const char* const kTarget = "fuzz_trace";
constexpr std::size_t kHeaderBytes = 32;  // docs/TRACE.md

std::uint64_t fnv1a(const char* p, std::size_t n) {
    std::uint64_t h = 1469598103934665603ull;
    for (std::size_t i = 0; i < n; ++i) {
        h ^= static_cast<unsigned char>(p[i]);
        h *= 1099511628211ull;
    }
    return h;
}

template <class T> void put(std::string& s, std::size_t at, T v) { std::memcpy(&s[at], &v, sizeof v); }

std::uint32_t get_u32(const std::string& s, std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, s.data() + at, sizeof v);
    return v;
}

// Writes a valid header for the payload bytes[32:].
void fix_header(std::string& bytes) {
    std::memcpy(&bytes[0], "RAPLTRC\n", 8);
    put(bytes, 8, raplas::kTraceVersion);
    put(bytes, 12, std::uint32_t(kHeaderBytes));
    put(bytes, 16, std::uint64_t(bytes.size() - kHeaderBytes));
    put(bytes, 24, fnv1a(bytes.data() + kHeaderBytes, bytes.size() - kHeaderBytes));
}

// The bytes of a trace that parsed, with its format name (the payload's
// second string, after the scene name) spelt as the trace writes it.
std::string canonical(const std::string& bytes, const raplas::Trace& t) {
    const std::size_t at = kHeaderBytes + 4 + get_u32(bytes, kHeaderBytes);
    const std::uint32_t old_len = get_u32(bytes, at);
    const std::string name = t.format.name();
    std::string out = bytes.substr(0, at);
    const auto len = std::uint32_t(name.size());
    out.append(reinterpret_cast<const char*>(&len), sizeof len);
    out += name;
    out += bytes.substr(at + 4 + old_len);
    fix_header(out);
    return out;
}

void parse(const std::string& bytes) {
    raplas::fuzz::guarded(kTarget, [&] {
        const raplas::Trace t = raplas::parse_trace(bytes, "fuzz.trace");
        (void)t.total_counts();
        if (raplas::serialize_trace(t) != canonical(bytes, t))
            raplas::fuzz::fail(kTarget, "trace does not serialize back to its bytes");
    });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, std::size_t size) {
    const std::string bytes = raplas::fuzz::as_string(data, size);
    parse(bytes);
    if (size >= kHeaderBytes) {
        std::string fixed = bytes;
        fix_header(fixed);
        if (fixed != bytes) parse(fixed);
    }
    return 0;
}
