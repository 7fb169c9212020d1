#include "raplas/util/nearest.hpp"

#include <algorithm>
#include <limits>

namespace raplas {

std::size_t edit_distance(const std::string& a, const std::string& b) {
    const std::size_t n = a.size(), m = b.size();
    // three rows of the dynamic programme: i-2, i-1, i
    std::vector<std::size_t> back2(m + 1), back1(m + 1), row(m + 1);
    for (std::size_t j = 0; j <= m; ++j) back1[j] = j;
    for (std::size_t i = 1; i <= n; ++i) {
        row[0] = i;
        for (std::size_t j = 1; j <= m; ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            row[j] = std::min({back1[j] + 1, row[j - 1] + 1, back1[j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                row[j] = std::min(row[j], back2[j - 2] + 1);
        }
        std::swap(back2, back1);
        std::swap(back1, row);
    }
    return back1[m];
}

std::size_t near_limit(std::size_t length) { return std::clamp<std::size_t>(length / 4, 1, 3); }

std::vector<std::string> nearest_names(const std::string& word, const std::vector<std::string>& candidates,
                                       std::size_t max_names) {
    const std::size_t limit = near_limit(word.size());
    constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
    std::size_t best = none;
    std::vector<std::string> names;
    for (const auto& c : candidates) {
        std::size_t d = edit_distance(word, c);
        if (d > limit) d = word.size() >= 3 && c.size() > word.size() && c.compare(0, word.size(), word) == 0
                               ? limit + 1  // a prefix: near, after every typo within the limit
                               : none;
        if (d == none || d > best) continue;
        if (d < best) names.clear();
        best = d;
        if (std::find(names.begin(), names.end(), c) == names.end()) names.push_back(c);
    }
    if (names.size() > max_names) names.resize(max_names);
    return names;
}

std::string or_list(const std::vector<std::string>& words) {
    std::string s;
    for (std::size_t i = 0; i < words.size(); ++i)
        s += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
    return s;
}

std::string did_you_mean(const std::vector<std::string>& names) {
    if (names.empty()) return "";
    std::vector<std::string> quoted;
    for (const auto& n : names) quoted.push_back("'" + n + "'");
    return " (did you mean " + or_list(quoted) + "?)";
}

}  // namespace raplas
