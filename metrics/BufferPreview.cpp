#include "metrics/BufferPreview.h"

#include "framework/SemanticBuffers.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace fp {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

bool endsWith(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// Every finite value of the first three channels lies in [-1, 1] (with half-float slack).
bool looksLikeUnitVectors(const Image& img) {
    constexpr float kSlack = 1.001f;
    for (int c = 0; c < std::min(3, img.channelCount()); ++c)
        for (int y = 0; y < img.height(); ++y)
            for (int x = 0; x < img.width(); ++x) {
                const float v = img.plane(c).at(x, y);
                if (std::isfinite(v) && std::fabs(v) > kSlack)
                    return false;
            }
    return true;
}

// Three significant digits, but whole numbers up to a million in full ("1000", not "1e+03").
std::string number(float v) {
    const float a = std::fabs(v);
    return a >= 1000.0f && a < 1e6f ? fmt::format("{:.0f}", v) : fmt::format("{:.3g}", v);
}

}  // namespace

const char* previewKindName(PreviewKind kind) {
    switch (kind) {
        case PreviewKind::Color:
            return "colour";
        case PreviewKind::Depth:
            return "depth";
        case PreviewKind::Normal:
            return "normal";
        case PreviewKind::Id:
            return "id";
        case PreviewKind::Data:
            return "data";
    }
    return "data";
}

PreviewKind classifyLayer(const LayerDescription& layer, const Image* pixels) {
    const std::string& key = layer.buffer.empty() ? layer.name : layer.buffer;
    if (const SemanticBuffer* sem = findSemanticBuffer(key)) {
        if (sem->kind == PortKind::Color)
            return PreviewKind::Color;
        if (isDepthBuffer(key))
            return PreviewKind::Depth;
        if (key == "WorldNormal")
            return PreviewKind::Normal;
        if (key == "InstanceId" || key == "ShadingModel")
            return PreviewKind::Id;
        return PreviewKind::Data;
    }
    // A standard error is a spread, not a colour, even when its channels are R G B.
    if (endsWith(layer.name, ".StdErr"))
        return PreviewKind::Data;
    if (layer.integerChannels)
        return PreviewKind::Id;
    const std::string name = lower(layer.name);
    const auto& s = layer.suffixes;
    if (name.find("depth") != std::string::npos || s == std::vector<std::string>{"Z"})
        return PreviewKind::Depth;
    if (s == std::vector<std::string>{"X", "Y", "Z"}) {
        if (name.find("normal") != std::string::npos || !pixels || looksLikeUnitVectors(*pixels))
            return PreviewKind::Normal;
        return PreviewKind::Data;
    }
    if (s.size() >= 3 && s[0] == "R" && s[1] == "G" && s[2] == "B")
        return PreviewKind::Color;
    return PreviewKind::Data;
}

