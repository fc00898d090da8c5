// hybrid_reflections: rays that finish on screen are SSR's, bit for bit; rays the screen cannot
// finish are traced through the scene, so coverage and hits only grow.
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

namespace fp {

namespace {

// hzb → `type` (ssr or hybrid_reflections), SSR at Epic (GGX rays, postProcessQuality 100).
std::map<std::string, Texture> run(test::MemorySource& src, const std::string& type,
                                   std::map<std::string, uint64_t>* work = nullptr) {
    test::MemorySink sink;
    const std::vector<NodeDesc> chain = {
        test::node("hzb"),
        test::node(type, {{"quality", 4}, {"postProcessQuality", 100}},
                   {{"furthestHzb", "hzb.furthest"}})};
    const std::vector<std::string> outputs = {type + ".reflection", type + ".hitMask"};
    const FrameReport rep = executePlan(test::planFor(chain, outputs), src, sink);
    if (work) *work = rep.passes.back().work;
    return sink.layers;
}

// floorAndWall's glowing floor and wall, glossy (roughness 0.3) so SSR traces them, under a sun.
Scene glossyRoom() {
    Scene s = test::floorAndWall();
    s.materials[0] = test::lambert(0.5f, test::kGlow);
    s.materials[0].roughness = 0.3f;
    s.lights.push_back(test::sun({0.3, -1, 0.2}));
    return s;
}

}  // namespace

TEST_CASE("hybrid_reflections: rays that finish on screen are SSR's, bit for bit") {
    // The scene the fallback traces is empty and has no sky light: a ray the screen cannot finish
    // brings nothing, as in SSR, so the two passes agree at every pixel.
    const Scene scene = glossyRoom();
    auto src = test::captureToMemory(scene, test::wallCamera(40));
    const auto ssr = run(src, "ssr");
    const Scene empty;
    src.sceneData = &empty;
    std::map<std::string, uint64_t> work;
    const auto hybrid = run(src, "hybrid_reflections", &work);
    for (const char* port : {"reflection", "hitMask"}) {
        const Image& a = hybrid.at(std::string("hybrid_reflections.") + port).image();
        const Image& b = ssr.at(std::string("ssr.") + port).image();
        for (int c = 0; c < a.channelCount(); ++c) CHECK(test::sameBits(a.plane(c), b.plane(c)));
    }
    CHECK(work.at("fallbackRays") > 0);
    CHECK(work.at("fallbackHits") == 0);
}

TEST_CASE("hybrid_reflections: with the scene, the rays the screen missed find it") {
    // The same capture with its scene: each ray either finishes on screen (SSR's sample) or
    // falls back (SSR: nothing; here a hit, weight 1): hits and coverage never fall, and grow
    // where the wall behind the camera or the floor off screen is reflected.
    const Scene scene = glossyRoom();
    auto src = test::captureToMemory(scene, test::wallCamera(40));
    const auto ssr = run(src, "ssr");
    std::map<std::string, uint64_t> work;
    const auto hybrid = run(src, "hybrid_reflections", &work);
    CHECK(work.at("fallbackHits") > 0);
    const Plane& hm = hybrid.at("hybrid_reflections.hitMask").image().plane(0);
    const Plane& sm = ssr.at("ssr.hitMask").image().plane(0);
    const Plane& ha = hybrid.at("hybrid_reflections.reflection").image().plane(3);
    const Plane& sa = ssr.at("ssr.reflection").image().plane(3);
    int grew = 0;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x) {
            CHECK(hm.at(x, y) >= sm.at(x, y));
            CHECK(ha.at(x, y) >= sa.at(x, y));
            grew += hm.at(x, y) > sm.at(x, y);
        }
    CHECK(grew > 0);
}

}  // namespace fp
