#pragma once
// Limits on what an input may ask for, checked where the input is read so a bad file fails early
// with a message that says which limit, instead of allocating gigabytes or recursing without end.
// docs/commands.md ("Limits") lists them; raise one here and there together.
#include <cstdint>

namespace fp::limits {

constexpr int kMaxJsonDepth = 64;                 //!< nesting of any JSON file or --set value
constexpr int64_t kMaxFrames = 1'000'000;         //!< frames one spec may expand to
constexpr int64_t kMaxFrameNumber = 999'999'999;  //!< |frame number|: 9 digits, no int overflow
constexpr int kMaxFrameDigits = 16;               //!< width of a frame token (%016d, 16 #)
constexpr int kMaxImageDimension = 32768;         //!< width or height, pixels
constexpr int64_t kMaxImagePixels = int64_t(1) << 28;         //!< width × height (16384², 268 M)
constexpr int kMaxThreads = 1024;                             //!< --threads
constexpr int64_t kMaxExrAttributeBytes = int64_t(64) << 20;  //!< one EXR header attribute
constexpr int kMaxGltfNodeDepth = 256;                        //!< glTF node hierarchy depth

}  // namespace fp::limits
