// "Did you mean ...?": the known names nearest to a mistyped one, by
// Damerau-Levenshtein distance (optimal string alignment: insertions,
// deletions, substitutions and swaps of two neighbours count 1 each).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace raplas {

std::size_t edit_distance(const std::string& a, const std::string& b);

// The edits a mistyped word of this length may hold and still be "near":
// 1 up to 7 characters, 2 up to 11, 3 beyond (a quarter of the length).
std::size_t near_limit(std::size_t length);

// The candidates nearest to `word` (ties in the candidates' order), at most
// `max_names` of them; none when no candidate is within near_limit(word).
// A candidate that `word` begins (at least 3 characters: 'fov' -> 'fov_deg')
// counts as near too, after every closer one.
std::vector<std::string> nearest_names(const std::string& word, const std::vector<std::string>& candidates,
                                       std::size_t max_names = 3);

// " (did you mean 'a'?)", " (did you mean 'a' or 'b'?)"; "" for no names.
std::string did_you_mean(const std::vector<std::string>& names);
// "a, b or c"
std::string or_list(const std::vector<std::string>& words);

}  // namespace raplas
