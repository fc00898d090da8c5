#pragma once
// The files of one captured frame seen through a profile: one multi-layer EXR, or one EXR per
// buffer (<base>_<Material>.exr). Headers are read when opened; a buffer's pixels only when asked
// for, decoded as its mapping says (channel order and sign, sums, constants, scale and offset,
// sky threshold, packed normals). Frame N−1 companions are the caller's (CaptureSource's) job.
#include "io/CaptureProfile.h"
#include "io/ExrReader.h"

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace fp::io {

/// The channel names of a Truth.* layer `channels` wide: colour as R G B (A), a scalar as Y
/// (docs/captures.md).
std::vector<std::string> truthSuffixes(int channels);

class CaptureFiles {
public:
    /// `path`: the capture file, or for a multi-file profile the base or any one of its files.
    /// Throws fp::Error when no file of the capture can be opened, or the files differ in size.
    CaptureFiles(const std::string& path, const CaptureProfile& profile);

    const CaptureProfile& profile() const { return mProfile; }
    /// The file whose header (size, camera) stands for the capture.
    ExrReader& primary() const { return *mReaders.at(mPrimaryKey); }
    Extent extent() const { return primary().extent(); }
    /// Every file of the capture that exists: the file and, for multi-file profiles, its key.
    std::vector<std::pair<std::string, const ExrReader*>> files() const;
    /// The path that names the capture: the file, or the multi-file base.
    const std::string& capturePath() const { return mCapturePath; }

    /// The mapping that fills `buffer` here (the first of the profile's whose channels exist),
    /// or nullptr. Truth.* layers of the canonical naming need no mapping.
    const BufferMapping* mappingFor(const std::string& buffer) const;
    /// Every buffer this capture can give, Truth.* layers included.
    std::set<std::string> availableBuffers() const;
    /// Channel count of every Truth.* layer: the file's, and those the profile maps.
    std::map<std::string, int> truthChannels() const;
    /// What filling `buffer` reads, for `plan`: channel names (prefixed "<file>:" for
    /// multi-file captures), "constant …" or "frame N−1 …".
    std::vector<std::string> describe(const std::string& buffer) const;
    /// Which buffer the profile fills from this file channel ("" = none): for `inspect`.
    std::string bufferOfChannel(const std::string& fileKey, const std::string& channel) const;

    /// Reads `buffer`, `channels` wide (Truth layers: 1, 3 or 4). Notes (assumptions, the
    /// normal encoding picked, half-float depth) are appended to `notes`. A previousFrame mapping
    /// is not read here (fp::Error).
    Image read(const std::string& buffer, int channels, std::vector<std::string>& notes);

    /// Seconds spent reading the files' bytes so far (ExrReader::fileSeconds).
    double fileSeconds() const;
    /// Every channel decoded so far, "<file>:<channel>" for multi-file captures.
    std::vector<std::string> readLog() const;
    /// The caveats (BufferMapping::warning) of the buffers read so far, "<buffer>: <text>".
    const std::set<std::string>& warnings() const { return mWarnings; }

private:
    ExrReader* reader(const std::string& fileKey) const;
    /// The file channel a profile channel name stands for ({camera} substituted), or nullptr.
    const ExrChannel* channel(const BufferMapping& m, const std::string& spec) const;
    bool hasChannels(const BufferMapping& m) const;
    /// Sets the pixels that m.overrideWhere marks to m.overrideValue.
    void applyOverride(const BufferMapping& m, const std::string& buffer, Image& img);
    /// Throws fp::Error naming `buffer` unless `ch`'s part covers exactly the capture's pixels.
    void checkCoversCapture(const ExrReader& file, const ExrChannel& ch,
                            const std::string& buffer) const;
    void chooseCamera();

    CaptureProfile mProfile;
    std::string mCapturePath, mBase, mPrimaryKey;
    std::map<std::string, std::unique_ptr<ExrReader>> mReaders;  // file key ("" = single) → file
    std::string mCameraSuffix;  // "" or "_<Camera>", for {camera}
    std::set<std::string> mWarnings;
};

}  // namespace fp::io
