#pragma once
// Writes a frame's outputs: EXR (one part; or one part per mip for mip chains) or PNG previews,
// named by the output's file pattern under the output folder, never over an input.
#include "io/ExrWriter.h"
#include "framework/Executor.h"

#include <mutex>
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
        int pngLevel = 1;       //!< zlib level of PNG previews (io/PngWriter.h)
        std::set<std::string> protectedPaths;  //!< inputs: never overwritten
    };
    explicit OutputWriter(Options options) : mOptions(std::move(options)) {}

    /// One file written: where, and how long its encoding (checks, conversion, compression) and
    /// its writing (the bytes to disk, the rename) took.
    struct WrittenFile {
        std::string path;
        double encodeSeconds = 0, writeSeconds = 0;
    };
    /// Writes one output of `frame`. Safe to call from several threads at once.
    WrittenFile writeFile(const OutputDesc& output, const std::vector<OutputLayer>& layers,
                          const FrameInfo& frame);

    void write(const OutputDesc& output, const std::vector<OutputLayer>& layers,
               const FrameInfo& frame) override {
        writeFile(output, layers, frame);
    }
    /// The path an output takes for `frame`.
    std::string pathFor(const OutputDesc& output, int64_t frame) const;
    /// Every file written so far, in the order each was finished.
    std::vector<std::string> written() const {
        const std::lock_guard<std::mutex> lock(mMutex);
        return mWritten;
    }
    /// Where dumps go: Options::dumpDir, else <outputDir>/dump.
    std::string dumpDir() const;

private:
    Options mOptions;
    mutable std::mutex mMutex;
    std::vector<std::string> mWritten;
};

}  // namespace fp::io
