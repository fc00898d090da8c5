#pragma once
#include <string>
#include <vector>

namespace fp {

/// The candidate closest to `word` by edit distance, or "" when nothing is close enough to be a
/// plausible typo (distance > max(2, |word|/3)).
std::string suggestClosest(const std::string& word, const std::vector<std::string>& candidates);

/// " (did you mean 'x'?)" or "".
std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace fp
