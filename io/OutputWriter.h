#pragma once
// Writes a frame's outputs: EXR (one part; or one part per mip for mip chains) or PNG previews,
// named by the output's file pattern under the output folder, never over an input.
#include "io/ExrWriter.h"
#include "framework/Executor.h"

#include <set>
#include <string>
#include <vector>

namespace fp::io {

class OutputWriter final : public FrameSink {
public:
    struct Options {
        std::string outputDir = ".";
        std::string dumpDir;               //!< "" = <outputDir>/dump
        ExrCompression compression = ExrCompression::Zip;
        bool halfColor = true;  //!< colour layers as half (float32 when false); data is float32
        std::set<std::string> protectedPaths;  //!< inputs: never overwritten
    };
    explicit OutputWriter(Options options) : mOptions(std::move(options)) {}

    void write(const OutputDesc& output, const std::vector<OutputLayer>& layers,
               const FrameInfo& frame) override;
    /// The path an output takes for `frame`.
    std::string pathFor(const OutputDesc& output, int64_t frame) const;
    const std::vector<std::string>& written() const { return mWritten; }
    /// Where dumps go: Options::dumpDir, else <outputDir>/dump.
    std::string dumpDir() const;

private:
    Options mOptions;
    std::vector<std::string> mWritten;
};

}  // namespace fp::io
