// The area in `raplas simulate`'s reports (docs/MODEL.md §6): the JSON block
// block by block, the CSV column, the summary line and the note, checked
// against the closed form of the default coefficients on a small built-in
// scene.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "run_raplas.hpp"

namespace {

using namespace raplas_test;
using ::testing::HasSubstr;
using ::testing::Not;

// The paper config (32 PSI pipes, 1 RTI pipe, FIFOs of 1,000) on a 16 x 16
// image of the coarsest built-in mesh, 8 x 8 groups, 3 ICCs.
const std::vector<std::string> kSmall = {"simulate", "--config", "paper", "--iccs", "3",
                                         "--set", "image.width=16", "--set", "image.height=16",
                                         "--set", "builtin_detail=0", "--set", "workload.group_size=8",
                                         "--set", "workload.shadow_group_size=8", "--json", "a.json"};

// One ICC under the defaults with N = 8: PSI 32 x (872 + 12 x 80) = 58,624,
// RTI 4,726 + 70 x 80 = 10,326, fixed 287 + 588 + 2 x 3 = 881; FIFOs
// 0.018375 x (1000 x 16 + 1000 x 39 + 1000 x 2 + 1000 x 3) = 1,102.5;
// Ray and Min-distance Memories 0.018375 x 64 x (18 + 6) = 28.224.
constexpr double kIcc = 58624 + 10326 + 881 + 1102.5 + 28.224;  // 70,961.724

// The cells of a CSV line without quoted cells.
std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out;
    std::string cell;
    for (char ch : line + ",") {
        if (ch != ',') {
            cell += ch;
            continue;
        }
        out.push_back(cell);
        cell.clear();
    }
    return out;
}

class AreaReport : public TempDirTest {
protected:
    nlohmann::json simulate(const std::vector<std::string>& more, std::string* summary = nullptr) const {
        const RunResult r = run(plus(kSmall, more));
        EXPECT_EQ(r.code, 0) << r.err;
        if (summary) *summary = r.out;
        return nlohmann::json::parse(slurp(dir / "a.json"));
    }
};

TEST_F(AreaReport, TheJsonGivesEveryBlockPerIccAndInTotal) {
    std::string summary;
    const nlohmann::json j = simulate({"--csv", "a.csv"}, &summary);
    const nlohmann::json& a = j["area"];
    EXPECT_EQ(a["model"], "blocks");
    EXPECT_EQ(a["unit"], "slice-equivalents");
    EXPECT_EQ(a["iccs"], 3);
    const nlohmann::json& per = a["per_icc"];
    EXPECT_EQ(per["psi"].get<double>(), 58624.0);
    EXPECT_EQ(per["rti"].get<double>(), 10326.0);
    EXPECT_EQ(per["fixed"]["triangle_selector"].get<double>(), 287.0);
    EXPECT_EQ(per["fixed"]["ray_data_fetcher"].get<double>(), 588.0);
    EXPECT_EQ(per["fixed"]["decoders"].get<double>(), 6.0);
    EXPECT_EQ(per["fixed"]["sphere_selector"].get<double>(), 0.0);
    EXPECT_EQ(per["fixed"]["total"].get<double>(), 881.0);
    EXPECT_NEAR(per["fifos"]["sphere"].get<double>(), 294.0, 1e-9);       // 0.018375 x 16,000
    EXPECT_NEAR(per["fifos"]["triangle"].get<double>(), 716.625, 1e-9);   // x 39,000
    EXPECT_NEAR(per["fifos"]["planeid"].get<double>(), 36.75, 1e-9);      // x 1,000 x 16 bits
    EXPECT_NEAR(per["fifos"]["first_tri"].get<double>(), 55.125, 1e-9);   // x 3,000
    EXPECT_NEAR(per["ray_memories"]["ray"].get<double>(), 21.168, 1e-9);  // x 64 x 18
    EXPECT_NEAR(per["ray_memories"]["min_distance"].get<double>(), 7.056, 1e-9);  // x 64 x 6
    EXPECT_NEAR(per["total"].get<double>(), kIcc, 1e-6);
    // The scene memories: one copy of the trace's spheres and triangles.
    const double spheres = j["spheres"].get<double>(), triangles = j["triangles"].get<double>();
    ASSERT_GT(spheres, 0);
    const double scene = 0.018375 * (spheres * 16 + triangles * 39);
    EXPECT_EQ(a["scene_memories"]["copies"], 1);
    EXPECT_NEAR(a["scene_memories"]["sphere"].get<double>(), 0.018375 * spheres * 16, 1e-9);
    EXPECT_NEAR(a["scene_memories"]["total"].get<double>(), scene, 1e-9);
    for (const char* k : {"psi", "rti"}) EXPECT_NEAR(a["totals"][k].get<double>(), 3 * per[k].get<double>(), 1e-6) << k;
    for (const char* k : {"fixed", "fifos", "ray_memories"})
        EXPECT_NEAR(a["totals"][k].get<double>(), 3 * per[k]["total"].get<double>(), 1e-6) << k;
    EXPECT_NEAR(a["totals"]["iccs"].get<double>(), 3 * kIcc, 1e-6);
    EXPECT_NEAR(a["total"].get<double>(), 3 * kIcc + scene, 1e-6);
    EXPECT_TRUE(a["note"].is_null());
    EXPECT_DOUBLE_EQ(j["area_time"].get<double>(), a["total"].get<double>() * j["total_cycles"].get<double>());
    // The CSV's area column is the total.
    const std::vector<std::string> csv = lines_of(slurp(dir / "a.csv"));
    ASSERT_EQ(csv.size(), 2u);
    const std::vector<std::string> head = cells(csv[0]), row = cells(csv[1]);
    const auto col = std::find(head.begin(), head.end(), "area") - head.begin();
    ASSERT_LT(std::size_t(col), row.size());
    EXPECT_NEAR(std::stod(row[col]), a["total"].get<double>(), 1e-3);
    EXPECT_THAT(summary, HasSubstr("  area 212934 slice-equivalents: 3 ICCs of 70961.7 (PSI 58624, RTI 10326"));
    EXPECT_THAT(summary, Not(HasSubstr("area note")));
}

