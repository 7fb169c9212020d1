#include "raplas/util/memory_budget.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "raplas/util/error.hpp"

namespace raplas {

std::uint64_t parse_memory_size(const std::string& text, const std::string& what, bool* off) {
    if (off) *off = false;
    if (text == "off") {
        if (off) *off = true;
        return 0;
    }
    const char* s = text.c_str();
    char* end = nullptr;
    const double v = std::strtod(s, &end);
    std::string unit(end);
    std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return char(std::toupper(c)); });
    if (unit.size() >= 3 && unit.compare(unit.size() - 2, 2, "IB") == 0) unit.resize(unit.size() - 2);  // KiB
    else if (!unit.empty() && unit.back() == 'B') unit.pop_back();                                       // KB, B
    double scale = 0;
    if (unit.empty()) scale = 1;
    else if (unit == "K") scale = 1024.0;
    else if (unit == "M") scale = 1024.0 * 1024;
    else if (unit == "G") scale = 1024.0 * 1024 * 1024;
    else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
    if (end == s || scale == 0 || !std::isfinite(v) || v <= 0 || v * scale >= 1.8e19)
        throw InputError(what + ": '" + text + "' is not a memory size (e.g. 512M, 4G, or off)");
    return std::uint64_t(v * scale);
}

namespace {

// A value of /proc/meminfo or /proc/self/status, in bytes (0: not found).
std::uint64_t proc_kb(const char* file, const char* key) {
    std::ifstream in(file);
    std::string line;
    const std::string k = std::string(key) + ":";
    while (std::getline(in, line))
        if (line.compare(0, k.size(), k) == 0) return std::strtoull(line.c_str() + k.size(), nullptr, 10) * 1024;
    return 0;
}

// The first line of a cgroup file as a number; false for "max" or no file.
bool cgroup_value(const std::string& file, std::uint64_t& v) {
    std::ifstream in(file);
    std::string s;
    if (!(in >> s) || s == "max") return false;
    char* end = nullptr;
    v = std::strtoull(s.c_str(), &end, 10);
    return end != s.c_str();
}

}  // namespace

MemoryLimit memory_limit() {
    MemoryLimit m;
    if (const char* env = std::getenv("RAPLAS_MAX_MEMORY"); env && *env) {
        bool off = false;
        m.bytes = parse_memory_size(env, "RAPLAS_MAX_MEMORY", &off);
        m.unlimited = off;
        m.source = "RAPLAS_MAX_MEMORY";
        return m;
    }
    m.bytes = proc_kb("/proc/meminfo", "MemAvailable");
    m.source = "MemAvailable";
    // cgroup v2: this process's group, e.g. "0::/user.slice/x.scope".
    std::ifstream cg("/proc/self/cgroup");
    std::string line;
    while (std::getline(cg, line)) {
        if (line.compare(0, 3, "0::") != 0) continue;
        const std::string dir = "/sys/fs/cgroup" + line.substr(3);
        std::uint64_t max = 0, current = 0;
        if (cgroup_value(dir + "/memory.max", max)) {
            cgroup_value(dir + "/memory.current", current);
            const std::uint64_t left = max > current ? max - current : 0;
            if (m.bytes == 0 || left < m.bytes) {
                m.bytes = left;
                m.source = "cgroup memory.max";
            }
        }
    }
    if (m.bytes == 0) m.unlimited = true;  // nothing known: no check
    return m;
}

std::string format_bytes(double b) {
    char buf[64];
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB"};
    int u = 0;
    while (b >= 1024 && u < 5) b /= 1024, ++u;
    if (u == 0) std::snprintf(buf, sizeof buf, "%.0f B", b);
    else std::snprintf(buf, sizeof buf, b < 10 ? "%.2f %s" : b < 100 ? "%.1f %s" : "%.0f %s", b, units[u]);
    return buf;
}

void check_memory(const std::string& command, std::vector<MemoryItem> items) {
    const MemoryLimit lim = memory_limit();
    const double resident = double(resident_memory());
    double total = resident;
    for (const auto& i : items) total += i.bytes;
    if (const char* log = std::getenv("RAPLAS_MEMORY_LOG"); log && *log && std::string(log) != "0") {
        std::fprintf(stderr, "raplas: memory: %s: estimate %.0f bytes (%s), limit %s (%s): in use %.0f;", command.c_str(),
                     total, format_bytes(total).c_str(), lim.unlimited ? "none" : format_bytes(double(lim.bytes)).c_str(),
                     lim.source.c_str(), resident);
        for (const auto& i : items) std::fprintf(stderr, " %s %.0f;", i.what.c_str(), i.bytes);
        std::fprintf(stderr, "\n");
    }
    if (lim.unlimited || total <= double(lim.bytes)) return;
    std::stable_sort(items.begin(), items.end(), [](const MemoryItem& a, const MemoryItem& b) { return a.bytes > b.bytes; });
    std::ostringstream o;
    o << command << " needs about " << format_bytes(total) << " (";
    const std::size_t shown = std::min<std::size_t>(items.size(), 3);
    for (std::size_t i = 0; i < shown; ++i) o << items[i].what << ": " << format_bytes(items[i].bytes) << ", ";
    if (items.size() > shown) o << "..., ";
    o << format_bytes(resident) << " in use already) but " << format_bytes(double(lim.bytes)) << " is available ("
      << lim.source << "); make it smaller, or set --max-memory / RAPLAS_MAX_MEMORY (docs/MEMORY.md)";
    throw InputError(o.str());
}

std::uint64_t resident_memory() { return proc_kb("/proc/self/status", "VmRSS"); }

}  // namespace raplas
