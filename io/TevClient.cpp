#include "io/TevClient.h"

#include "foundation/Error.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace fp::io {

namespace {

enum : uint8_t { kCreateImage = 4, kUpdateImage = 6 };
constexpr int kDefaultTevPort = 14158;

class Packet {
public:
    explicit Packet(uint8_t type) : mBytes(4, '\0') { mBytes.push_back(char(type)); }
    void byte(uint8_t v) { mBytes.push_back(char(v)); }
    void u32(uint32_t v) { raw(&v, 4); }
    void u64(uint64_t v) { raw(&v, 8); }
    void f32(float v) { raw(&v, 4); }
    void text(const std::string& s) {
        FP_CHECK(s.find('\0') == std::string::npos, "tev: a name may not hold a zero byte");
        mBytes += s;
        mBytes.push_back('\0');
    }
    std::string done() {
        const uint32_t size = uint32_t(mBytes.size());
        std::memcpy(mBytes.data(), &size, 4);  // little-endian hosts only (x86-64, aarch64)
        return std::move(mBytes);
    }

private:
    void raw(const void* p, std::size_t n) { mBytes.append(static_cast<const char*>(p), n); }
    std::string mBytes;
};

}  // namespace

std::string tevCreateImagePacket(const std::string& name, int width, int height,
                                 const std::vector<std::string>& channels, bool grabFocus) {
    Packet p(kCreateImage);
    p.byte(grabFocus ? 1 : 0);
    p.text(name);
    p.u32(uint32_t(width));
    p.u32(uint32_t(height));
    p.u32(uint32_t(channels.size()));
    for (const auto& c : channels) p.text(c);
    return p.done();
}

std::string tevUpdateImagePacket(const std::string& name, const Image& image, int x, int y,
                                 int w, int h, bool grabFocus) {
    Packet p(kUpdateImage);
    const int channels = image.channelCount();
    p.byte(grabFocus ? 1 : 0);
    p.text(name);
    p.u32(uint32_t(channels));
    for (const auto& c : image.channels()) p.text(c);
    p.u32(uint32_t(x));
    p.u32(uint32_t(y));
    p.u32(uint32_t(w));
    p.u32(uint32_t(h));
    // Planar data: channel c's pixels one after the other.
    const uint64_t pixels = uint64_t(w) * uint64_t(h);
    for (int c = 0; c < channels; ++c) p.u64(uint64_t(c) * pixels);
    for (int c = 0; c < channels; ++c) p.u64(1);
    for (int c = 0; c < channels; ++c)
        for (int row = y; row < y + h; ++row)
            for (int col = x; col < x + w; ++col) p.f32(image.plane(c).at(col, row));
    return p.done();
}

TevClient::TevClient(const std::string& address) : mAddress(address) {
    std::string host = address, port = std::to_string(kDefaultTevPort);
    if (const auto colon = address.rfind(':'); colon != std::string::npos) {
        host = address.substr(0, colon);
        port = address.substr(colon + 1);
    }
    if (host.empty()) host = "127.0.0.1";
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (const int rc = ::getaddrinfo(host.c_str(), port.c_str(), &hints, &found); rc != 0)
        throw UsageError(fmt::format("--tev {}: not an address ({})", address, gai_strerror(rc)));
    int error = 0;
    for (addrinfo* a = found; a && mSocket < 0; a = a->ai_next) {
        const int s = ::socket(a->ai_family, a->ai_socktype, a->ai_protocol);
        if (s < 0) continue;
        if (::connect(s, a->ai_addr, a->ai_addrlen) == 0) {
            mSocket = s;
        } else {
            error = errno;
            ::close(s);
        }
    }
    ::freeaddrinfo(found);
    if (mSocket < 0)
        throw Error(fmt::format("--tev {}: cannot connect ({}); is tev running? (start it with "
                                "`tev`, which listens on 127.0.0.1:{})",
                                address, std::strerror(error), kDefaultTevPort));
}

TevClient::~TevClient() {
    if (mSocket >= 0) ::close(mSocket);
}

void TevClient::send(const std::string& packet) {
    std::size_t sent = 0;
    while (sent < packet.size()) {
        const ssize_t n = ::send(mSocket, packet.data() + sent, packet.size() - sent, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0)
            throw Error(fmt::format("tev {}: the connection closed ({})", mAddress,
                                    std::strerror(errno)));
        sent += std::size_t(n);
    }
}

void TevClient::sendImage(const std::string& name, const Image& image, bool grabFocus) {
    send(tevCreateImagePacket(name, image.width(), image.height(), image.channels(), grabFocus));
    for (int y = 0; y < image.height(); y += kTevTileSize)
        for (int x = 0; x < image.width(); x += kTevTileSize)
            send(tevUpdateImagePacket(name, image, x, y,
                                      std::min(kTevTileSize, image.width() - x),
                                      std::min(kTevTileSize, image.height() - y), false));
}

void TevSink::write(const OutputDesc& output, const std::vector<OutputLayer>& layers,
                    const FrameInfo& frame) {
    mInner.write(output, layers, frame);
    for (const auto& l : layers) mTev.sendImage(l.name, l.texture->image());
}

}  // namespace fp::io
