// The memory budget: sizes, the limit's sources, the refusal message, and
// estimates that follow the configuration (the estimates against measured
// peak RSS: docs/MEMORY.md, tools/memory_check.py).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>

#include "memory_estimate.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/memory_budget.hpp"

using namespace raplas;
using ::testing::HasSubstr;

namespace {

// Sets RAPLAS_MAX_MEMORY for one test.
struct LimitEnv {
    explicit LimitEnv(const char* v) { ::setenv("RAPLAS_MAX_MEMORY", v, 1); }
    ~LimitEnv() { ::unsetenv("RAPLAS_MAX_MEMORY"); }
};

std::string refusal(const std::string& command, const std::vector<MemoryItem>& items) {
    try {
        check_memory(command, items);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(MemoryBudget, ParsesSizesInPowersOf1024) {
    EXPECT_EQ(parse_memory_size("123", "x"), 123u);
    EXPECT_EQ(parse_memory_size("512K", "x"), 512u * 1024);
    EXPECT_EQ(parse_memory_size("512KiB", "x"), 512u * 1024);
    EXPECT_EQ(parse_memory_size("3MB", "x"), 3u << 20);
    EXPECT_EQ(parse_memory_size("1.5G", "x"), 3ull << 29);
    EXPECT_EQ(parse_memory_size("2t", "x"), 2ull << 40);
    bool off = false;
    EXPECT_EQ(parse_memory_size("off", "x", &off), 0u);
    EXPECT_TRUE(off);
    for (const char* bad : {"", "G", "12Q", "-1G", "0", "nan", "1e30T", "4 G"})
        EXPECT_THROW(parse_memory_size(bad, "--max-memory"), InputError) << bad;
    try {
        parse_memory_size("lots", "--max-memory");
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "--max-memory: 'lots' is not a memory size (e.g. 512M, 4G, or off)");
    }
}

TEST(MemoryBudget, FormatsBytes) {
    EXPECT_EQ(format_bytes(12), "12 B");
    EXPECT_EQ(format_bytes(1536), "1.50 KiB");
    EXPECT_EQ(format_bytes(50.0 * (1 << 20)), "50.0 MiB");
    EXPECT_EQ(format_bytes(9.83e12), "8.94 TiB");
}

TEST(MemoryBudget, LimitComesFromTheEnvironmentOrTheMachine) {
    {
        LimitEnv env("3G");
        const MemoryLimit m = memory_limit();
        EXPECT_FALSE(m.unlimited);
        EXPECT_EQ(m.bytes, 3ull << 30);
        EXPECT_EQ(m.source, "RAPLAS_MAX_MEMORY");
    }
    {
        LimitEnv env("off");
        EXPECT_TRUE(memory_limit().unlimited);
    }
    const MemoryLimit m = memory_limit();  // this machine: /proc/meminfo or the cgroup
    EXPECT_FALSE(m.unlimited);
    EXPECT_GT(m.bytes, 16u << 20);
    EXPECT_TRUE(m.source == "MemAvailable" || m.source == "cgroup memory.max") << m.source;
    EXPECT_GT(resident_memory(), 1u << 20);
}

TEST(MemoryBudget, RefusalNamesTheLargestItemsAndTheLimit) {
    LimitEnv env("1G");
    const std::vector<MemoryItem> items = {
        {"small", 1e6}, {"huge", 3e9}, {"medium", 2e8}, {"tiny", 10}};
    const std::string msg = refusal("render", items);
    EXPECT_THAT(msg, ::testing::StartsWith("render needs about "));
    EXPECT_THAT(msg, HasSubstr("(huge: 2.79 GiB, medium: 191 MiB, small: 977 KiB, ..., "));
    EXPECT_THAT(msg, HasSubstr(" in use already) but 1.00 GiB is available (RAPLAS_MAX_MEMORY); "));
    EXPECT_EQ(msg.find("tiny"), std::string::npos);
    // within the limit: no refusal
    EXPECT_EQ(refusal("render", {{"small", 1e6}}), "");
    LimitEnv off("off");
    EXPECT_EQ(refusal("render", items), "");
}

TEST(MemoryBudget, ModelEstimateFollowsIccsAndFifoDepths) {
    model::SimConfig c;
    c.iccs = 100;
    c.icc.triangle_fifo.depth = 1000000;
    c.icc.planeid_fifo.depth = 10;
    TraceShape t;
    t.spheres = 1000;
    t.triangles = 2000;
    t.primary_groups = 4;
    const std::vector<MemoryItem> a = model::model_memory(c, t);
    ASSERT_FALSE(a.empty());
    // the FIFOs: 24 bytes per Triangle FIFO entry, 16 + 12 per PlaneID and First-Triangle-ID entry
    EXPECT_EQ(a[0].what, "100 ICCs x FIFO depths 1000000/10 (Triangle/PlaneID)");
    EXPECT_DOUBLE_EQ(a[0].bytes, 100.0 * (1000000 * 24 + 10 * 28));
    auto total = [](const std::vector<MemoryItem>& v) {
        double s = 0;
        for (const auto& i : v) s += i.bytes;
        return s;
    };
    // twice the ICCs: twice the per-ICC cost; the ICCs without a group hold no group state
    c.iccs = 200;
    const double per_icc = (total(model::model_memory(c, t)) - total(a)) / 100.0;
    EXPECT_GT(per_icc, 24.0e6);
    EXPECT_LT(per_icc, 24.0e6 + 64 * 1024);
}