PreviewRange previewRange(const Image& pixels, PreviewKind kind) {
    PreviewRange r;
    if (kind == PreviewKind::Color)
        return r;
    if (kind == PreviewKind::Normal) {
        r.valid = true;
        r.min = -1.0f;
        r.max = 1.0f;
    }
    r.logarithmic = kind == PreviewKind::Depth;
    float lo = INFINITY, hi = -INFINITY;
    const int channels = kind == PreviewKind::Depth ? 1 : pixels.channelCount();
    for (int c = 0; c < channels; ++c)
        for (int y = 0; y < pixels.height(); ++y)
            for (int x = 0; x < pixels.width(); ++x) {
                const float v = pixels.plane(c).at(x, y);
                if (kind == PreviewKind::Depth && !(std::isfinite(v) && v > 0.0f)) {
                    ++r.skyPixels;
                } else if (!std::isfinite(v)) {
                    ++r.nonFinite;
                } else {
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
            }
    if (kind != PreviewKind::Normal && lo <= hi) {
        r.valid = true;
        r.min = lo;
        r.max = hi;
    }
    return r;
}

std::array<float, 3> idColor(uint32_t id) {
    if (id == 0)
        return {0.0f, 0.0f, 0.0f};
    // An integer hash (a murmur3-style finaliser) spreads neighbouring ids far apart in colour.
    uint32_t h = id;
    h ^= h >> 16;
    h *= 0x7feb352dU;
    h ^= h >> 15;
    h *= 0x846ca68bU;
    h ^= h >> 16;
    // Kept between 0.2 and 1 so that no id is mistaken for 0 (black).
    return {0.2f + 0.8f * float(h & 0xff) / 255.0f, 0.2f + 0.8f * float(h >> 8 & 0xff) / 255.0f,
            0.2f + 0.8f * float(h >> 16 & 0xff) / 255.0f};
}

Image previewData(const Image& pixels, PreviewKind kind, const PreviewRange& range) {
    const int w = pixels.width(), h = pixels.height(), n = pixels.channelCount();
    Image out(w, h, {"R", "G", "B"});
    auto put = [&](int x, int y, const std::array<float, 3>& rgb) {
        for (int c = 0; c < 3; ++c)
            out.plane(c).at(x, y) = rgb[c];
    };
    const double logLo = range.valid ? std::log(double(range.min)) : 0.0;
    const double logSpan = range.valid ? std::log(double(range.max)) - logLo : 0.0;
    const float span = range.max - range.min;
    auto unit = [&](float v) {  // linear: min → 0, max → 1; a constant layer mid-grey
        return span > 0.0f ? std::clamp((v - range.min) / span, 0.0f, 1.0f) : 0.5f;
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            switch (kind) {
                case PreviewKind::Depth: {
                    const float d = pixels.plane(0).at(x, y);
                    if (!(std::isfinite(d) && d > 0.0f)) {
                        put(x, y, kSkyColor);
                        break;
                    }
                    const float g =
                        logSpan > 0.0
                            ? float(std::clamp((std::log(double(d)) - logLo) / logSpan, 0.0, 1.0))
                            : 0.0f;
                    put(x, y, {g, g, g});
                    break;
                }
                case PreviewKind::Id: {
                    const float v = pixels.plane(0).at(x, y);
                    if (!std::isfinite(v) || v < 0.0f)
                        put(x, y, kInvalidColor);
                    else
                        put(x, y, idColor(uint32_t(std::lround(v))));
                    break;
                }
                case PreviewKind::Normal:
                case PreviewKind::Data:
                case PreviewKind::Color: {
                    std::array<float, 3> rgb = {0.0f, 0.0f, 0.0f};
                    bool bad = false;
                    for (int c = 0; c < 3; ++c) {
                        const int from = n == 1 ? 0 : c;  // 1 channel → grey; 2 → R G and black B
                        if (from >= n)
                            continue;
                        const float v = pixels.plane(from).at(x, y);
                        bad = bad || !std::isfinite(v);
                        rgb[c] = kind == PreviewKind::Normal
                                     ? std::clamp(v * 0.5f + 0.5f, 0.0f, 1.0f)
                                     : unit(v);
                    }
                    put(x, y, bad ? kInvalidColor : rgb);
                    break;
                }
            }
        }
    return out;
}

std::string previewRangeLabel(PreviewKind kind, const PreviewRange& range) {
    // An end a millionth of the other's size is rounding noise around 0 (7.1e-15 → 0).
    auto tidy = [&](float v) {
        const float big = std::max(std::fabs(range.min), std::fabs(range.max));
        return number(std::fabs(v) < 1e-6f * big ? 0.0f : v);
    };
    std::string label;
    switch (kind) {
        case PreviewKind::Color:
            return "colour (OCIO)";
        case PreviewKind::Normal:
            label = "normal -1..1";
            break;
        case PreviewKind::Depth:
            label = range.valid ? fmt::format("depth {}..{} log", tidy(range.min), tidy(range.max))
                                : "depth: all sky";
            break;
        case PreviewKind::Id:
            label = range.valid ? fmt::format("id {}..{}", tidy(range.min), tidy(range.max))
                                : "id: no finite value";
            break;
        case PreviewKind::Data:
            label = !range.valid ? "no finite value"
                    : range.min == range.max
                        ? fmt::format("constant {}", number(range.min))
                        : fmt::format("{}..{}", tidy(range.min), tidy(range.max));
            break;
    }
    if (range.skyPixels)
        label += fmt::format(", {} sky", range.skyPixels);
    if (range.nonFinite)
        label += fmt::format(", {} NaN/Inf", range.nonFinite);
    return label;
}

}  // namespace fp
