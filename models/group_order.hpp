// The order in which the Host issues ray groups to passes and ICCs
// (workload.group_order; docs/MODEL.md §3, "Group order"). A trace keeps
// the front end's order (primary tiles in row-major order, then one shadow
// group per hit pixel in pixel order); the model permutes it, so one trace
// serves every order. Primary groups stay before shadow groups and each kind
// is permuted among itself.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "raplas/frontend/trace_io.hpp"

namespace raplas::model {

enum class GroupOrder { pixel, random, morton, strided };
GroupOrder group_order_from_name(const std::string& name);
const char* group_order_name(GroupOrder o);

// Position i of the issue order holds trace group order[i]:
// - pixel: the trace's order;
// - random: a Fisher-Yates shuffle driven by `seed` (splitmix64);
// - morton: by the Z-order (Morton) code of the group's pixel (px, py: a
//   primary tile's first pixel, a shadow group's pixel), ties by trace order;
// - strided: with G groups of a kind, K ICCs and P = ceil(G / K) passes,
//   position k·K + i (pass k, ICC i) holds group i·P + k: each ICC takes a
//   contiguous stretch of the image, one group a pass. Positions whose
//   group would be past the last are left out, so when G is not a multiple
//   of K the last ICC's stretch is short and the passes after the first gap
//   hold groups of the next pass.
std::vector<std::uint32_t> issue_order(const Trace& t, GroupOrder order, std::uint64_t seed, std::uint32_t iccs);

}  // namespace raplas::model
