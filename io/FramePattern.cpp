#include "io/FramePattern.h"

#include "passes/core/Error.h"

#include <OpenImageIO/filesystem.h>

#include <regex>

namespace fp::io {

namespace {
// A frame token: a run of '#' or '@', or printf %d / %0Nd.
const std::regex kToken(R"((#+|@+|%0?(\d*)d))");

int tokenDigits(const std::string& token) {
    if (token[0] == '%') {
        const auto digits = token.substr(1, token.size() - 2);
        return digits.empty() ? 1 : std::stoi(digits);
    }
    // One '#' is four digits (oiiotool); a run of them is one digit each (Nuke, Deadline), so
    // both "shot.#.exr" and "shot.####.exr" give shot.0001.exr. '@' is one digit each.
    if (token[0] == '#' && token.size() == 1) return 4;
    return int(token.size());
}
}  // namespace

FramePattern::FramePattern(const std::string& pattern) : mPattern(pattern) {
    std::smatch m;
    if (!std::regex_search(pattern, m, kToken)) return;
    mHasToken = true;
    // An inline range right before the token ("shot.1-10#.exr") is the pattern's frame spec.
    const std::string before = m.prefix().str();
    static const std::regex kRange(R"(([-\d,x y]*\d)$)");
    std::smatch r;
    std::string prefix = before;
    if (std::regex_search(before, r, kRange) && r.str(1).find_first_of("-,") != std::string::npos) {
        mInlineFrames = r.str(1);
        prefix = before.substr(0, before.size() - r.str(1).size());
    }
    mPrefix = prefix;
    mSuffix = m.suffix().str();
    mDigits = tokenDigits(m.str(0));
}

std::string FramePattern::path(int frame) const {
    if (!mHasToken) return mPattern;
    const std::string digits = frame < 0 ? fmt::format("-{:0{}d}", -frame, mDigits)
                                         : fmt::format("{:0{}d}", frame, mDigits);
    return mPrefix + digits + mSuffix;
}

std::vector<int> parseFrameSpec(const std::string& spec) {
    std::vector<int> frames;
    if (spec.empty() || !OIIO::Filesystem::enumerate_sequence(spec, frames) || frames.empty())
        throw UsageError(fmt::format("'{}' is not a frame spec (examples: 1001, 1-10, 1-10x2, "
                                     "3,4,10-20x2)",
                                     spec));
    return frames;
}

}  // namespace fp::io
