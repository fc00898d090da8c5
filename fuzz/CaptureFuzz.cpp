// Fuzz target: a capture EXR (seeds are framepass's own captures), opened through the canonical
// profile as `run` opens it — header, camera, then every buffer it offers, sanitized.
#include "fuzz/FuzzSupport.h"
#include "io/CaptureProfile.h"
#include "io/CaptureSource.h"
#include "framework/SemanticBuffers.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const fp::io::CaptureProfile profile = fp::io::CaptureProfile::load("canonical");
    return fp::fuzz::expectCleanErrors([&] {
        fp::io::CaptureSource::Options o;
        o.path = fp::fuzz::asFile(data, size, ".exr", "capture");
        fp::io::CaptureSource source(o, profile);
        source.frameInfo();
        for (const auto& buffer : source.files().availableBuffers()) {
            const fp::SemanticBuffer* b = fp::findSemanticBuffer(buffer);
            source.loadBuffer(buffer, b ? int(b->channels.size())
                                        : source.files().truthChannels()[buffer]);
        }
    });
}
