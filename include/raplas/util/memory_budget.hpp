// Memory budget: a run whose estimated peak memory exceeds what the machine
// has is refused up front with the estimate (InputError, exit 2) instead of
// being killed by the kernel. The limit is RAPLAS_MAX_MEMORY when set (raplas
// --max-memory sets it), else the smaller of MemAvailable (/proc/meminfo) and
// the cgroup's memory.max minus memory.current. Estimates: docs/MEMORY.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace raplas {

struct MemoryItem {
    std::string what;  // e.g. "shadow ray groups recorded (9,596 groups)"
    double bytes = 0;
};

struct MemoryLimit {
    bool unlimited = false;
    std::uint64_t bytes = 0;
    std::string source;  // "RAPLAS_MAX_MEMORY", "MemAvailable", "cgroup memory.max"
};

// "123", "512K", "1.5G", "2T" (powers of 1024; a trailing B or iB is allowed)
// or "off" (no limit). Throws InputError naming `what` on anything else.
std::uint64_t parse_memory_size(const std::string& text, const std::string& what, bool* off = nullptr);

MemoryLimit memory_limit();

// "1.23 GiB", "456 MiB", "789 KiB", "12 B".
std::string format_bytes(double bytes);

// Throws InputError when the items and what the process holds already
// (resident_memory) add up to more than the limit:
// "COMMAND needs about X (A: a, B: b, C: c, ...) but Y is available (SOURCE); ..."
// naming the largest items.
void check_memory(const std::string& command, std::vector<MemoryItem> items);

// Resident memory of this process now (VmRSS), bytes; 0 if unknown.
std::uint64_t resident_memory();

}  // namespace raplas
