#include "foundation/Suggest.h"

#include <algorithm>
#include <cctype>

namespace fp {

namespace {
int editDistance(const std::string& a, const std::string& b) {
    std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = int(j);
    for (std::size_t i = 1; i <= a.size(); ++i) {
        cur[0] = int(i);
        for (std::size_t j = 1; j <= b.size(); ++j) {
            // Case differences count half as much as other edits: "truth" vs "Truth" is a near miss.
            bool same = a[i - 1] == b[j - 1];
            bool caseOnly = !same && std::tolower(a[i - 1]) == std::tolower(b[j - 1]);
            int sub = prev[j - 1] + (same || caseOnly ? 0 : 1);
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
        }
        std::swap(prev, cur);
    }
    return prev[b.size()];
}
}  // namespace

std::string suggestClosest(const std::string& word, const std::vector<std::string>& candidates) {
    std::string best;
    int bestDistance = std::max<int>(2, int(word.size()) / 3) + 1;
    for (const auto& c : candidates) {
        int d = editDistance(word, c);
        if (d < bestDistance) {
            bestDistance = d;
            best = c;
        }
    }
    return best;
}

std::string asciiLowercase(std::string s) {
    for (auto& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates) {
    std::string s = suggestClosest(word, candidates);
    return s.empty() ? std::string() : " (did you mean '" + s + "'?)";
}

}  // namespace fp
