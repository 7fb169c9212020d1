// Memory the timing model will allocate for a configuration and a trace
// shape (docs/MEMORY.md): per-ICC FIFOs, pipelines and group state, the
// stream memories and the functional model's copies of the geometry.
#pragma once

#include <vector>

#include "config.hpp"
#include "raplas/frontend/memory_estimate.hpp"

namespace raplas::model {

std::vector<MemoryItem> model_memory(const SimConfig& c, const TraceShape& t);

}  // namespace raplas::model
