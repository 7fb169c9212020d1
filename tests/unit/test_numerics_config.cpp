// The machine config keys of the intersectors' numerics (numerics.format,
// numerics.rti_test, numerics.psi_normalize), how they combine, and the
// resolved form --dump-config prints.
#include <gtest/gtest.h>

#include <string>

#include "config.hpp"
#include "raplas/util/error.hpp"

namespace {

using raplas::NumFormat;

raplas::model::SimConfig config_with(std::initializer_list<std::string> sets) {
    raplas::ParamSet p = raplas::model::machine_params();
    for (const auto& s : sets) p.set(s);
    return raplas::model::config_from_params(p);
}

std::string error_of(std::initializer_list<std::string> sets) {
    try {
        config_with(sets);
    } catch (const raplas::InputError& e) {
        return e.what();
    }
    return "";
}

TEST(NumericsConfig, FormatAndPsiNormalisationCombine) {
    EXPECT_EQ(config_with({}).format, NumFormat::float32());
    EXPECT_EQ(config_with({"numerics.format=fp1-7-16"}).format.name(), "fp1-7-16");
    EXPECT_EQ(config_with({"numerics.format=fp1-7-16", "numerics.psi_normalize=false"}).format.name(),
              "fp1-7-16-psiunnorm");
    EXPECT_EQ(config_with({"numerics.format=fp1-7-16-psiunnorm"}).format.name(), "fp1-7-16-psiunnorm");
    EXPECT_EQ(config_with({"numerics.format=fp1-7-16", "numerics.psi_normalize=true"}).format.name(), "fp1-7-16");
    // float32 without PSI normalisation runs emulated with float32's widths
    const NumFormat f = config_with({"numerics.psi_normalize=false"}).format;
    EXPECT_EQ(f.kind, NumFormat::Kind::custom);
    EXPECT_EQ(f.name(), "fp1-8-23-psiunnorm");
}

TEST(NumericsConfig, ContradictionsNameTheKey) {
    EXPECT_NE(error_of({"numerics.format=float64", "numerics.psi_normalize=false"}).find("numerics.psi_normalize"),
              std::string::npos);
    EXPECT_NE(error_of({"numerics.format=fp1-7-16-psiunnorm", "numerics.psi_normalize=true"})
                  .find("numerics.psi_normalize"),
              std::string::npos);
    EXPECT_NE(error_of({"numerics.format=fp1-7"}).find("numerics.format"), std::string::npos);
}

TEST(NumericsConfig, DumpedConfigLoadsAgainToTheSameNumerics) {
    const std::initializer_list<std::initializer_list<std::string>> cases = {
        {},
        {"numerics.format=fp1-7-16-psiunnorm-wt"},
        {"numerics.format=fp1-7-16", "numerics.rti_test=watertight", "numerics.psi_normalize=false"},
        {"numerics.psi_normalize=false"},
        {"numerics.format=float64-wt"},
        {"numerics.format=fp1-8-15-rtz", "numerics.rti_test=division_free"},
    };
    for (const auto& sets : cases) {
        raplas::ParamSet p = raplas::model::machine_params();
        for (const auto& s : sets) p.set(s);
        const NumFormat want = raplas::model::config_from_params(p).format;
        raplas::model::resolve_numerics(p);
        EXPECT_EQ(p.get_string("numerics.format"), want.name());
        EXPECT_EQ(p.get_string("numerics.rti_test") == "watertight", want.rti == raplas::RtiTest::watertight);
        EXPECT_EQ(p.get_bool("numerics.psi_normalize"), want.psi_normalize);
        raplas::ParamSet back = raplas::model::machine_params();
        back.load_text(p.dump(), "dump");
        EXPECT_EQ(raplas::model::config_from_params(back).format, want) << want.name();
    }
}

}  // namespace

namespace {

// The keys of the open hardware choices (docs/MODEL.md §3): each reaches the
// block it configures, and the PlaneID FIFO can follow the Triangle FIFO.
TEST(MachineChoicesConfig, ReadingsEmptyCyclesOverlapAndPlaneIdDepth) {
    using raplas::model::TriangleSelect;
    const auto d = config_with({});
    EXPECT_EQ(d.icc.decoder.select, TriangleSelect::any);  // the paper's §4 (docs/MODEL.md §3)
    EXPECT_EQ(config_with({"icc.triangle_select=both"}).icc.decoder.select, TriangleSelect::both);
    EXPECT_EQ(d.icc.fetcher.empty_cycles, 1u);
    EXPECT_FALSE(d.overlap_passes);
    EXPECT_EQ(d.icc.planeid_fifo.depth, 1000u);
    const auto c = config_with({"icc.triangle_select=any", "icc.rdf_empty_cycles=0", "host.overlap_passes=true",
                                "fifo.triangle_depth=37", "fifo.planeid_depth=0"});
    EXPECT_EQ(c.icc.decoder.select, TriangleSelect::any);
    EXPECT_EQ(c.icc.fetcher.empty_cycles, 0u);
    EXPECT_TRUE(c.overlap_passes);
    EXPECT_EQ(c.icc.planeid_fifo.depth, 37u);  // 0: as deep as the Triangle FIFO
    EXPECT_NE(error_of({"icc.triangle_select=all"}).find("icc.triangle_select"), std::string::npos);
    EXPECT_NE(error_of({"icc.rdf_empty_cycles=-1"}).find("icc.rdf_empty_cycles"), std::string::npos);
    EXPECT_NE(error_of({"host.overlap_passes=true", "sim.estimate=sample_passes"}).find("host.overlap_passes"),
              std::string::npos);
}

}  // namespace
