#include "io/CaptureFiles.h"

#include "foundation/Error.h"
#include "framework/SemanticBuffers.h"

#include <cmath>
#include <filesystem>

namespace fp::io {

namespace {

constexpr std::string_view kCameraToken = "{camera}";

std::string replaceAll(std::string s, std::string_view from, const std::string& to) {
    for (auto pos = s.find(from); pos != std::string::npos; pos = s.find(from, pos + to.size()))
        s.replace(pos, from.size(), to);
    return s;
}

std::string filePath(const std::string& pattern, const std::string& base, const std::string& key) {
    return replaceAll(replaceAll(pattern, "{base}", base), "{file}", key);
}

// The camera a channel name belongs to where the profile's name holds {camera}: "" for the
// name without suffix, "Name" for "<prefix>_Name<suffix>", nothing when it does not match.
std::optional<std::string> cameraOf(const std::string& spec, const std::string& name) {
    const auto pos = spec.find(kCameraToken);
    const std::string prefix = spec.substr(0, pos), suffix = spec.substr(pos + kCameraToken.size());
    if (name.size() < prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix))
        return std::nullopt;
    const std::string mid = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    if (mid.empty()) return "";
    if (mid[0] != '_' || mid.size() == 1 || mid.find('.') != std::string::npos) return std::nullopt;
    return mid.substr(1);
}

bool isIdBuffer(const std::string& buffer) {
    return buffer == "InstanceId" || buffer == "ShadingModel";
}

// Mean distance from unit length over the non-zero pixels, read as signed or as packed.
double unitLengthError(const Image& img, bool packed) {
    double sum = 0;
    uint64_t n = 0;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            double len2 = 0, raw2 = 0;
            for (int c = 0; c < 3; ++c) {
                const double v = img.plane(c).at(x, y);
                raw2 += v * v;
                const double d = packed ? 2.0 * v - 1.0 : v;
                len2 += d * d;
            }
            if (raw2 == 0 || !std::isfinite(len2)) continue;  // background
            sum += std::fabs(std::sqrt(len2) - 1.0);
            ++n;
        }
    return n ? sum / n : 0.0;
}

}  // namespace

CaptureFiles::CaptureFiles(const std::string& path, const CaptureProfile& profile)
    : mProfile(profile), mCapturePath(path) {
    const std::string& pattern = mProfile.filePattern();
    if (pattern.empty()) {
        mReaders[""] = std::make_unique<ExrReader>(path);
        mPrimaryKey = "";
    } else {
        // The files a profile names, in the order its buffers list them.
        std::vector<std::string> keys;
        for (const auto& [buffer, list] : mProfile.buffers())
            for (const auto& m : list)
                if (!m.file.empty() && std::find(keys.begin(), keys.end(), m.file) == keys.end())
                    keys.push_back(m.file);
        // Given one of the files rather than the base: strip "_<key>.exr". A path that holds
        // {file} itself names every file ("shot{file}.0001.exr": one file per buffer with the
        // frame number after the buffer's name, as G-buffer datasets write them).
        mBase = path;
        const bool named = path.find("{file}") != std::string::npos;
        for (const auto& k : keys) {
            if (named) break;
            const std::string tail = filePath(pattern, "", k);
            if (path.size() > tail.size() && path.ends_with(tail)) {
                mBase = path.substr(0, path.size() - tail.size());
                break;
            }
        }
        mCapturePath = mBase;
        std::vector<std::string> tried;
        for (const auto& k : keys) {
            const std::string file = named ? replaceAll(mBase, "{file}", k) : filePath(pattern, mBase, k);
            tried.push_back(std::filesystem::path(file).filename().string());
            if (!std::filesystem::exists(file)) continue;
            mReaders[k] = std::make_unique<ExrReader>(file);
            if (mPrimaryKey.empty()) mPrimaryKey = k;
        }
        if (mReaders.empty())
            throw Error(fmt::format("{}: no file of this capture exists (profile {} looks for "
                                    "{})",
                                    mBase, mProfile.name(), fmt::join(tried, ", ")));
        for (const auto& [k, r] : mReaders)
            FP_CHECK(r->extent() == primary().extent(),
                     "{} is {}×{} but {} is {}×{}: the files of one capture have one size",
                     r->path(), r->extent().width, r->extent().height, primary().path(),
                     primary().extent().width, primary().extent().height);
    }
    chooseCamera();
}

