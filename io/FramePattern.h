#pragma once
// Frame sequences: `#` alone = 4 digits (oiiotool), a run `####` = one digit per `#` (Nuke,
// Deadline), `@` = one digit each, printf `%04d`; frame specs such as "1001-1100x2", "1-5y2",
// "3,4,10-20x2" are expanded by OpenImageIO's own oiiotool helper.
#include <string>
#include <vector>

namespace fp::io {

class FramePattern {
public:
    /// `pattern` may or may not contain frame tokens; an inline range ("shot.1-10#.exr") is
    /// remembered as the pattern's own frame spec.
    explicit FramePattern(const std::string& pattern);

    bool hasFrameToken() const { return mHasToken; }
    /// The file name for `frame` (the pattern itself when it has no token).
    std::string path(int frame) const;
    /// The frame spec written inside the pattern, if any ("" otherwise).
    const std::string& inlineFrames() const { return mInlineFrames; }

private:
    std::string mPattern, mPrefix, mSuffix, mInlineFrames;
    int mDigits = 0;
    bool mHasToken = false;
};

/// Expands a frame spec; throws fp::UsageError (quoting the spec) when it is malformed.
std::vector<int> parseFrameSpec(const std::string& spec);

}  // namespace fp::io
