#include "app/Sheet.h"

#include "io/CaptureFiles.h"
#include "io/CaptureProfile.h"
#include "io/CaptureSource.h"
#include "io/ContactSheet.h"
#include "io/ExrLayers.h"
#include "io/PngWriter.h"
#include "io/SafeFiles.h"
#include "foundation/Error.h"
#include "framework/SemanticBuffers.h"
#include "color/DisplayTransform.h"
#include "metrics/BufferPreview.h"

#include <algorithm>
#include <filesystem>
#include <optional>

namespace fp::app {

namespace {

constexpr int kMaxDefaultTileWidth = 256;

// The EXR files to show: the file itself, or a folder's *.exr sorted by name.
std::vector<std::string> sheetInputs(const std::string& input) {
    namespace fs = std::filesystem;
    if (!fs::is_directory(input))
        return {input};
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(input)) {
        std::string ext = entry.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
        if (entry.is_regular_file() && ext == ".exr")
            files.push_back(entry.path().string());
    }
    std::sort(files.begin(), files.end());
    if (files.empty())
        throw UsageError(fmt::format("{}: no .exr files in this folder", input));
    return files;
}

std::string layerTitle(const io::ExrLayerInfo& layer) {
    if (!layer.name.empty())
        return layer.name;
    std::string joined;  // the unnamed layer: its channels, "RGBA"
    for (const auto& s : layer.suffixes)
        joined += s;
    return joined;
}

}  // namespace

nlohmann::json writeSheet(const SheetOptions& opt) {
    io::checkWritable(opt.output, "-o");
    const io::CaptureProfile profile = io::CaptureProfile::load(opt.profile);
    const std::vector<std::string> files = sheetInputs(opt.input);
    const bool folder = std::filesystem::is_directory(opt.input);
    // Colour tiles go through the display pass's own transform: its defaults (scene_linear
    // in, the config's default display and view, no exposure).
    std::optional<DisplayTransform> display;

    // What to show: a folder's files layer by layer (a run's dumps); a capture buffer by
    // buffer as its profile reads it (depth in scene units with its sky, normals decoded,
    // sums and constants), then the layers no buffer reads.
    struct Source {
        std::string file;  //!< shown before the layer for a folder
        LayerDescription desc;
        std::string title;
        Image pixels;
    };
    std::vector<Source> sources;
    if (folder) {
        for (const auto& path : files) {
            io::ExrReader reader(path);
            const std::string file = std::filesystem::path(path).filename().string();
            for (const auto& layer : io::listLayers(reader))
                sources.push_back(
                    {file,
                     {layer.name, layer.suffixes, "",
                      std::all_of(layer.channels.begin(), layer.channels.end(),
                                  [](const io::ExrChannel* c) { return c->type == Imf::UINT; })},
                     layerTitle(layer), io::readLayer(reader, layer)});
        }
    } else {
        io::CaptureFiles capture(opt.input, profile);
        for (const auto& buffer : capture.availableBuffers()) {
            const io::BufferMapping* m = capture.mappingFor(buffer);
            if (m && !m->previousFrame.empty()) continue;  // frame N−1's: not this file's
            std::vector<std::string> notes;
            const int width = findSemanticBuffer(buffer)
                                  ? int(findSemanticBuffer(buffer)->channels.size())
                                  : capture.truthChannels()[buffer];
            Image pixels = capture.read(buffer, width, notes);
            const bool ids = buffer == "InstanceId" || buffer == "ShadingModel";
            sources.push_back({"", {buffer, pixels.channels(), buffer, ids}, buffer,
                               std::move(pixels)});
        }
        for (const auto& [key, constReader] : capture.files()) {
            io::ExrReader reader(constReader->path());
            for (const auto& layer : io::listLayers(reader)) {
                bool read = false;
                for (const auto* c : layer.channels)
                    read = read || !capture.bufferOfChannel(key, c->name).empty() ||
                           isTruthBuffer(c->name);
                if (read) continue;
                sources.push_back({"", {layer.name, layer.suffixes, "", false},
                                   layerTitle(layer) + " (not read)",
                                   io::readLayer(reader, layer)});
            }
        }
    }

    std::vector<io::SheetTile> tiles;
    nlohmann::json list = nlohmann::json::array();
    int tileWidth = opt.tile, tileHeight = 1;
    for (const Source& source : sources) {
        {
            if (tileWidth == 0)
                tileWidth = std::min(source.pixels.width(), kMaxDefaultTileWidth);
            const LayerDescription& desc = source.desc;
            const Image& pixels = source.pixels;
            const PreviewKind kind = classifyLayer(desc, &pixels);
            const PreviewRange range = previewRange(pixels, kind);
            Image rgb;
            if (kind == PreviewKind::Color) {
                if (!display)
                    display.emplace(io::loadColorConfig(opt.ocioConfig), "scene_linear", "",
                                    "", 0.0f, true);
                rgb = display->apply(pixels);
            } else {
                rgb = previewData(pixels, kind, range);
            }
            io::SheetTile tile;
            tile.title = (folder ? source.file + ": " : "") + source.title;
            tile.subtitle = previewRangeLabel(kind, range);
            // Scaled now: the sheet holds tiles, never every full-size layer at once.
            tile.rgb = io::scaleToWidth(rgb, tileWidth);
            tileHeight = std::max(tileHeight, tile.rgb.height());

            nlohmann::json t = {{"file", source.file},
                                {"layer", desc.name},
                                {"channels", desc.suffixes},
                                {"buffer", desc.buffer},
                                {"kind", previewKindName(kind)},
                                {"label", tile.title + " | " + tile.subtitle}};
            if (range.valid)
                t["range"] = {{"min", range.min},
                              {"max", range.max},
                              {"scale", range.logarithmic ? "log" : "linear"}};
            else
                t["range"] = nullptr;
            if (kind == PreviewKind::Depth)
                t["skyPixels"] = range.skyPixels;
            else if (kind != PreviewKind::Color)
                t["nonFinite"] = range.nonFinite;
            list.push_back(t);
            tiles.push_back(std::move(tile));
        }
    }
    const io::SheetLayout layout =
        io::sheetLayout(tiles.size(), opt.columns, tileWidth, tileHeight);
    io::writePng(opt.output, io::composeSheet(tiles, layout));

    return {{"sheet", opt.output},
            {"width", layout.width()},
            {"height", layout.height()},
            {"columns", layout.columns},
            {"rows", layout.rows},
            {"tileWidth", layout.tileWidth},
            {"tileHeight", layout.tileHeight},
            {"labelHeight", io::SheetLayout::kLabelHeight},
            {"tiles", list}};
}

}  // namespace fp::app
