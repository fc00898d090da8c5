#pragma once
// A client of tev's remote-control protocol (the HDR viewer many rendering engineers keep open):
// framepass pushes buffers to it as named images, from `framepass run --tev` and from the
// workbench's button. The protocol is TCP to 127.0.0.1:14158 by default; each packet is its
// length (uint32, little-endian, counting the length itself), a type byte and the fields, strings
// zero-terminated. CreateImage (type 4): grab focus (1 byte), name, width, height, channel
// count (uint32 each), channel names. UpdateImage (type 6, "v3"): grab focus, name, channel
// count, channel names, x, y, width, height (uint32), then per channel an offset and a stride
// (uint64, in floats) into the float32 data that follows. Images are sent in tiles so no packet
// grows with the image.
#include "framework/Executor.h"
#include "foundation/Image.h"

#include <memory>
#include <string>
#include <vector>

namespace fp::io {

/// The largest tile one UpdateImage packet carries (pixels a side).
inline constexpr int kTevTileSize = 256;

/// The bytes of a CreateImage packet.
std::string tevCreateImagePacket(const std::string& name, int width, int height,
                                 const std::vector<std::string>& channels, bool grabFocus);
/// The bytes of an UpdateImage packet with the pixels of `image` in [x, x+w) × [y, y+h).
std::string tevUpdateImagePacket(const std::string& name, const Image& image, int x, int y,
                                 int w, int h, bool grabFocus);

class TevClient {
public:
    /// Connects to "HOST:PORT" (or "HOST", port 14158). Throws fp::Error saying whether nothing
    /// listens there or the address is bad.
    explicit TevClient(const std::string& address);
    ~TevClient();
    TevClient(const TevClient&) = delete;
    TevClient& operator=(const TevClient&) = delete;

    /// Creates (or replaces) the image `name` in tev and sends its pixels, tile by tile.
    void sendImage(const std::string& name, const Image& image, bool grabFocus = false);
    const std::string& address() const { return mAddress; }

private:
    void send(const std::string& packet);
    std::string mAddress;
    int mSocket = -1;
};

/// Hands every output on to `inner` and pushes each of its layers to tev as the image named
/// after the layer (a later frame replaces it): what `framepass run --tev` adds to the outputs.
class TevSink final : public FrameSink {
public:
    TevSink(FrameSink& inner, TevClient& tev) : mInner(inner), mTev(tev) {}
    void write(const OutputDesc& output, const std::vector<OutputLayer>& layers,
               const FrameInfo& frame) override;

private:
    FrameSink& mInner;
    TevClient& mTev;
};

}  // namespace fp::io
