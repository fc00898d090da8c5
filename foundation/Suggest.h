#pragma once
#include <string>
#include <vector>

namespace fp {

/// The candidate closest to `word` by edit distance, or "" when nothing is close enough to be a
/// plausible typo (distance > max(2, |word|/3)).
std::string suggestClosest(const std::string& word, const std::vector<std::string>& candidates);

/// `s` with ASCII letters in lower case: names matched without regard to case (cvars, file
/// extensions).
std::string asciiLowercase(std::string s);

/// " (did you mean 'x'?)" or "".
std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace fp
