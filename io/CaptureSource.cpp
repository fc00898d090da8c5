#include "io/CaptureSource.h"

#include "foundation/SceneAlignment.h"

#include "io/CameraIO.h"
#include "io/ConfigLoader.h"
#include "foundation/Error.h"
#include "framework/SemanticBuffers.h"

#include <fmt/ranges.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace fp::io {

namespace OCIO = OCIO_NAMESPACE;

std::string colorConfigPath(const std::string& explicitPath) {
    std::string path = explicitPath;
    if (path.empty())
        if (const char* env = std::getenv("OCIO"); env && *env)
            path = env;
    if (path.empty())
        path = configDirectory() + "/ocio/config.ocio";
    return path;
}

OCIO::ConstConfigRcPtr loadColorConfig(const std::string& explicitPath) {
    const std::string path = colorConfigPath(explicitPath);
    try {
        return OCIO::Config::CreateFromFile(path.c_str());
    } catch (const OCIO::Exception& e) {
        throw Error(fmt::format("{}: cannot load the OCIO config: {}", path, e.what()));
    }
}

SanitizeCounts sanitizeBuffer(const std::string& buffer, Image& img) {
    // No NaN ever reaches an output. Colour: non-finite or negative → 0. Depth: NaN, zero or
    // negative → sky (a view depth lies beyond the near plane, so never ≤ 0, and 1/depth would be
    // infinite). Normals: renormalised when off unit length by more than half precision; zero is
    // what sky pixels hold (the passes' normalize keeps it 0, never NaN), so a zero normal is bad
    // only on a surface — checked against the depth under --strict.
    const SemanticBuffer* sem = findSemanticBuffer(buffer);
    const bool isColor = sem ? sem->kind == PortKind::Color : true;
    const bool isDepth = isDepthBuffer(buffer);
    // Row bands on every core: a 1080p capture is some twenty such planes a frame.
    auto sanitizeRows = [&](const tbb::blocked_range<int>& rows, SanitizeCounts counts) {
        for (int c = 0; c < img.channelCount(); ++c)
            for (int y = rows.begin(); y < rows.end(); ++y) {
                float* row = img.plane(c).row(y);
                for (int x = 0; x < img.width(); ++x) {
                    float& v = row[x];
                    if (isDepth) {
                        if (std::isnan(v) || v <= 0.0f) {
                            ++counts.nonFinite;
                            v = std::numeric_limits<float>::infinity();
                        }
                    } else if (!std::isfinite(v)) {
                        ++counts.nonFinite;
                        v = 0.0f;
                    } else if (isColor && v < 0.0f) {
                        ++counts.negative;
                        v = 0.0f;
                    }
                }
            }
        if (buffer == "WorldNormal" && img.channelCount() == 3)
            for (int y = rows.begin(); y < rows.end(); ++y)
                for (int x = 0; x < img.width(); ++x) {
                    Vec3f n{img.plane(0).at(x, y), img.plane(1).at(x, y), img.plane(2).at(x, y)};
                    const float len = length(n);
                    if (len == 0.0f || std::fabs(len - 1.0f) < 1e-3f)
                        continue;
                    ++counts.nonUnitNormals;
                    for (int c = 0; c < 3; ++c)
                        img.plane(c).at(x, y) = n[c] / len;
                }
        return counts;
    };
    const SanitizeCounts counts = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, img.height(), 16), SanitizeCounts{}, sanitizeRows,
        [](SanitizeCounts a, const SanitizeCounts& b) { return a += b; });
    return counts;
}

CaptureSource::CaptureSource(Options options, CaptureProfile profile)
    : SceneBackedSource(std::move(options)), mFiles(mOptions.path, profile) {}

void CaptureSource::note(const std::string& text) {
    if (std::find(mNotes.begin(), mNotes.end(), text) != mNotes.end()) return;
    if (mOptions.strict)
        throw UsageError(fmt::format("{}: frame {}: {} (--strict: nothing is assumed)",
                                     mFiles.capturePath(), mOptions.frame, text));
    mNotes.push_back(text);
}