void CaptureFiles::chooseCamera() {
    std::set<std::string> found;
    bool usesToken = false;
    for (const auto& [buffer, list] : mProfile.buffers())
        for (const auto& m : list)
            for (const auto& group : m.groups)
                for (const auto& spec : group) {
                    if (spec.find(kCameraToken) == std::string::npos) continue;
                    usesToken = true;
                    if (const ExrReader* r = reader(m.file))
                        for (const auto& c : r->channels())
                            if (auto cam = cameraOf(spec, c.name)) found.insert(*cam);
                }
    if (!usesToken) return;
    if (!mProfile.camera().empty()) {
        if (!found.count(mProfile.camera()))
            throw UsageError(fmt::format("{}: no layer of camera '{}' (cameras here: [{}])",
                                         mCapturePath, mProfile.camera(), fmt::join(found, ", ")));
        mCameraSuffix = "_" + mProfile.camera();
        return;
    }
    if (found.size() > 1)
        throw UsageError(fmt::format(
            "{}: layers of several cameras ([{}]); choose one with \"profile\": {{\"base\": "
            "\"{}\", \"camera\": \"NAME\"}} (\"\" = the layers without a camera suffix)",
            mCapturePath, fmt::join(found, ", "), mProfile.name()));
    if (found.size() == 1 && !found.begin()->empty()) mCameraSuffix = "_" + *found.begin();
}

void CaptureFiles::checkCoversCapture(const ExrReader& file, const ExrChannel& ch,
                                      const std::string& buffer) const {
    // Every buffer of a capture is read onto the same pixels: a part whose data window is not
    // exactly the capture's would leave pixels unwritten or drop some without a word.
    const auto want = primary().header(0).dataWindow();
    const auto have = file.header(ch.part).dataWindow();
    if (have == want) return;
    throw Error(fmt::format(
        "{}: buffer '{}' (channel '{}', part {}) covers pixels ({},{})–({},{}), {}×{}, but the "
        "capture covers ({},{})–({},{}), {}×{}: every buffer of a capture must cover the same "
        "pixels (re-export it at the capture's size, e.g. oiiotool --resize or --crop)",
        file.path(), buffer, ch.name, ch.part, have.min.x, have.min.y, have.max.x, have.max.y,
        have.max.x - have.min.x + 1, have.max.y - have.min.y + 1, want.min.x, want.min.y,
        want.max.x, want.max.y, want.max.x - want.min.x + 1, want.max.y - want.min.y + 1));
}

ExrReader* CaptureFiles::reader(const std::string& fileKey) const {
    auto it = mReaders.find(fileKey);
    return it == mReaders.end() ? nullptr : it->second.get();
}

double CaptureFiles::fileSeconds() const {
    double seconds = 0;
    for (const auto& [k, r] : mReaders) seconds += r->fileSeconds();
    return seconds;
}

std::vector<std::pair<std::string, const ExrReader*>> CaptureFiles::files() const {
    std::vector<std::pair<std::string, const ExrReader*>> out;
    for (const auto& [k, r] : mReaders) out.emplace_back(k, r.get());
    return out;
}

const ExrChannel* CaptureFiles::channel(const BufferMapping& m, const std::string& spec) const {
    const ExrReader* r = reader(m.file);
    return r ? r->findChannel(replaceAll(spec, kCameraToken, mCameraSuffix)) : nullptr;
}

bool CaptureFiles::hasChannels(const BufferMapping& m) const {
    for (const auto& group : m.groups)
        for (const auto& spec : group)
            if (!channel(m, spec)) return false;
    for (const auto& spec : m.overrideWhere)
        if (!channel(m, spec)) return false;
    return true;
}

const BufferMapping* CaptureFiles::mappingFor(const std::string& buffer) const {
    const auto* list = mProfile.mappings(buffer);
    if (!list) return nullptr;
    for (const auto& m : *list) {
        if (!m.constant.empty() && m.overrideWhere.empty()) return &m;
        if (!m.previousFrame.empty()) {
            if (mappingFor(m.previousFrame)) return &m;
            continue;
        }
        if (hasChannels(m)) return &m;
    }
    return nullptr;
}

std::map<std::string, int> CaptureFiles::truthChannels() const {
    std::map<std::string, std::set<std::string>> suffixes;
    for (const auto& c : primary().channels()) {
        if (!isTruthBuffer(c.name)) continue;
        const auto dot = c.name.rfind('.');
        suffixes[c.name.substr(0, dot)].insert(c.name.substr(dot + 1));
    }
    std::map<std::string, int> out;
    for (const auto& [layer, s] : suffixes) out[layer] = int(s.size());
    // A Truth layer the profile maps (a renderer's own pass) is as wide as its mapping, as
    // inspect shows it and compare reads it.
    for (const auto& [buffer, list] : mProfile.buffers())
        if (isTruthBuffer(buffer))
            if (const BufferMapping* m = mappingFor(buffer))
                out[buffer] = !m->groups.empty() ? int(m->groups.front().size())
                                                 : int(m->constant.size());
    return out;
}

