#pragma once
// A frame read from a capture through its profile: the headers (channels, camera) when opened,
// pixels buffer by buffer as the executor asks for them, frame N−1's files only for buffers the
// profile takes from the previous frame, the scene's BVH and the OCIO config only if a pass needs
// them. Input pixels pass through the sanitize policy of docs/design.md, Numerics and determinism on the way in.
#include "io/CaptureFiles.h"
#include "io/CaptureProfile.h"
#include "io/scene/SceneLoader.h"
#include "framework/Executor.h"
#include "foundation/RayScene.h"

#include <atomic>
#include <functional>
#include <map>
#include <mutex>
#include <memory>
#include <string>

namespace fp::io {

struct SanitizeCounts {
    uint64_t nonFinite = 0, negative = 0, nonUnitNormals = 0;
    uint64_t total() const { return nonFinite + negative + nonUnitNormals; }
    SanitizeCounts& operator+=(const SanitizeCounts& o) {
        nonFinite += o.nonFinite;
        negative += o.negative;
        nonUnitNormals += o.nonUnitNormals;
        return *this;
    }
};

/// The input policy of docs/design.md (Numerics and determinism), applied in place to capture
/// buffer `buffer`: colour that is not finite or is negative becomes 0; depth that is NaN or ≤ 0
/// becomes sky (+inf); normals off unit length are renormalised (zero, the sky's, stays zero).
/// Returns what it changed. Every capture, on disk or in memory, goes through it.
SanitizeCounts sanitizeBuffer(const std::string& buffer, Image& image);

/// Whether the scene lines up with the capture (foundation/SceneAlignment.h), measured once on
/// the first frame that traces rays and shared by the frames of a run: a scene that does not is
/// an error on every frame, never a silently dark one.
struct SceneAlignmentCheck {
    std::once_flag once;
    std::string error;    //!< non-empty: most camera rays disagree with the capture's depth
    std::string warning;  //!< non-empty: some do (a partial scene, moved objects)
};

/// How to open one frame of a capture, and where its scene and OCIO config come from.
struct CaptureOptions {
    std::string path;  //!< the capture file of this frame (multi-file profiles: its base)
    std::string previousPath;  //!< frame N−1's capture ("" = none: a sequence's first)
    int64_t frame = 1;
    std::string cameraSidecar;                //!< "" = header, then <path>.camera.json
    std::string previousCameraSidecar;        //!< frame N−1's camera file, when per frame
    std::function<const SceneFile&()> scene;  //!< loads the scene, geometry too, on first call
    /// The scene's RayScene around a camera position, shared by the sources of a session (null:
    /// each source builds its own from `scene`).
    std::function<std::shared_ptr<const RayScene>(const Vec3d& origin)> rayScene;
    std::function<const std::vector<Light>&()> lights;  //!< reads the scene's lights only
    std::function<const Environment&()> environment;    //!< the scene's sky light (no geometry)
    std::function<OCIO_NAMESPACE::ConstConfigRcPtr()> colorConfig;  //!< loads on first call
    bool strict = false;  //!< bad input pixels and assumed values are errors
    bool firstInSequence = true;
    /// Checks the scene against this capture before the first ray (null: not checked).
    std::shared_ptr<SceneAlignmentCheck> alignment;
};

/// What every capture source shares beyond its pixels: the scene's BVH (built on first use around
/// the frame's eye), its lights and sky, and the OCIO config, all from CaptureOptions.
class SceneBackedSource : public FrameSource {
public:
    const RayScene& scene() override;
    const std::vector<Light>& lights() override;
    const Environment& environment() override;
    OCIO_NAMESPACE::ConstConfigRcPtr colorConfig() override;

protected:
    explicit SceneBackedSource(CaptureOptions options) : mOptions(std::move(options)) {}
    /// Something the reader of this frame should know (CaptureSource: its notes).
    virtual void sceneNote(const std::string&) {}
    CaptureOptions mOptions;

private:
    std::shared_ptr<const RayScene> mRayScene;
};

class CaptureSource final : public SceneBackedSource {
public:
    using Options = CaptureOptions;
    CaptureSource(Options options, CaptureProfile profile);

    FrameInfo frameInfo() override;
    Texture loadBuffer(const std::string& buffer, int channels) override;
    InputSeconds inputSeconds() const override;

    CaptureFiles& files() { return mFiles; }
    const SanitizeCounts& sanitized() const { return mSanitized; }
    /// What was assumed or chosen while reading (camera values not given, profile guesses, the
    /// normal encoding, a missing frame N−1), each once.
    const std::vector<std::string>& notes() const { return mNotes; }
    /// Every channel decoded, frame N−1's too.
    std::vector<std::string> readLog() const;
    /// The files this frame read, each with its role: "capture", "previous frame capture",
    /// "cameraSidecar".
    std::vector<std::pair<std::string, std::string>> filesRead() const;

    /// Reads `reads` now, in order, for loadBuffer to hand out later (a sequence reads frame
    /// N+1 this way while frame N runs: CaptureReadAhead). Stops at the first buffer that fails
    /// to read, or when `cancelled` turns true: loadBuffer then reads the rest as usual, and a
    /// bad buffer's error comes from there, where the frame asks for it.
    void readAhead(const std::vector<CaptureRead>& reads, const std::atomic<bool>& cancelled);

private:
    void note(const std::string& text);
    void sceneNote(const std::string& text) override { note(text); }
    Image readPreviousFrame(const std::string& buffer, const BufferMapping& m, int channels);
    CaptureFiles mFiles;
    std::unique_ptr<CaptureFiles> mPrevious;
    std::vector<std::string> mNotes;
    std::string mCameraSidecar;  // the sidecar frameInfo() read, if any
    std::optional<FrameInfo> mInfo;
    SanitizeCounts mSanitized;
    std::map<std::string, std::pair<int, Texture>> mReadAhead;  // buffer → (channels, pixels)
    double fileSeconds() const;
    double mLoadSeconds = 0, mLoadFileSeconds = 0;  // in loadBuffer; of it, reading the files
};

/// The OCIO config to use: `explicitPath`, else $OCIO, else configs/ocio/config.ocio.
OCIO_NAMESPACE::ConstConfigRcPtr loadColorConfig(const std::string& explicitPath);
/// The path loadColorConfig(explicitPath) reads.
std::string colorConfigPath(const std::string& explicitPath);

}  // namespace fp::io
