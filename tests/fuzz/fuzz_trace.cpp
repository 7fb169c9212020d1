// fuzz_trace: the profile trace reader (parse_trace).
//
// Each input is parsed twice: as is (header, version, block sizes and
// checksums), and, when it is at least a file header long, with a valid file
// header and every block's checksum made right (as far as the block sizes
// fit the input), so that mutations reach the block parsers. A trace that
// parses must serialize to bytes that parse to a trace serializing to the
// very same bytes (the writer's blocking and the number format's canonical
// name may differ from the input's).
#include <cstdint>
#include <cstring>
#include <string>

#include "fuzz_common.hpp"
#include "raplas/frontend/trace_io.hpp"

namespace {

const char* const kTarget = "fuzz_trace";
constexpr std::size_t kHeaderBytes = raplas::kTraceFileHeaderBytes;  // docs/TRACE.md

template <class T> void put(std::string& s, std::size_t at, T v) { std::memcpy(&s[at], &v, sizeof v); }


// A valid file header (version 4 kept, any other made the current one), and
// each block's checksum recomputed as its version computes it.
void fix_blocks(std::string& bytes) {
    std::uint32_t version;
    std::memcpy(&version, bytes.data() + 8, 4);
    if (version != raplas::kTraceOldestVersion) version = raplas::kTraceVersion;
    std::memcpy(&bytes[0], "RAPLTRC\n", 8);
    put(bytes, 8, version);
    put(bytes, 12, std::uint32_t(kHeaderBytes));
    put(bytes, 16, std::uint64_t(0));
    put(bytes, 24, std::uint64_t(0));
    for (std::size_t at = kHeaderBytes; at + raplas::kTraceBlockHeaderBytes <= bytes.size();) {
        std::uint64_t size;
        std::memcpy(&size, bytes.data() + at + 4, 8);
        const std::size_t payload = at + raplas::kTraceBlockHeaderBytes;
        if (size > bytes.size() - payload) break;
        put(bytes, at + 12, raplas::trace_block_checksum(version, bytes.data() + payload, std::size_t(size)));
        at = payload + std::size_t(size);
    }
}

void parse(const std::string& bytes) {
    raplas::fuzz::guarded(kTarget, [&] {
        const raplas::Trace t = raplas::parse_trace(bytes, "fuzz.trace");
        (void)t.total_counts();
        const std::string once = raplas::serialize_trace(t);
        if (raplas::serialize_trace(raplas::parse_trace(once, "again.trace")) != once)
            raplas::fuzz::fail(kTarget, "trace does not serialize back to its bytes");
    });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, std::size_t size) {
    const std::string bytes = raplas::fuzz::as_string(data, size);
    parse(bytes);
    if (size >= kHeaderBytes) {
        std::string fixed = bytes;
        fix_blocks(fixed);
        if (fixed != bytes) parse(fixed);
    }
    return 0;
}
