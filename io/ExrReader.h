#pragma once
// Reads multi-layer (and multi-part) OpenEXR files channel by channel: the header is read when
// the file is opened, pixels only for the channels asked for (docs/captures.md, lazy reads).
#include "foundation/Image.h"

#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfPixelType.h>

#include <memory>
#include <string>
#include <vector>

namespace OPENEXR_IMF_INTERNAL_NAMESPACE { class MultiPartInputFile; class IStream; }

namespace fp::io {

struct ExrChannel {
    std::string name;  //!< full name, e.g. "WorldNormal.X"
    int part = 0;
    Imf::PixelType type = Imf::FLOAT;
};

class ExrReader {
public:
    /// Opens the file and reads its headers; throws fp::Error naming the file if it cannot.
    explicit ExrReader(const std::string& path);
    ~ExrReader();

    const std::string& path() const { return mPath; }
    const std::vector<ExrChannel>& channels() const { return mChannels; }
    const ExrChannel* findChannel(const std::string& name) const;
    Extent extent() const { return mExtent; }
    const Imf::Header& header(int part = 0) const;
    int partCount() const;

    /// Reads the named channels (all from one part or several) into one image whose channels
    /// are called `names`. Half and uint data are converted to float while decoding.
    Image read(const std::vector<std::string>& fileChannels, const std::vector<std::string>& names);
    /// Same, for channels picked from channels() (names repeat across the parts of a mip chain).
    Image read(const std::vector<const ExrChannel*>& channels, const std::vector<std::string>& names);
    /// `rows` rows of them from row `firstRow` of their data window (one part): a large file
    /// read a band at a time.
    Image readRows(const std::vector<const ExrChannel*>& channels,
                   const std::vector<std::string>& names, int firstRow, int rows);

    /// Every channel decoded so far, in order: the proof that reads are lazy.
    const std::vector<std::string>& readLog() const { return mReadLog; }
    /// Seconds spent so far reading bytes from the file (headers and pixel chunks), apart from
    /// decompressing and converting them: a run's report separates the two.
    double fileSeconds() const;

private:
    std::string mPath;
    std::unique_ptr<Imf::IStream> mStream;  // before mFile, which reads through it
    std::unique_ptr<Imf::MultiPartInputFile> mFile;
    std::vector<ExrChannel> mChannels;
    Extent mExtent;
    std::vector<Extent> mPartExtents;
    std::vector<std::string> mReadLog;
};

}  // namespace fp::io
