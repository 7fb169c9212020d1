// Statistics of a simulation, written directly as JSON and CSV.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "baseline_memory.hpp"
#include "top.hpp"

namespace raplas {

struct SimReportInput {
    const model::SimResult* result = nullptr;
    const model::SimConfig* config = nullptr;
    const Trace* trace = nullptr;
    std::string config_name;
    std::string scene_name;
    double frontend_wall_s = 0;
    const model::MemoryStats* memory = nullptr;  // memory system figures (none: not reported)
};

// Deterministic figures under their own keys; wall-clock figures only under "wall".
nlohmann::json sim_json(const SimReportInput& in);
// One flat row of the scalar figures (the sweep's columns).
// One line on a `first_mismatch` object of sim_json: which ray (kind, group,
// pixel) and both answers; "none" for null.
std::string describe_mismatch(const nlohmann::json& first_mismatch);
std::string sim_csv_header();
std::string sim_csv_row(const nlohmann::json& j);
std::string sim_summary(const nlohmann::json& j);

}  // namespace raplas