FrameInfo CaptureSource::frameInfo() {
    if (mInfo)
        return *mInfo;
    FrameInfo info;
    info.number = mOptions.frame;
    info.extent = mFiles.extent();
    info.firstInSequence = mOptions.firstInSequence;
    CameraLookup lookup;
    lookup.sidecar = mOptions.cameraSidecar;
    lookup.capturePath = mFiles.capturePath();
    lookup.header = &mFiles.primary().header();
    lookup.extent = info.extent;
    lookup.profileUnits = mFiles.profile().sceneUnitsPerMeter();
    if (auto found = findCamera(lookup)) {
        info.camera = found->camera;
        info.hasCamera = true;
        if (!found->sidecar.empty()) mCameraSidecar = found->sidecar;
        for (const auto& a : found->assumptions) note(a);
    }
    // A capture whose camera does not say where it was last frame: the previous frame's own
    // capture does (two renders of a shot, cur.exr and prev.exr, each with its camera).
    // A camera file per frame (Unreal's matrices as text) holds no previous camera either:
    // frame N−1's file is it.
    if (info.hasCamera && !info.camera.previous) {
        CameraLookup prevLookup;
        prevLookup.extent = info.extent;
        prevLookup.profileUnits = mFiles.profile().sceneUnitsPerMeter();
        std::optional<CaptureFiles> previous;
        if (!mOptions.previousCameraSidecar.empty() &&
            std::filesystem::exists(mOptions.previousCameraSidecar)) {
            prevLookup.sidecar = mOptions.previousCameraSidecar;
        } else if (!mOptions.previousPath.empty() && mFiles.profile().filePattern().empty() &&
                   std::filesystem::exists(mOptions.previousPath)) {
            previous.emplace(mOptions.previousPath, mFiles.profile());
            prevLookup.capturePath = previous->capturePath();
            prevLookup.header = &previous->primary().header();
        }
        if (!prevLookup.sidecar.empty() || prevLookup.header)
            if (auto prev = findCamera(prevLookup)) info.camera.previous = prev->camera.current;
    }
    mInfo = info;
    return info;
}

std::vector<std::pair<std::string, std::string>> CaptureSource::filesRead() const {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& [key, reader] : mFiles.files()) out.emplace_back("capture", reader->path());
    if (mPrevious)
        for (const auto& [key, reader] : mPrevious->files())
            out.emplace_back("previous frame capture", reader->path());
    if (!mCameraSidecar.empty()) out.emplace_back("cameraSidecar", mCameraSidecar);
    return out;
}

std::vector<std::string> CaptureSource::readLog() const {
    std::vector<std::string> log = mFiles.readLog();
    if (mPrevious)
        for (const auto& c : mPrevious->readLog()) log.push_back("frame N-1 " + c);
    return log;
}

Image CaptureSource::readPreviousFrame(const std::string& buffer, const BufferMapping& m,
                                       int channels) {
    const std::string& prev = mOptions.previousPath;
    bool exists = false;
    if (!prev.empty()) {
        if (!mPrevious) {
            try {
                mPrevious = std::make_unique<CaptureFiles>(prev, mFiles.profile());
            } catch (const Error&) {
                if (std::filesystem::exists(prev)) throw;  // there, but unreadable
            }
        }
        exists = mPrevious != nullptr;
    }
    if (!exists) {
        // No frame N−1 on disk: the first frame of a sequence has no history, as after a
        // camera cut — black colour, sky depth.
        // Said plainly: the screen-space passes that read last frame's colour (SSGI, SSR) find
        // nothing to gather on this frame.
        note(fmt::format(
            "frame {}: no previous frame{} for {}: no history, as after a camera cut, so the "
            "passes that gather last frame's colour (SSGI, SSR) find no light on this frame{}",
            mOptions.frame, prev.empty() ? "" : " (" + prev + ")", buffer,
            prev.empty() ? "; give the previous frame's capture with --previous FILE (or "
                           "\"previous\" in the config), or run a numbered sequence"
                         : ""));
        const bool isDepth = isDepthBuffer(buffer);
        const SemanticBuffer* sem = findSemanticBuffer(buffer);
        return Image(mFiles.extent().width, mFiles.extent().height, sem->channels,
                     isDepth ? std::numeric_limits<float>::infinity() : 0.0f);
    }
    FP_CHECK(mPrevious->extent() == mFiles.extent(),
             "{}: frame N−1 ({}) is {}×{}, this frame is {}×{}", mFiles.capturePath(), prev,
             mPrevious->extent().width, mPrevious->extent().height, mFiles.extent().width,
             mFiles.extent().height);
    std::vector<std::string> notes;
    Image img = mPrevious->read(m.previousFrame, channels, notes);
    for (const auto& n : notes) note(n);
    // Named as the buffer asked for (PrevSceneColor's R G B are SceneColor's R G B).
    return img;
}

