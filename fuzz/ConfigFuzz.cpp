// Fuzz target: a run config, parsed, validated and planned against the built-in passes (the
// path of `framepass plan`), with the capture's buffers given so binding is exercised too.
#include "fuzz/FuzzSupport.h"
#include "io/ConfigLoader.h"
#include "framework/PassRegistry.h"
#include "framework/Planner.h"
#include "framework/SemanticBuffers.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return fp::fuzz::expectCleanErrors([&] {
        const std::string path = fp::fuzz::asFile(data, size, ".json", "config");
        const fp::io::RunConfig config = fp::io::loadRunConfig(path);
        fp::PlanInputs in;
        in.priorErrors = config.errors;
        std::set<std::string> buffers;
        for (const auto& b : fp::semanticBuffers()) buffers.insert(b.name);
        in.availableBuffers = buffers;
        in.lightNames = {"key", "fill"};
        fp::makePlan(config.graph, fp::builtinPasses(), in);
    });
}
