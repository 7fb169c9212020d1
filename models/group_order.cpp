#include "group_order.hpp"

#include <algorithm>
#include <numeric>

#include "raplas/util/error.hpp"

namespace raplas::model {

GroupOrder group_order_from_name(const std::string& name) {
    if (name == "random") return GroupOrder::random;
    if (name == "morton") return GroupOrder::morton;
    if (name == "strided") return GroupOrder::strided;
    return GroupOrder::pixel;
}

const char* group_order_name(GroupOrder o) {
    switch (o) {
        case GroupOrder::random: return "random";
        case GroupOrder::morton: return "morton";
        case GroupOrder::strided: return "strided";
        case GroupOrder::pixel: break;
    }
    return "pixel";
}

namespace {

std::uint64_t splitmix64(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

std::uint64_t spread(std::uint32_t v) {  // the bits of v at the even positions
    std::uint64_t x = v;
    x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
    x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
    x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;
    x = (x | (x << 2)) & 0x3333333333333333ull;
    x = (x | (x << 1)) & 0x5555555555555555ull;
    return x;
}

// The groups [begin, end) of one kind in the order asked for.
void order_kind(const Trace& t, GroupOrder order, std::uint64_t seed, std::uint32_t iccs, std::uint32_t begin,
                std::uint32_t end, std::vector<std::uint32_t>& out) {
    const std::uint32_t g = end - begin;
    std::vector<std::uint32_t> idx(g);
    std::iota(idx.begin(), idx.end(), begin);
    switch (order) {
        case GroupOrder::pixel: break;
        case GroupOrder::random: {
            std::uint64_t state = seed ^ (std::uint64_t(begin) << 32);
            for (std::uint32_t i = g; i > 1; --i) {
                const std::uint32_t j = std::uint32_t(splitmix64(state) % i);
                std::swap(idx[i - 1], idx[j]);
            }
            break;
        }
        case GroupOrder::morton: {
            auto code = [&](std::uint32_t i) {
                const TraceGroup& x = t.groups[i];
                return spread(std::uint32_t(std::max(0, x.px))) | (spread(std::uint32_t(std::max(0, x.py))) << 1);
            };
            std::stable_sort(idx.begin(), idx.end(), [&](std::uint32_t a, std::uint32_t b) { return code(a) < code(b); });
            break;
        }
        case GroupOrder::strided: {
            const std::uint32_t k = std::max(1u, iccs), passes = (g + k - 1) / k;
            idx.clear();
            for (std::uint32_t pass = 0; pass < passes; ++pass)
                for (std::uint32_t i = 0; i < k; ++i)
                    if (const std::uint64_t j = std::uint64_t(i) * passes + pass; j < g) idx.push_back(begin + std::uint32_t(j));
            break;
        }
    }
    out.insert(out.end(), idx.begin(), idx.end());
}

}  // namespace

std::vector<std::uint32_t> issue_order(const Trace& t, GroupOrder order, std::uint64_t seed, std::uint32_t iccs) {
    const auto total = std::uint32_t(t.groups.size());
    if (t.primary_groups > total) throw InputError("issue_order: more primary groups than groups");
    std::vector<std::uint32_t> out;
    out.reserve(total);
    order_kind(t, order, seed, iccs, 0, t.primary_groups, out);
    order_kind(t, order, seed, iccs, t.primary_groups, total, out);
    return out;
}

}  // namespace raplas::model
