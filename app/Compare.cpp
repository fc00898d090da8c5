// compare: error of one image against a reference (docs/design.md, Truth and evaluation), as numbers, JSON and a
// heat map.
#include "app/Compare.h"

#include "app/Invocation.h"
#include "app/MemoryLimit.h"
#include "app/TruthDefinitions.h"
#include "foundation/Suggest.h"

#include "io/CaptureFiles.h"
#include "io/CaptureSource.h"
#include "io/ContactSheet.h"
#include "io/ExrLayers.h"
#include "io/ExrWriter.h"
#include "io/PngWriter.h"
#include "io/SafeFiles.h"
#include "foundation/Error.h"
#include "framework/SemanticBuffers.h"
#include "color/DisplayTransform.h"
#include "metrics/ErrorMetrics.h"
#include "metrics/Heatmap.h"

#include <OpenImageIO/imageio.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <set>

namespace fp::app {

namespace {

std::string displayName(const std::string& layer) { return layer.empty() ? "\"\"" : layer; }

// The one layer both files have (ignoring depth and standard errors), for when no --layer is
// given.
std::string commonLayer(const io::ExrReader& a, const io::ExrReader& b) {
    std::set<std::string> inB;
    for (const auto& l : io::listLayers(b)) inB.insert(l.name);
    std::vector<std::string> common, namesA;
    for (const auto& l : io::listLayers(a)) {
        namesA.push_back(displayName(l.name));
        const bool stdErr = l.name.size() > 7 && l.name.compare(l.name.size() - 7, 7, ".StdErr") == 0;
        const bool meta = l.name == "SceneDepth" || stdErr;
        if (inB.count(l.name) && !meta) common.push_back(l.name);
    }
    if (common.size() == 1) return common[0];
    throw UsageError(fmt::format("{} and {} share {} comparable layers; pick one with --layer "
                                 "(and --ref-layer if the reference names it differently). "
                                 "Layers of {}: {}",
                                 a.path(), b.path(), common.size(), a.path(), fmt::join(namesA, ", ")));
}

// A buffer a profile maps, read through it. A semantic buffer has its width; any other layer the
// profile maps (a Truth.* layer from a renderer's own pass) is as wide as its mapping.
Image readMapped(io::CaptureFiles& files, const io::BufferMapping& m, const std::string& layer) {
    const SemanticBuffer* sem = findSemanticBuffer(layer);
    const int channels = sem                 ? int(sem->channels.size())
                         : !m.groups.empty() ? int(m.groups.front().size())
                                             : int(m.constant.size());
    std::vector<std::string> notes;
    return files.read(layer, channels, notes);
}

// `layer` of the file: through the profile when it maps a buffer of that name (so a Blender
// capture's SceneDepth is in scene units, with its sky), else the file's own layer.
Image readImage(io::ExrReader& file, const std::string& layer,
                const io::CaptureProfile& profile) {
    if (profile.mappings(layer)) {
        io::CaptureFiles files(file.path(), profile);
        if (const io::BufferMapping* m = files.mappingFor(layer))
            return readMapped(files, *m, layer);
    }
    return io::readLayer(file, io::findLayer(file, layer));
}

bool isExr(const std::string& path) {
    return asciiLowercase(std::filesystem::path(path).extension().string()) == ".exr";
}

// A picture that is not OpenEXR (PNG, JPEG, TIFF, …), whole, through OpenImageIO: 8-bit data
// becomes 0..1 (no colour conversion), channels named as the file names them (R G B A).
Image readPicture(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in)
        throw UsageError(fmt::format("{}: cannot read it as a picture: {}", path,
                                     OIIO::geterror()));
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<std::string> names;
    for (int c = 0; c < spec.nchannels; ++c)
        names.push_back(c < int(spec.channelnames.size()) ? spec.channelnames[std::size_t(c)]
                                                           : fmt::format("C{}", c));
    std::vector<float> pixels(std::size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
        throw Error(fmt::format("{}: could not read its pixels: {}", path, in->geterror()));
    Image img(spec.width, spec.height, names);
    for (int y = 0; y < spec.height; ++y)
        for (int x = 0; x < spec.width; ++x)
            for (int c = 0; c < spec.nchannels; ++c)
                img.plane(c).at(x, y) =
                    pixels[(std::size_t(y) * spec.width + x) * spec.nchannels + std::size_t(c)];
    return img;
}

// One file compared: an EXR read layer by layer (through a profile), or a picture read whole.
struct ComparedFile {
    std::string path;
    std::optional<io::ExrReader> exr;
    std::optional<Image> picture;
    explicit ComparedFile(const std::string& p) : path(p) {
        if (p.find("{file}") != std::string::npos) return;  // one file per buffer: via a profile
        if (isExr(p)) exr.emplace(p);
        else picture = readPicture(p);
    }
};

Image oneChannel(const Image& img, int c, const std::string& name) {
    Image out(img.width(), img.height(), {name});
    for (int y = 0; y < img.height(); ++y)
        std::copy_n(img.plane(c).row(y), img.width(), out.plane(0).row(y));
    return out;
}

// What users compare, spelled as oiiotool and Nuke users would: a layer ("Truth.AO",
// "ViewLayer.DiffInd"), one channel of it ("ViewLayer.AO.R", or "R" of a picture), or a product
// of such ("ViewLayer.GlossInd*ViewLayer.GlossCol": Blender splits light into light × colour).
Image readSpec(ComparedFile& file, const std::string& spec, const io::CaptureProfile& profile) {
    if (const auto star = spec.find('*'); star != std::string::npos) {
        Image product = readSpec(file, spec.substr(0, star), profile);
        const Image factor = readSpec(file, spec.substr(star + 1), profile);
        FP_CHECK(factor.width() == product.width() && factor.height() == product.height(),
                 "{}: the factors of '{}' differ in size", file.path, spec);
        const bool broadcast = factor.channelCount() == 1;
        if (!broadcast && factor.channelCount() != product.channelCount())
            throw UsageError(fmt::format("{}: '{}' multiplies {} channels by {}", file.path, spec,
                                         product.channelCount(), factor.channelCount()));
        for (int c = 0; c < product.channelCount(); ++c)
            for (int y = 0; y < product.height(); ++y) {
                float* p = product.plane(c).row(y);
                const float* f = factor.plane(broadcast ? 0 : c).row(y);
                for (int x = 0; x < product.width(); ++x) p[x] *= f[x];
            }
        return product;
    }
    if (file.picture) {
        if (spec.empty()) return *file.picture;
        for (int c = 0; c < file.picture->channelCount(); ++c)
            if (file.picture->channels()[std::size_t(c)] == spec)
                return oneChannel(*file.picture, c, spec);
        throw UsageError(fmt::format("{}: a picture has channels, not layers; '{}' is none of "
                                     "them",
                                     file.path, spec));
    }
    if (!file.exr) {
        io::CaptureFiles files(file.path, profile);
        const io::BufferMapping* m = files.mappingFor(spec);
        if (!m)
            throw UsageError(fmt::format("{}: profile {} maps no buffer '{}'", file.path,
                                         profile.name(), spec));
        return readMapped(files, *m, spec);
    }
    io::ExrReader& exr = *file.exr;
    const auto layers = io::listLayers(exr);
    const bool isLayer = std::any_of(layers.begin(), layers.end(),
                                     [&](const io::ExrLayerInfo& l) { return l.name == spec; });
    // LAYER.CHANNEL: one channel of a layer.
    if (const auto dot = spec.rfind('.'); !isLayer && !profile.mappings(spec) &&
                                          dot != std::string::npos) {
        const std::string layer = spec.substr(0, dot), channel = spec.substr(dot + 1);
        for (const auto& l : layers)
            if (l.name == layer)
                for (std::size_t c = 0; c < l.suffixes.size(); ++c)
                    if (l.suffixes[c] == channel)
                        return oneChannel(io::readLayer(exr, l), int(c), channel);
    }
    return readImage(exr, spec, profile);
}

constexpr const char* kReflectedEmitterLayer = "Truth.ReflectedEmitter";

// --mask: which pixels count. "sky" leaves out the sky (where the profile finds SceneDepth);
// "shading-model=N" and "id=N" keep one shading model or one object (ShadingModel, InstanceId
// through the profile); "reflected-emitter[=F]" leaves out the pixels whose reflection lobe
// sees an emitter (Truth.ReflectedEmitter above F, 0 by default); any other word is a picture
// whose first channel > 0 marks the kept pixels. Several masks multiply.
struct MaskSources {
    const std::string& a;
    const std::string& b;
    const io::CaptureProfile& profileA;
    const io::CaptureProfile& profileB;
};

std::optional<Image> readBuffer(const std::string& path, const io::CaptureProfile& profile,
                                const std::string& buffer) {
    if (!isExr(path) && path.find("{file}") == std::string::npos) return std::nullopt;
    std::optional<io::CaptureFiles> files;
    try {
        files.emplace(path, profile);
    } catch (const Error&) {
        return std::nullopt;
    }
    if (!files->mappingFor(buffer)) return std::nullopt;
    std::vector<std::string> notes;
    return files->read(buffer, 1, notes);
}

// 1 where `keep` holds for the first channel of `source`, else 0; `left` counts the zeros.
template <typename Keep>
Image maskWhere(const Image& source, Keep keep, int64_t* left = nullptr) {
    Image m(source.width(), source.height(), {"Y"});
    int64_t dropped = 0;
    for (int y = 0; y < m.height(); ++y)
        for (int x = 0; x < m.width(); ++x) {
            const bool kept = keep(source.plane(0).at(x, y));
            m.plane(0).at(x, y) = kept ? 1.0f : 0.0f;
            dropped += !kept;
        }
    if (left) *left = dropped;
    return m;
}

Image maskOf(const std::string& spec, const MaskSources& src, float skyDistance, Extent size,
             std::string& note) {
    auto keepEqual = [&](const std::string& buffer, const std::string& value) {
        int wanted = 0;
        try {
            std::size_t used = 0;
            wanted = std::stoi(value, &used);
            if (used != value.size()) throw std::invalid_argument(value);
        } catch (const std::exception&) {
            throw UsageError(fmt::format("--mask {}: expected a whole number after '='", spec));
        }
        std::optional<Image> ids = readBuffer(src.b, src.profileB, buffer);
        if (!ids) ids = readBuffer(src.a, src.profileA, buffer);
        if (!ids)
            throw UsageError(fmt::format("--mask {}: neither file has {} (profiles {}, {})", spec,
                                         buffer, src.profileA.name(), src.profileB.name()));
        Image m = maskWhere(*ids, [&](float v) { return std::lround(v) == wanted; });
        note = fmt::format("only {} {}", buffer, wanted);
        return m;
    };
    if (spec.rfind("shading-model=", 0) == 0) return keepEqual("ShadingModel", spec.substr(14));
    if (spec.rfind("id=", 0) == 0) return keepEqual("InstanceId", spec.substr(3));
    if (spec == "sky") {
        std::optional<Image> depth = readBuffer(src.b, src.profileB, "SceneDepth");
        if (!depth) depth = readBuffer(src.a, src.profileA, "SceneDepth");
        if (!depth) {
            note = fmt::format("no SceneDepth in either file (profile {}): nothing masked",
                               src.profileB.name());
            logWarning(note);
            Image all(size.width, size.height, {"Y"});
            for (int y = 0; y < size.height; ++y) std::fill_n(all.plane(0).row(y), size.width, 1.0f);
            return all;
        }
        note = "sky masked by SceneDepth";
        return notSkyMask(*depth, skyDistance);
    }
    if (spec == "reflected-emitter" || spec.rfind("reflected-emitter=", 0) == 0) {
        float above = 0.0f;
        if (spec.size() > 18) {
            const std::string value = spec.substr(18);
            char* end = nullptr;
            above = std::strtof(value.c_str(), &end);
            if (value.empty() || *end != '\0' || !(above >= 0.0f && above < 1.0f))
                throw UsageError(fmt::format(
                    "--mask {}: expected a fraction in [0, 1) after '=' (the share of the "
                    "reflection lobe that may see an emitter)",
                    spec));
        }
        std::optional<Image> seen;
        for (const std::string* path : {&src.b, &src.a}) {
            if (!isExr(*path)) continue;
            ComparedFile file(*path);
            const auto layers = io::listLayers(*file.exr);
            if (std::any_of(layers.begin(), layers.end(), [](const io::ExrLayerInfo& l) {
                    return l.name == kReflectedEmitterLayer;
                })) {
                seen = readSpec(file, kReflectedEmitterLayer, io::CaptureProfile::load("canonical"));
                break;
            }
        }
        if (!seen)
            throw UsageError(fmt::format(
                "--mask {}: neither file has a {} layer; `framepass capture --truth` writes it",
                spec, kReflectedEmitterLayer));
        int64_t left = 0;
        Image m = maskWhere(*seen, [&](float v) { return v <= above; }, &left);
        note = fmt::format("{} pixels whose reflection sees an emitter left out ({} > {})", left,
                           kReflectedEmitterLayer, above);
        return m;
    }
    ComparedFile file(spec);
    const Image picture = readSpec(file, "", io::CaptureProfile::load("canonical"));
    note = "mask " + spec;
    return maskWhere(picture, [](float v) { return v > 0.0f; });
}

void checkSameShape(const Image& a, const Image& b, const std::string& nameA,
                    const std::string& nameB) {
    if (a.channelCount() != b.channelCount())
        throw UsageError(fmt::format("{} has {} channels but {} has {}", nameA, a.channelCount(),
                                     nameB, b.channelCount()));
    if (a.width() != b.width() || a.height() != b.height())
        throw UsageError(fmt::format("{} is {}×{} but {} is {}×{}", nameA, a.width(), a.height(),
                                     nameB, b.width(), b.height()));
}

std::string pngPathFor(const std::string& exr) {
    std::filesystem::path p(exr);
    return p.replace_extension(".png").string();
}

}  // namespace

std::string heatmapPngPath(const std::string& exr) { return pngPathFor(exr); }

std::optional<FlipResult> compareFlip(const Image& a, const Image& b, const Image* mask,
                                      const std::string& mode, bool displayReferred,
                                      double pixelsPerDegree, Image* map) {
    if (mode != "auto" && mode != "hdr" && mode != "ldr" && mode != "off")
        throw UsageError(fmt::format("FLIP is auto, hdr, ldr or off, not '{}'", mode));
    if (!(std::isfinite(pixelsPerDegree) && pixelsPerDegree > 0))
        throw UsageError(fmt::format("the pixels per degree of FLIP's observer are a positive "
                                     "number, not {}",
                                     pixelsPerDegree));
    const int c = b.channelCount();
    if (mode == "off" || (c != 1 && c != 3 && c != 4)) return std::nullopt;
    FlipOptions o;
    o.pixelsPerDegree = pixelsPerDegree;
    o.hdr = mode == "hdr" || (mode == "auto" && !displayReferred);
    return flip(b, a, mask, o, map);
}

void addFlipFigures(nlohmann::json& figures, const std::optional<FlipResult>& flip,
                    double pixelsPerDegree) {
    if (!flip) {
        figures["flip"] = nullptr;
        return;
    }
    figures["flip"] = flip->mean;
    nlohmann::json how = {{"mode", flip->hdr ? "hdr" : "ldr"}, {"pixelsPerDegree", pixelsPerDegree}};
    if (flip->hdr)
        how.update({{"exposures", flip->exposures},
                    {"startExposure", flip->startExposure},
                    {"stopExposure", flip->stopExposure}});
    if (flip->nonFinitePixels) how["nonFinitePixels"] = flip->nonFinitePixels;
    figures["flipSettings"] = how;
}

nlohmann::json CompareResult::toJson(const CompareOptions& opt) const {
    nlohmann::json j = stats.toJson();
    addFlipFigures(j, flip, opt.pixelsPerDegree);
    j["a"] = {{"file", opt.a}, {"layer", layerA}};
    j["b"] = {{"file", opt.b}, {"layer", layerB}};
    j["mask"] = maskNote;
    if (!warnings.empty()) j["warnings"] = warnings;
    if (!opt.heatmap.empty())
        j["heatmap"] = {{"exr", opt.heatmap}, {"png", pngPathFor(opt.heatmap)}, {"scale", heatScale}};
    return j;
}

ErrorStats compareImages(const Image& a, const Image& b, const Image* mask,
                         const Image* referenceStdErr, double tolerance, const std::string& nameA,
                         const std::string& nameB, Image* absError) {
    // NaN passes every comparison with it, so a NaN tolerance would put no pixel over it.
    if (!(std::isfinite(tolerance) && tolerance >= 0.0))
        throw UsageError(fmt::format("the tolerance must be a finite number ≥ 0, not {}", tolerance));
    checkSameShape(a, b, nameA, nameB);
    if (mask && (mask->width() != a.width() || mask->height() != a.height()))
        throw UsageError(fmt::format("the mask is {}×{}, the images are {}×{}", mask->width(),
                                     mask->height(), a.width(), a.height()));
    if (referenceStdErr && (referenceStdErr->width() != b.width() ||
                            referenceStdErr->height() != b.height() ||
                            referenceStdErr->channelCount() != b.channelCount()))
        throw UsageError(fmt::format("the standard error of {} is not shaped as it", nameB));
    ErrorInputs in;
    in.result = &a;
    in.reference = &b;
    in.referenceStdErr = referenceStdErr;
    in.mask = mask;
    in.tolerance = tolerance;
    return measureError(in, absError);
}

// What compareFiles will hold at once, known from A's header before a pixel is read: A and B
// (and B's .StdErr) at A's channels, one plane a mask and |A − B|, the heat map's colour, on top
// of the process. A picture is already read: it counts as it is.
uint64_t compareForecast(const CompareOptions& opt, ComparedFile& a, const std::string& layerA) {
    Extent e{};
    int channels = 3;
    if (a.exr) {
        e = a.exr->extent();
        for (const auto& l : io::listLayers(*a.exr))
            if (l.name == layerA) channels = int(l.channels.size());
    } else if (a.picture) {
        e = {a.picture->width(), a.picture->height()};
        channels = a.picture->channelCount();
    }
    const int masks = int(std::count_if(opt.masks.begin(), opt.masks.end(),
                                        [](const std::string& m) { return m != "none"; }));
    const int planes = 3 * channels + masks + 1 + (opt.heatmap.empty() ? 0 : 3);
    return residentBytes() + imageBytes(e, planes);
}

CompareResult compareFiles(const CompareOptions& opt) {
    if (!opt.heatmap.empty())
        for (const auto& out : {opt.heatmap, pngPathFor(opt.heatmap)}) {
            io::refuseToOverwriteInputs(out, {opt.a, opt.b}, "--heatmap");
            io::checkWritable(out, "--heatmap");
        }
    CompareResult result;
    ComparedFile a(opt.a), b(opt.b);
    // No --layer: the layer both files have, or with --ref-layer the only layer of A.
    auto onlyLayer = [](io::ExrReader& exr) {
        const auto layers = io::listLayers(exr);
        return layers.size() == 1 ? layers[0].name : std::string();
    };
    const std::string layerA = result.layerA =
        !opt.layer.empty() || !a.exr ? opt.layer
        : opt.refLayer.empty()       ? (b.exr ? commonLayer(*a.exr, *b.exr) : opt.layer)
                                     : onlyLayer(*a.exr);
    const std::string layerB = result.layerB = opt.refLayer.empty() ? layerA : opt.refLayer;
    checkMemory(compareForecast(opt, a, layerA), "both images, the reference's noise, the masks, "
                "|A − B| and the heat map, and what this process holds already",
                opt.maxMemory, 0);
    const io::CaptureProfile profileA = io::CaptureProfile::load(opt.profile);
    const io::CaptureProfile profileB =
        opt.refProfile.empty() ? profileA : io::CaptureProfile::load(opt.refProfile);
    const Image imgA = readSpec(a, layerA, profileA);
    const Image imgB = readSpec(b, layerB, profileB);
    const std::string nameA = fmt::format("{}[{}]", opt.a, displayName(layerA));
    const std::string nameB = fmt::format("{}[{}]", opt.b, displayName(layerB));
    checkSameShape(imgA, imgB, nameA, nameB);
    // Two truths of different definitions (AO radius, bounces) as their headers record them.
    if (a.exr && b.exr)
        for (auto& w : truthDefinitionMismatch(nameA, layerA, readTruthDefinitions(a.exr->header()),
                                               nameB, layerB, readTruthDefinitions(b.exr->header()))) {
            logWarning(w);
            result.warnings.push_back(std::move(w));
        }
    std::optional<Image> stdErr;
    if (b.exr)
        for (const auto& l : io::listLayers(*b.exr))
            if (l.name == layerB + ".StdErr" && int(l.channels.size()) == imgB.channelCount())
                stdErr = io::readLayer(*b.exr, l);

    std::optional<Image> mask;
    std::vector<std::string> maskNotes;
    const MaskSources sources{opt.a, opt.b, profileA, profileB};
    for (const auto& m : opt.masks) {
        if (m == "none") continue;
        std::string note;
        Image one = maskOf(m, sources, float(opt.skyDistance),
                           {imgA.width(), imgA.height()}, note);
        if (one.width() != imgA.width() || one.height() != imgA.height())
            throw UsageError(fmt::format("--mask {}: is {}×{}, the images are {}×{}", m,
                                         one.width(), one.height(), imgA.width(),
                                         imgA.height()));
        if (mask)
            for (int y = 0; y < one.height(); ++y)
                for (int x = 0; x < one.width(); ++x)
                    mask->plane(0).at(x, y) *= one.plane(0).at(x, y);
        else
            mask = std::move(one);
        maskNotes.push_back(note);
    }
    result.maskNote = maskNotes.empty() ? "no mask" : fmt::format("{}", fmt::join(maskNotes, "; "));
    Image absError(imgA.width(), imgA.height(), {"Y"});
    const Image* kept = mask ? &*mask : nullptr;
    result.stats = compareImages(imgA, imgB, kept, stdErr ? &*stdErr : nullptr, opt.tolerance,
                                 nameA, nameB, &absError);
    Image flipMap;
    result.flip = compareFlip(imgA, imgB, kept, opt.flip, a.picture.has_value(),
                              opt.pixelsPerDegree, &flipMap);

    float& scale = result.heatScale;
    if (!opt.heatmap.empty()) {
        scale = opt.heatMax > 0 ? float(opt.heatMax) : heatScale(absError, kept);
        const Image heat = heatmap(absError, kept, scale);
        io::ExrMetadata meta;
        meta.strings["framepass:heatScale"] = fmt::format("{}", scale);
        meta.strings["framepass:compare"] = fmt::format("{}[{}] vs {}[{}]", opt.a,
                                                        displayName(layerA), opt.b,
                                                        displayName(layerB));
        std::vector<io::ExrLayer> layers = {{"Heat", &heat, true}, {"AbsError", &absError, false}};
        if (result.flip) layers.push_back({"Flip", &flipMap, false});  // FLIP's per-pixel error
        io::writeExr(opt.heatmap, {{"heat", layers}}, meta);
        const DisplayTransform display(io::loadColorConfig(opt.ocioConfig), "scene_linear", "",
                                       "", 0.0f, true);
        // The PNG carries its scale: the colour map from 0 to `scale` under the image.
        io::writePng(pngPathFor(opt.heatmap),
                     io::withColorBar(display.apply(heat), display.apply(heatmapRamp()), "0",
                                      fmt::format("{:.4g}", scale), "|error|"));
    }

    return result;
}

}  // namespace fp::app
