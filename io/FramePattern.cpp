#include "io/FramePattern.h"

#include "foundation/Error.h"
#include "foundation/Limits.h"

#include <OpenImageIO/filesystem.h>

#include <regex>

namespace fp::io {

namespace {
// A frame token: a run of '#' or '@', or printf %d / %0Nd.
const std::regex kToken(R"((#+|@+|%0?(\d*)d))");

int tokenDigits(const std::string& token, const std::string& pattern) {
    if (token[0] == '%') {
        const auto digits = token.substr(1, token.size() - 2);
        if (digits.empty()) return 1;
        // Checked before converting: "%0999999999999d" overflows int, "%0999999999d" would
        // format a gigabyte-long file name.
        if (digits.size() > 3 || std::stoi(digits) > limits::kMaxFrameDigits)
            throw UsageError(fmt::format("'{}': frame width {} is more than {} digits (the limit)",
                                         pattern, digits, limits::kMaxFrameDigits));
        return std::stoi(digits);
    }
    if (int(token.size()) > limits::kMaxFrameDigits)
        throw UsageError(fmt::format("'{}': frame token '{}' is more than {} digits (the limit)",
                                     pattern, token.substr(0, 20), limits::kMaxFrameDigits));
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
    mDigits = tokenDigits(m.str(0), pattern);
}

std::string FramePattern::path(int frame) const {
    if (!mHasToken) return mPattern;
    const std::string digits = frame < 0 ? fmt::format("-{:0{}d}", -int64_t(frame), mDigits)
                                         : fmt::format("{:0{}d}", frame, mDigits);
    return mPrefix + digits + mSuffix;
}

std::vector<int> parseFrameSpec(const std::string& spec) {
    // Checked here before OpenImageIO expands it: its loop runs once per frame of each range's
    // span (x/y steps only pick among them) in int, so a huge span allocates gigabytes or
    // overflows. Each item: N, A-B, A-BxS or A-ByS.
    static const std::regex kItem(
        R"(^\s*(-?\d{1,18})\s*(?:-\s*(-?\d{1,18})\s*(?:[xy]\s*(-?\d{1,18})\s*)?)?$)");
    int64_t total = 0;
    std::size_t start = 0;
    while (start <= spec.size()) {
        const std::size_t comma = std::min(spec.find(',', start), spec.size());
        const std::string item = spec.substr(start, comma - start);
        std::smatch m;
        if (std::regex_match(item, m, kItem)) {
            const int64_t first = std::stoll(m.str(1));
            const int64_t last = m[2].matched ? std::stoll(m.str(2)) : first;
            for (int64_t f : {first, last})
                if (f < -limits::kMaxFrameNumber || f > limits::kMaxFrameNumber)
                    throw UsageError(fmt::format("frames '{}': frame {} is beyond ±{} (the limit)",
                                                 spec, f, limits::kMaxFrameNumber));
            if (m[3].matched && std::stoll(m.str(3)) == 0)
                throw UsageError(fmt::format("frames '{}': a step of 0", spec));
            total += (first > last ? first - last : last - first) + 1;
            if (total > limits::kMaxFrames)
                throw UsageError(fmt::format("frames '{}': more than {} frames in one run (the "
                                             "limit; split the shot into chunks)",
                                             spec, limits::kMaxFrames));
        } else {
            break;  // not the syntax: reported below with the examples
        }
        start = comma + 1;
    }
    std::vector<int> frames;
    if (spec.empty() || start <= spec.size() ||
        !OIIO::Filesystem::enumerate_sequence(spec, frames) || frames.empty())
        throw UsageError(fmt::format("'{}' is not a frame spec (examples: 1001, 1-10, 1-10x2, "
                                     "3,4,10-20x2)",
                                     spec));
    return frames;
}

}  // namespace fp::io