std::vector<std::string> truthSuffixes(int channels) {
    if (channels == 1) return {"Y"};
    if (channels == 4) return {"R", "G", "B", "A"};
    return {"R", "G", "B"};
}

std::set<std::string> CaptureFiles::availableBuffers() const {
    std::set<std::string> out;
    for (const auto& [buffer, list] : mProfile.buffers())
        if (mappingFor(buffer)) out.insert(buffer);
    for (const auto& [layer, n] : truthChannels()) out.insert(layer);
    return out;
}

std::vector<std::string> CaptureFiles::describe(const std::string& buffer) const {
    const BufferMapping* m = mappingFor(buffer);
    if (!m) {
        std::vector<std::string> out;
        if (isTruthBuffer(buffer))
            for (const auto& s : truthSuffixes(truthChannels()[buffer]))
                out.push_back(buffer + "." + s);
        return out;
    }
    std::vector<std::string> out;
    if (!m->overrideWhere.empty())
        out.push_back(fmt::format("{} where {} > 0, else", fmt::join(m->overrideValue, ","),
                                  fmt::join(m->overrideWhere, "|")));
    if (!m->constant.empty()) {
        out.push_back(fmt::format("constant {}", fmt::join(m->constant, ",")));
        return out;
    }
    if (!m->previousFrame.empty()) return {"frame N-1 " + m->previousFrame};
    for (const auto& group : m->groups)
        for (const auto& spec : group)
            out.push_back((m->file.empty() ? "" : m->file + ":") +
                          replaceAll(spec, kCameraToken, mCameraSuffix));
    return out;
}

std::string CaptureFiles::bufferOfChannel(const std::string& fileKey,
                                          const std::string& channel) const {
    for (const auto& [buffer, list] : mProfile.buffers()) {
        const BufferMapping* m = mappingFor(buffer);
        if (!m || m->file != fileKey) continue;
        for (const auto& group : m->groups)
            for (const auto& spec : group)
                if (replaceAll(spec, kCameraToken, mCameraSuffix) == channel) return buffer;
    }
    if (fileKey.empty() && isTruthBuffer(channel)) return channel.substr(0, channel.rfind('.'));
    return "";
}

