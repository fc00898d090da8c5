// The tev client against a fake tev: a socket on 127.0.0.1 that reads the packets, decodes them as
// tev's protocol says (docs/serve.md, tev) and rebuilds the image from the tiles.
#include "io/TevClient.h"
#include "foundation/Error.h"

#include <doctest/doctest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <map>
#include <string>
#include <thread>

namespace fp::test {

namespace {

// Reads every byte a client sends until it closes.
class FakeTev {
public:
    FakeTev() {
        mListen = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(::bind(mListen, reinterpret_cast<sockaddr*>(&a), sizeof(a)) == 0);
        socklen_t len = sizeof(a);
        ::getsockname(mListen, reinterpret_cast<sockaddr*>(&a), &len);
        mPort = ntohs(a.sin_port);
        REQUIRE(::listen(mListen, 1) == 0);
        mThread = std::thread([this] {
            const int c = ::accept(mListen, nullptr, nullptr);
            char buf[65536];
            for (ssize_t n; (n = ::recv(c, buf, sizeof(buf), 0)) > 0;) bytes.append(buf, std::size_t(n));
            ::close(c);
        });
    }
    ~FakeTev() { ::close(mListen); }
    std::string address() const { return "127.0.0.1:" + std::to_string(mPort); }
    void join() { mThread.join(); }
    std::string bytes;

private:
    int mListen = -1, mPort = 0;
    std::thread mThread;
};

struct Reader {
    const std::string& s;
    std::size_t at = 0;
    template <class T>
    T get() {
        T v;
        std::memcpy(&v, s.data() + at, sizeof(T));
        at += sizeof(T);
        return v;
    }
    std::string text() {
        const std::size_t end = s.find('\0', at);
        std::string t = s.substr(at, end - at);
        at = end + 1;
        return t;
    }
};

}  // namespace

TEST_SUITE("io") {
    TEST_CASE("the tev client sends an image tev rebuilds bit for bit, in bounded tiles") {
        Image image(300, 20, {"R", "G", "B"});
        for (int c = 0; c < 3; ++c)
            for (int y = 0; y < 20; ++y)
                for (int x = 0; x < 300; ++x) image.plane(c).at(x, y) = float(c * 10000 + y * 300 + x) * 0.5f;
        FakeTev tev;
        {
            io::TevClient client(tev.address());
            client.sendImage("ssgi.diffuse (frame 1)", image, true);
        }
        tev.join();

        Reader r{tev.bytes};
        std::map<std::string, Image> rebuilt;
        int updates = 0;
        while (r.at < tev.bytes.size()) {
            const std::size_t start = r.at;
            const uint32_t length = r.get<uint32_t>();
            const uint8_t type = r.get<uint8_t>();
            CHECK(length <= 4 + 1 + 64 + 16 + 3 * 16 + io::kTevTileSize * io::kTevTileSize * 3 * 4);
            if (type == 4) {  // CreateImage
                CHECK(r.get<uint8_t>() == 1);
                const std::string name = r.text();
                CHECK(name == "ssgi.diffuse (frame 1)");
                const uint32_t w = r.get<uint32_t>(), h = r.get<uint32_t>(), n = r.get<uint32_t>();
                std::vector<std::string> channels;
                for (uint32_t c = 0; c < n; ++c) channels.push_back(r.text());
                CHECK(channels == image.channels());
                rebuilt.emplace(name, Image(int(w), int(h), channels));
            } else {
                REQUIRE(type == 6);  // UpdateImage
                ++updates;
                r.get<uint8_t>();
                Image& img = rebuilt.at(r.text());
                const uint32_t n = r.get<uint32_t>();
                for (uint32_t c = 0; c < n; ++c) r.text();
                const uint32_t x = r.get<uint32_t>(), y = r.get<uint32_t>(), w = r.get<uint32_t>(),
                               h = r.get<uint32_t>();
                std::vector<uint64_t> offsets(n), strides(n);
                for (auto& o : offsets) o = r.get<uint64_t>();
                for (auto& s : strides) s = r.get<uint64_t>();
                const std::size_t data = r.at;
                for (uint32_t c = 0; c < n; ++c)
                    for (uint32_t i = 0; i < w * h; ++i) {
                        float v;
                        std::memcpy(&v, tev.bytes.data() + data + (offsets[c] + i * strides[c]) * 4, 4);
                        img.plane(int(c)).at(int(x + i % w), int(y + i / w)) = v;
                    }
                r.at = data + std::size_t(n) * w * h * 4;
            }
            CHECK(r.at - start == length);
        }
        CHECK(updates == 2);  // 300 pixels wide: two tiles of at most 256
        const Image& got = rebuilt.at("ssgi.diffuse (frame 1)");
        for (int c = 0; c < 3; ++c)
            for (int y = 0; y < 20; ++y)
                for (int x = 0; x < 300; ++x) REQUIRE(got.plane(c).at(x, y) == image.plane(c).at(x, y));
    }

    TEST_CASE("the tev client says when nothing listens, and refuses a bad address") {
        int port = 0;
        {  // a port that was free a moment ago
            FakeTev closed;
            port = std::stoi(closed.address().substr(10));
            { io::TevClient wake(closed.address()); }  // lets its accept() and read return
            closed.join();
        }
        CHECK_THROWS_WITH(io::TevClient("127.0.0.1:" + std::to_string(port)),
                          doctest::Contains("is tev running?"));
        CHECK_THROWS_AS(io::TevClient("no such host name.invalid:1"), UsageError);
    }
}

}  // namespace fp::test
