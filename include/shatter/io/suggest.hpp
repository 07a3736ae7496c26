#pragma once
// "Did you mean" hints for misspelt names (scene keys, column names, material names).

#include <string>
#include <string_view>
#include <vector>

namespace shatter::io {

// Edit distance (Levenshtein) between two strings.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidate closest to `word` when it is plausibly a typo of it (distance at most a third of
// the word's length, at least 1 and at most 3); empty otherwise.
std::string closest(std::string_view word, const std::vector<std::string>& candidates);

// " (did you mean 'x'?)" or "" — ready to append to an error message.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace shatter::io