TEST_F(AreaReport, RtiPipesAndFifoDepthsGrowTheArea) {
    const nlohmann::json base = simulate({});
    const nlohmann::json rti = simulate({"--set", "icc.rti_pipes=16"});
    // 3 ICCs x 15 more pipes of 10,326
    EXPECT_NEAR(rti["area"]["total"].get<double>() - base["area"]["total"].get<double>(), 3 * 15 * 10326.0, 1e-6);
    const nlohmann::json fifo = simulate({"--fifo", "10"});
    // Sphere and Triangle FIFOs of 10 (PlaneID FIFOs stay 1,000): 3 x 0.018375 x 990 x (16 + 39) less
    EXPECT_NEAR(base["area"]["total"].get<double>() - fifo["area"]["total"].get<double>(),
                3 * 0.018375 * 990 * (16 + 39), 1e-6);
}

TEST_F(AreaReport, KeysTheAreaDoesNotFollowAreNamedInTheJsonAndTheSummary) {
    std::string summary;
    const nlohmann::json j = simulate({"--set", "icc.psi_stages=12"}, &summary);
    ASSERT_TRUE(j["area"]["note"].is_string());
    EXPECT_THAT(j["area"]["note"].get<std::string>(), HasSubstr("icc.psi_stages = 12"));
    EXPECT_THAT(summary, HasSubstr("  area note: icc.psi_stages = 12"));
}

TEST_F(AreaReport, PeUnitsGiveThePapersFigureNineArea) {
    std::string summary;
    const nlohmann::json j = simulate({"--set", "area.model=pe_units"}, &summary);
    EXPECT_EQ(j["area"]["model"], "pe_units");
    EXPECT_EQ(j["area"]["unit"], "PE");
    EXPECT_EQ(j["area"]["total"].get<double>(), 3 * 1.0 + 2.0);
    EXPECT_THAT(j["area"]["note"].get<std::string>(), HasSubstr("pe_units"));
    EXPECT_THAT(summary, HasSubstr("  area 5 PE (area.model = pe_units)"));
    EXPECT_THAT(summary, HasSubstr("  area note: "));
    const nlohmann::json d = simulate({"--set", "area.model=pe_units", "--set", "memory.system=distributed"});
    EXPECT_EQ(d["area"]["total"].get<double>(), 3 * (1.0 + 2.0));
}

TEST_F(AreaReport, BaselinesHaveNoStreamFifosAndTheDistributedMemoryACopyPerIcc) {
    const nlohmann::json sh = simulate({"--set", "memory.system=shared"});
    EXPECT_EQ(sh["area"]["per_icc"]["fifos"]["total"].get<double>(), 0.0);
    EXPECT_EQ(sh["area"]["scene_memories"]["copies"], 1);
    EXPECT_NEAR(sh["area"]["per_icc"]["total"].get<double>(), kIcc - 1102.5, 1e-6);
    const nlohmann::json d = simulate({"--set", "memory.system=distributed"});
    EXPECT_EQ(d["area"]["scene_memories"]["copies"], 3);
    EXPECT_NEAR(d["area"]["total"].get<double>(),
                3 * (kIcc - 1102.5) + 3 * d["area"]["scene_memories"]["sphere"].get<double>() +
                    3 * d["area"]["scene_memories"]["triangle"].get<double>(),
                1e-6);
}

}  // namespace