void CaptureSource::readAhead(const std::vector<CaptureRead>& reads,
                              const std::atomic<bool>& cancelled) {
    for (const CaptureRead& r : reads) {
        if (cancelled) return;
        try {
            Texture t = loadBuffer(r.buffer, r.channels);
            mReadAhead.insert_or_assign(r.buffer, std::make_pair(r.channels, std::move(t)));
        } catch (const std::exception&) {
            return;  // read again, and reported, when the frame asks for it
        }
    }
}

double CaptureSource::fileSeconds() const {
    return mFiles.fileSeconds() + (mPrevious ? mPrevious->fileSeconds() : 0.0);
}

FrameSource::InputSeconds CaptureSource::inputSeconds() const {
    return {fileSeconds(), std::max(0.0, mLoadSeconds - mLoadFileSeconds)};
}

Texture CaptureSource::loadBuffer(const std::string& buffer, int channels) {
    if (auto it = mReadAhead.find(buffer); it != mReadAhead.end() && it->second.first == channels) {
        Texture t = std::move(it->second.second);
        mReadAhead.erase(it);
        return t;
    }
    // The time decoding took is the load's less the files' reading within it.
    const auto start = std::chrono::steady_clock::now();
    const double filesBefore = fileSeconds();
    struct Timed {
        CaptureSource& source;
        std::chrono::steady_clock::time_point start;
        double filesBefore;
        ~Timed() {
            source.mLoadSeconds +=
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            source.mLoadFileSeconds += source.fileSeconds() - filesBefore;
        }
    } timed{*this, start, filesBefore};
    const BufferMapping* m = mFiles.mappingFor(buffer);
    Image img;
    if (m && !m->previousFrame.empty()) {
        img = readPreviousFrame(buffer, *m, channels);
    } else {
        std::vector<std::string> notes;
        img = mFiles.read(buffer, channels, notes);
        for (const auto& n : notes) note(n);
    }
    FP_CHECK(img.width() == mFiles.extent().width && img.height() == mFiles.extent().height,
             "{}: frame {}: buffer '{}' is {}×{}, the capture is {}×{}", mFiles.capturePath(),
             mOptions.frame, buffer, img.width(), img.height(), mFiles.extent().width,
             mFiles.extent().height);

    SanitizeCounts counts = sanitizeBuffer(buffer, img);
    // A normal buffer that is zero everywhere is a mapping to the wrong channels or a pass the
    // renderer did not write; with surfaces in the depth it would shade every pixel as sky.
    if (buffer == "WorldNormal" && mFiles.mappingFor("SceneDepth")) {
        bool allZero = true;
        for (int c = 0; c < 3 && allZero; ++c)
            for (int y = 0; y < img.height() && allZero; ++y) {
                const float* row = img.plane(c).row(y);
                allZero = std::all_of(row, row + img.width(), [](float v) { return v == 0.0f; });
            }
        if (allZero) {
            std::vector<std::string> notes;
            const Image depth = mFiles.read("SceneDepth", 1, notes);
            uint64_t surfaces = 0;
            for (int y = 0; y < depth.height(); ++y)
                for (int x = 0; x < depth.width(); ++x) {
                    const float d = depth.plane(0).at(x, y);
                    surfaces += d > 0.0f && std::isfinite(d);
                }
            if (surfaces > 0)
                throw Error(fmt::format(
                    "{}: frame {}: buffer 'WorldNormal' ({}) is zero at every pixel, but "
                    "SceneDepth has {} surface pixels: the normals were not written, or the "
                    "profile maps the wrong channels",
                    mFiles.capturePath(), mOptions.frame, fmt::join(mFiles.describe(buffer), " "),
                    surfaces));
        }
    }
    if (buffer == "WorldNormal" && mOptions.strict && mFiles.mappingFor("SceneDepth")) {
        std::vector<std::string> notes;
        const Image depth = mFiles.read("SceneDepth", 1, notes);
        if (depth.width() == img.width() && depth.height() == img.height())
            for (int y = 0; y < img.height(); ++y)
                for (int x = 0; x < img.width(); ++x) {
                    const float d = depth.plane(0).at(x, y);
                    if (d > 0.0f && std::isfinite(d) && img.plane(0).at(x, y) == 0.0f &&
                        img.plane(1).at(x, y) == 0.0f && img.plane(2).at(x, y) == 0.0f)
                        ++counts.nonUnitNormals;  // a surface with no normal
                }
    }
    if (counts.total() > 0 && mOptions.strict)
        throw Error(
            fmt::format("{}: frame {}: buffer '{}' has {} non-finite (or, for depth, ≤ 0), {} "
                        "negative and {} non-unit values (--strict)",
                        mFiles.capturePath(), mOptions.frame, buffer, counts.nonFinite,
                        counts.negative, counts.nonUnitNormals));
    mSanitized += counts;
    return Texture(std::move(img));
}

