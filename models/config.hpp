// Machine configuration: every parameter declared once (default, range,
// description), read from configs/*.toml, overridable with --set, dumpable.
#pragma once

#include <string>

#include "icc.hpp"
#include "watchdog.hpp"
#include "raplas/util/params.hpp"

namespace raplas::model {

enum class SimMode { cycle, event };

struct SimConfig {
    std::uint32_t iccs = 1;
    double clock_mhz = 400;
    Icc::Params icc;
    std::uint32_t sphere_record_bytes = 16, triangle_record_bytes = 39;
    std::uint64_t pass_overhead_cycles = 0;
    std::uint64_t triangle_lag_cycles = 0;  // the triangle stream starts this many cycles after the sphere stream
    // Workload overrides of the scene (0 = keep the scene's value).
    std::uint32_t group_size = 0, shadow_group_size = 0, triangles_per_sphere = 0;
    NumFormat format = NumFormat::float32();
    FunctionalMode functional = FunctionalMode::compute;
    SimMode mode = SimMode::event;
    std::uint64_t sync_cycles = 4096;      // cycles simulated between kernel time updates
    std::uint64_t watchdog_cycles = 1000000;
    Fault fault = Fault::none;  // fault injection (tests of the watchdog)
    std::uint32_t fault_icc = 0;
};

ParamSet machine_params();
SimConfig config_from_params(const ParamSet& p);

}  // namespace raplas::model
