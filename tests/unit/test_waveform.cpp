// `simulate --vcd`: the netlist's waveform. Every signal, port and FIFO by its
// hierarchical name, one clock period per cycle, written whole or not at all,
// and the same results as without it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "run_raplas.hpp"

namespace {

namespace fs = std::filesystem;
using namespace raplas_test;

class Waveform : public TempDirTest {};

// The full names of a VCD's variables ("raplas.icc_0.triangle_fifo.full"),
// without SystemC's outer scope; and its last time stamp.
struct VcdHeader {
    std::set<std::string> names;
    std::uint64_t last_time = 0;
};
VcdHeader read_vcd(const fs::path& p) {
    VcdHeader h;
    std::istringstream in(slurp(p));
    std::vector<std::string> scope;
    std::string line;
    bool body = false;
    while (std::getline(in, line)) {
        std::istringstream w(line);
        std::string t;
        w >> t;
        if (body) {
            if (!t.empty() && t[0] == '#') h.last_time = std::stoull(t.substr(1));
            continue;
        }
        if (t == "$scope") {
            std::string kind, name;
            w >> kind >> name;
            scope.push_back(name);
        } else if (t == "$upscope") {
            scope.pop_back();
        } else if (t == "$var") {
            std::string type, width, id, name;
            w >> type >> width >> id >> name;
            std::string full;
            for (std::size_t i = 1; i < scope.size(); ++i) full += scope[i] + ".";  // (scope 0: "SystemC")
            h.names.insert(full + name);
        } else if (t == "$enddefinitions") {
            body = true;
        }
    }
    return h;
}

TEST_F(Waveform, TracesEveryPortAndSignalOfTheNetlistByItsHierarchicalName) {
    const std::vector<std::string> sim = {"simulate", "-q", "--set", "image.width=8", "--set", "image.height=8",
                                          "--set", "builtin_detail=0", "--iccs", "2", "--fifo", "4"};
    const RunResult plain = run(plus(sim, {"--json", "plain.json"}));
    ASSERT_EQ(plain.code, 0) << plain.err;
    const RunResult traced = run(plus(sim, {"--json", "traced.json", "--vcd", "w.vcd"}));
    ASSERT_EQ(traced.code, 0) << traced.err;

    // The waveform changes no result (the default event mode and the netlist agree).
    nlohmann::json a = nlohmann::json::parse(slurp(dir / "plain.json"));
    nlohmann::json b = nlohmann::json::parse(slurp(dir / "traced.json"));
    EXPECT_EQ(a["engine"], "event");
    EXPECT_EQ(b["engine"], "netlist") << "a waveform is the netlist's";
    for (auto* j : {&a, &b}) j->erase("wall"), j->erase("engine");
    EXPECT_EQ(a, b);

    // Written whole: the file and no temporary beside it.
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path().filename().string());
    EXPECT_THAT(files, ::testing::UnorderedElementsAre("plain.json", "traced.json", "w.vcd"));

    const VcdHeader h = read_vcd(dir / "w.vcd");
    for (const char* name :
         {"raplas.clock", "raplas.pass", "raplas.sphere_valid", "raplas.triangle_ready_1", "raplas.sphere_record.index",
          "raplas.host.pass", "raplas.host.sphere_done", "raplas.sphere_stream_link.valid",
          "raplas.sphere_stream_link.stall", "raplas.sphere_stream_link.ready_1", "raplas.triangle_stream_link.record.sphere",
          "raplas.icc_0.active", "raplas.icc_0.hold", "raplas.icc_0.decided", "raplas.icc_0.planeid_pop",
          "raplas.icc_0.psi_out.sphere", "raplas.icc_0.rti_issue.pairs", "raplas.icc_1.sphere_fifo.size",
          "raplas.icc_1.planeid_fifo.full", "raplas.icc_1.first_tri_fifo.size", "raplas.icc_1.triangle_fifo.full",
          "raplas.icc_1.sphere_selector.ready", "raplas.icc_1.psi.hold", "raplas.icc_1.psi.out.valid",
          "raplas.icc_1.decoder.planeid_pop", "raplas.icc_1.triangle_selector.ready",
          "raplas.icc_1.triangle_selector.record.index", "raplas.icc_1.ray_data_fetcher.issue.pairs",
          "raplas.icc_1.rti.busy", "raplas.icc_1.rti.ready"})
        EXPECT_TRUE(h.names.count(name)) << name;
    // One clock period (2,500 ps at 400 MHz) per cycle: the run ends at its last rising edge.
    EXPECT_EQ(h.last_time, a["total_cycles"].get<std::uint64_t>() * 2500);
}

}  // namespace
