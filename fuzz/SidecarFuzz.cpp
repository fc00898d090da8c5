// Fuzz target: a camera sidecar (<capture>.camera.json), read as `run` reads it for a 64×48 frame.
#include "fuzz/FuzzSupport.h"
#include "io/CameraIO.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return fp::fuzz::expectCleanErrors([&] {
        std::vector<std::string> assumed;
        fp::io::readCameraSidecar(fp::fuzz::asFile(data, size, ".camera.json", "sidecar"),
                                  {64, 48}, assumed);
    });
}