Image CaptureFiles::read(const std::string& buffer, int channels, std::vector<std::string>& notes) {
    const SemanticBuffer* sem = findSemanticBuffer(buffer);
    std::vector<std::string> names = sem ? sem->channels : truthSuffixes(channels);
    const Extent size = extent();
    const BufferMapping* m = mappingFor(buffer);
    if (!m && isTruthBuffer(buffer)) {
        std::vector<std::string> file;
        for (const auto& s : names) file.push_back(buffer + "." + s);
        for (const auto& c : file) {
            const ExrChannel* ch = primary().findChannel(c);
            FP_CHECK(ch, "{}: buffer '{}' needs channel '{}', which the file does not have",
                     primary().path(), buffer, c);
            checkCoversCapture(primary(), *ch, buffer);
        }
        return primary().read(file, names);
    }
    FP_CHECK(m, "{}: the capture has no '{}' (profile {})", mCapturePath, buffer, mProfile.name());
    FP_CHECK(m->previousFrame.empty(), "{}: '{}' comes from the previous frame", mCapturePath,
             buffer);
    if (!m->assumption.empty()) notes.push_back(fmt::format("{}: {}", buffer, m->assumption));

    Image img(size.width, size.height, names);
    if (!m->constant.empty()) {
        for (int c = 0; c < img.channelCount(); ++c)
            for (int y = 0; y < size.height; ++y)
                std::fill_n(img.plane(c).row(y), size.width, m->constant[std::size_t(c)]);
        applyOverride(*m, buffer, img);
        return img;
    }
    ExrReader& file = *reader(m->file);
    if (!m->warning.empty()) mWarnings.insert(buffer + ": " + m->warning);
    Image term;
    bool firstTerm = true;
    for (std::size_t g = 0; g < m->groups.size(); ++g) {
        std::vector<const ExrChannel*> found;
        for (const auto& spec : m->groups[g]) {
            const ExrChannel* ch = channel(*m, spec);
            FP_CHECK(ch, "{}: buffer '{}' needs channel '{}', which the file does not have",
                     file.path(), buffer, spec);
            // Integer channels hold ids; reading one as depth or colour is a profile mistake.
            if (ch->type == Imf::UINT && !isIdBuffer(buffer))
                throw UsageError(fmt::format("{}: channel '{}' is uint, but {} is not an id "
                                             "buffer ({})",
                                             file.path(), ch->name, buffer, m->pointer));
            if (ch->type == Imf::HALF && isDepthBuffer(buffer))
                notes.push_back(fmt::format(
                    "{} (depth) is half float: 11-bit steps (8 cm at 100 m) and sky at 65504; "
                    "prefer float depth", ch->name));
            checkCoversCapture(file, *ch, buffer);
            found.push_back(ch);
        }
        FP_CHECK(int(found.size()) == img.channelCount(),
                 "{}: buffer '{}' is {} channels wide but its mapping lists {} ({})", file.path(),
                 buffer, img.channelCount(), found.size(), m->pointer);
        const Image part = file.read(found, names);
        // Terms add; the groups of one term (a product) multiply into `term` first.
        const bool startsTerm = m->termOf.empty() || g == 0 || m->termOf[g] != m->termOf[g - 1];
        const bool endsTerm = m->termOf.empty() || g + 1 == m->groups.size() ||
                              m->termOf[g + 1] != m->termOf[g];
        if (startsTerm) term = endsTerm ? Image() : part;
        else
            for (int c = 0; c < img.channelCount(); ++c)
                for (int y = 0; y < size.height; ++y) {
                    float* dst = term.plane(c).row(y);
                    const float* src = part.plane(c).row(y);
                    for (int x = 0; x < size.width; ++x) dst[x] *= src[x];
                }
        if (!endsTerm) continue;
        const Image& add = startsTerm ? part : term;
        for (int c = 0; c < img.channelCount(); ++c)
            for (int y = 0; y < size.height; ++y) {
                float* dst = img.plane(c).row(y);
                const float* src = add.plane(c).row(y);
                for (int x = 0; x < size.width; ++x) dst[x] = firstTerm ? src[x] : dst[x] + src[x];
            }
        firstTerm = false;
    }
    if (std::isfinite(m->skyAbove))
        for (int y = 0; y < size.height; ++y) {
            float* row = img.plane(0).row(y);
            for (int x = 0; x < size.width; ++x)
                if (row[x] >= m->skyAbove) row[x] = std::numeric_limits<float>::infinity();
        }
    bool packed = m->normals == BufferMapping::Normals::Unorm;
    if (m->normals == BufferMapping::Normals::Auto) {
        packed = unitLengthError(img, true) < unitLengthError(img, false);
        notes.push_back(fmt::format("{}: normals read as {}", buffer,
                                    packed ? "packed (n·0.5+0.5)" : "signed (-1..1)"));
    }
    for (int c = 0; c < img.channelCount(); ++c) {
        const float s = (packed ? 2.0f : 1.0f) * (m->scale.empty() ? 1.0f : m->scale[c]);
        const float o = (packed ? -1.0f : 0.0f) * (m->scale.empty() ? 1.0f : m->scale[c]) +
                        (m->offset.empty() ? 0.0f : m->offset[c]);
        if (s == 1.0f && o == 0.0f) continue;
        for (int y = 0; y < size.height; ++y) {
            float* row = img.plane(c).row(y);
            for (int x = 0; x < size.width; ++x) row[x] = row[x] * s + o;
        }
    }
    applyOverride(*m, buffer, img);
    return img;
}

void CaptureFiles::applyOverride(const BufferMapping& m, const std::string& buffer, Image& img) {
    if (m.overrideWhere.empty()) return;
    std::vector<const ExrChannel*> found;
    for (const auto& spec : m.overrideWhere) {
        const ExrChannel* ch = channel(m, spec);
        FP_CHECK(ch, "{}: buffer '{}' needs channel '{}', which the file does not have",
                 mCapturePath, buffer, spec);
        found.push_back(ch);
    }
    const Image where = reader(m.file)->read(found, m.overrideWhere);
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            bool hit = false;
            for (int c = 0; c < where.channelCount(); ++c) hit = hit || where.plane(c).at(x, y) > 0.0f;
            if (hit)
                for (int c = 0; c < img.channelCount(); ++c)
                    img.plane(c).at(x, y) = m.overrideValue[std::size_t(c)];
        }
}

std::vector<std::string> CaptureFiles::readLog() const {
    std::vector<std::string> out;
    for (const auto& [k, r] : mReaders)
        for (const auto& c : r->readLog()) out.push_back(k.empty() ? c : k + ":" + c);
    return out;
}

}  // namespace fp::io