const RayScene& SceneBackedSource::scene() {
    if (!mRayScene) {
        FP_CHECK(mOptions.scene, "a pass needs scene geometry but the config names no 'scene'");
        const Vec3d origin = frameInfo().camera.current.position;
        mRayScene = mOptions.rayScene
                        ? mOptions.rayScene(origin)
                        : std::make_shared<const RayScene>(mOptions.scene().scene, origin);
        if (mOptions.alignment) {
            SceneAlignmentCheck& check = *mOptions.alignment;
            std::call_once(check.once, [&] {
                const FrameInfo info = frameInfo();
                if (!info.hasCamera) return;  // the pass that needs one says so
                const Image depth = loadBuffer("SceneDepth", 1).image();
                const SceneAlignment a = measureSceneAlignment(
                    *mRayScene, info.camera.current, depth,
                    alignmentStep(depth.width(), depth.height()));
                if (a.agreeingFraction() >= 0.9) return;
                // Is it units? The unit factors, each at a quarter of the rays.
                const SceneAlignment units = bestUnitScale(
                    *mRayScene, info.camera.current, depth,
                    alignmentStep(depth.width(), depth.height(), 1024));
                const SceneFile& sf = mOptions.scene();
                const std::string why = describeMisalignment(
                    a, units,
                    (sf.unitsDeclared ? sf.unitsAsWritten : info.camera.sceneUnitsPerMeter) /
                        units.scale);
                // Half the pixels is far beyond edges and thin geometry: a wrong scene.
                if (a.agreeingFraction() < 0.5)
                    check.error = fmt::format("{} ({})", why, sf.path);
                else
                    check.warning = fmt::format("{} ({}): the ray-traced passes see a scene that "
                                                "differs from the capture there",
                                                why, sf.path);
            });
            if (!check.error.empty()) throw UsageError(check.error);
            if (!check.warning.empty()) sceneNote(check.warning);
        }
    }
    return *mRayScene;
}

const std::vector<Light>& SceneBackedSource::lights() {
    FP_CHECK(mOptions.lights, "a pass needs the scene's lights but the config names no 'scene'");
    return mOptions.lights();
}

const Environment& SceneBackedSource::environment() {
    static const Environment none;  // no scene: no sky light, nothing to reflect but SSR
    return mOptions.environment ? mOptions.environment() : none;
}

OCIO::ConstConfigRcPtr SceneBackedSource::colorConfig() {
    FP_CHECK(mOptions.colorConfig, "a pass needs an OCIO config but none was provided");
    return mOptions.colorConfig();
}

}  // namespace fp::io
