#pragma once
// How `framepass sheet` shows a buffer a person cannot look at directly: each layer is classified
// (colour, depth, normals, ids or other data) and data layers are mapped to display-referred RGB
// over their own range — depth logarithmically with sky in its own colour, normals as n·½ + ½,
// ids as false colour — so that the range printed on the tile is the range in the buffer. Colour
// layers are not mapped here: they go through the OCIO display transform (DisplayTransform).
#include "foundation/Image.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace fp {

enum class PreviewKind { Color, Depth, Normal, Id, Data };

/// "colour", "depth", "normal", "id", "data".
const char* previewKindName(PreviewKind kind);

/// What the classifier knows of a layer before reading its pixels.
struct LayerDescription {
    std::string name;                   //!< "SceneDepth", "Truth.AO", "" for the unnamed layer
    std::vector<std::string> suffixes;  //!< channel suffixes in display order: R G B A, X Y Z
    std::string buffer;                 //!< the framepass buffer the profile maps it to, or ""
    bool integerChannels = false;       //!< every channel is stored as uint
};

/// The kind of a layer. By name first: a semantic buffer of kind colour (BaseColor, SceneColor…)
/// is colour, SceneDepth/PrevSceneDepth depth, WorldNormal normals, InstanceId/ShadingModel ids,
/// any other semantic buffer data; `*.StdErr` layers are data. Otherwise by channels: uint
/// channels are ids, a lone Z or a name containing "depth" is depth, X Y Z whose finite values
/// all lie in [-1, 1] (checked on `pixels` when given) are normals, R G B is colour, the rest data.
PreviewKind classifyLayer(const LayerDescription& layer, const Image* pixels);

/// The values a data tile is mapped over.
struct PreviewRange {
    bool valid = false;        //!< some finite value was seen (for depth: some positive one)
    float min = 0, max = 0;    //!< finite values (depth: finite and > 0), over all channels
    bool logarithmic = false;  //!< depth
    uint64_t skyPixels = 0;    //!< depth: +inf, NaN or ≤ 0 (drawn in kSkyColor)
    uint64_t nonFinite = 0;    //!< other kinds: NaN/Inf values (drawn in kInvalidColor)
};

/// The range of `pixels` as `kind` maps it: depth over its finite positive values, normals
/// fixed at [-1, 1], everything else over its finite values. Colour gets no range (invalid).
PreviewRange previewRange(const Image& pixels, PreviewKind kind);

/// Display-referred RGB in [0, 1] for a data layer (any kind but colour): depth as log grey from
/// min (black) to max (white), sky kSkyColor; normals n·½ + ½; ids false colour by a hash of the
/// integer value (0 black); data linear grey (1 channel), R G (2) or RGB (first 3) from min
/// (0) to max (1). NaN/Inf show as kInvalidColor. A constant data layer shows mid-grey.
Image previewData(const Image& pixels, PreviewKind kind, const PreviewRange& range);

/// The tile's label after the layer name: "depth 12.3..845 log", "0..1", "constant 1",
/// "normal -1..1", "id 0..11", "colour (OCIO)"; with ", N sky" or ", N NaN/Inf" when there are
/// any. ASCII only (OpenImageIO 2.4's render_text draws other characters as boxes).
std::string previewRangeLabel(PreviewKind kind, const PreviewRange& range);

/// The false colour of integer id `id` (display-referred; 0 is black).
std::array<float, 3> idColor(uint32_t id);

inline constexpr std::array<float, 3> kSkyColor = {0.35f, 0.55f, 0.85f};
inline constexpr std::array<float, 3> kInvalidColor = {1.0f, 0.0f, 1.0f};

}  // namespace fp
