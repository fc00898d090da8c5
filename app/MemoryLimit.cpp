#include "app/MemoryLimit.h"

#include "app/Invocation.h"
#include "foundation/Error.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <sys/resource.h>
#include <unistd.h>

namespace fp::app {

uint64_t parseByteSize(const std::string& text, const std::string& flag) {
    auto bad = [&]() {
        return UsageError(
            fmt::format("{} {}: expected a size such as 8G, 512M or 300000000 "
                        "(bytes)",
                        flag, text));
    };
    std::size_t used = 0;
    double value = 0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        throw bad();
    }
    std::string unit = text.substr(used);
    for (auto& c : unit)
        c = char(std::toupper(static_cast<unsigned char>(c)));
    if (unit.ends_with("IB"))
        unit.resize(unit.size() - 2);
    else if (unit.size() > 1 && unit.ends_with("B"))
        unit.pop_back();
    static const std::string kUnits = "KMGT";
    double scale = 1;
    if (!unit.empty()) {
        const auto pos = kUnits.find(unit);
        if (unit.size() != 1 || pos == std::string::npos)
            throw bad();
        scale = std::pow(1024.0, double(pos + 1));
    }
    if (!std::isfinite(value) || value <= 0 || value * scale > 1.8e19)
        throw bad();
    return uint64_t(value * scale);
}

namespace {
// The first number of a file, or nothing ("max", a missing file).
std::optional<uint64_t> readNumber(const std::string& path) {
    std::ifstream in(path);
    std::string text;
    if (!(in >> text) || text.empty() || !std::isdigit(static_cast<unsigned char>(text[0])))
        return std::nullopt;
    try {
        return std::stoull(text);
    } catch (const std::exception&) {
        return std::nullopt;
    }
}
}  // namespace

MemoryAllowance readMemoryAllowance(const std::string& procRoot, const std::string& cgroupRoot) {
    MemoryAllowance a;
    std::ifstream meminfo(procRoot + "/meminfo");
    std::string key, unit;
    uint64_t kib = 0;
    while (meminfo >> key >> kib >> unit) {
        if (key == "MemTotal:") a.physical = kib * 1024;
        if (key == "MemAvailable:") a.available = kib * 1024;
    }
    auto limitAt = [&](const std::string& limitFile, const std::string& usageFile) {
        const auto limit = readNumber(limitFile), usage = readNumber(usageFile);
        // cgroup v1 writes a page-rounded 2^63 for "no limit".
        if (!limit || *limit >= (uint64_t(1) << 62)) return;
        const uint64_t left = *limit > usage.value_or(0) ? *limit - usage.value_or(0) : 0;
        a.cgroupLeft = a.cgroupLimited ? std::min(a.cgroupLeft, left) : left;
        a.cgroupLimited = true;
    };
    // /proc/self/cgroup: "0::/path" (v2) or "N:controllers:/path" per v1 hierarchy.
    std::ifstream groups(procRoot + "/self/cgroup");
    std::string line;
    while (std::getline(groups, line)) {
        const auto first = line.find(':'), second = line.find(':', first + 1);
        if (first == std::string::npos || second == std::string::npos) continue;
        const std::string controllers = line.substr(first + 1, second - first - 1);
        const std::string path = line.substr(second + 1);
        if (controllers.empty()) {  // v2: every level from the process's group up to the root
            for (std::filesystem::path level = path;; level = level.parent_path()) {
                const std::string dir = fmt::format(
                    "{}{}", cgroupRoot, level.has_relative_path() ? level.string() : "");
                limitAt(dir + "/memory.max", dir + "/memory.current");
                if (!level.has_relative_path()) break;  // the root: done
            }
        } else if (fmt::format(",{},", controllers).find(",memory,") != std::string::npos) {
            const std::string dir = cgroupRoot + "/memory" + (path == "/" ? "" : path);
            limitAt(dir + "/memory.limit_in_bytes", dir + "/memory.usage_in_bytes");
        }
    }
    // A container whose /proc/self/cgroup names no path (its namespace's root).
    if (!a.cgroupLimited) {
        limitAt(cgroupRoot + "/memory.max", cgroupRoot + "/memory.current");
        limitAt(cgroupRoot + "/memory/memory.limit_in_bytes",
                cgroupRoot + "/memory/memory.usage_in_bytes");
    }
    return a;
}

uint64_t defaultMemoryLimit() {
    const MemoryAllowance a = readMemoryAllowance();
    uint64_t available = a.available;
    // Under a cgroup limit (a Slurm job, a container) the job's own allowance is what counts.
    if (a.cgroupLimited) available = available ? std::min(available, a.cgroupLeft) : a.cgroupLeft;
    // The limit is on the process's peak, which includes what it holds already.
    return available ? available / 4 * 3 + residentBytes() : 0;
}

uint64_t residentBytes() {
    // statm's second field: resident pages.
    std::ifstream statm("/proc/self/statm");
    uint64_t size = 0, resident = 0;
    if (!(statm >> size >> resident)) return 0;
    return resident * uint64_t(sysconf(_SC_PAGESIZE));
}

uint64_t peakResidentBytes() {
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
    return uint64_t(usage.ru_maxrss) * 1024;  // KiB on Linux
}

MemoryForecast forecastMemory(const Plan& plan, Extent frame, int frames, int readAhead,
                              bool halfColor, int writers) {
    MemoryForecast f;
    f.resident = residentBytes();
    readAhead = frames > 1 ? std::min(readAhead, frames - 1) : 0;
    f.frame = plan.estimateMemory(frame, readAhead > 0, frames > 1);
    for (const auto& r : plan.captureReads)
        f.readAhead += uint64_t(readAhead) * imageBytes(frame, r.channels);
    // The writer converts a file's colour layers to half before writing (data layers and float
    // colour are written in place); a PNG preview is 8-bit RGB.
    auto channelsOf = [&](const std::string& key) {
        if (key.rfind("capture:", 0) == 0) {
            for (const auto& r : plan.captureReads)
                if ("capture:" + r.buffer == key) return r.channels;
            return 0;
        }
        const auto dot = key.rfind('.');
        for (const PlanStep& s : plan.steps)
            if (dot != std::string::npos && s.name == key.substr(0, dot))
                for (const auto& o : s.io.outputs)
                    if (o.name == key.substr(dot + 1)) return int(o.channels.size());
        return 0;
    };
    const uint64_t pixels = uint64_t(frame.width) * uint64_t(frame.height);
    std::vector<uint64_t> files;
    for (const OutputDesc& out : plan.outputs) {
        // Writers hold a frame's outputs until written, while the next frame computes.
        if (writers > 0 && frames > 1)
            for (const auto& src : out.sources) f.queued += imageBytes(frame, channelsOf(src));
        uint64_t bytes = 0;
        if (out.file.ends_with(".png")) {
            bytes = 3 * pixels;
        } else if (halfColor) {
            for (const auto& src : out.sources) {
                auto kind = plan.outputKinds.find(src);
                if (kind != plan.outputKinds.end() && kind->second == PortKind::Color)
                    bytes += 2 * pixels * uint64_t(channelsOf(src));
            }
        }
        files.push_back(bytes);
    }
    // Each writer converts one file at a time: the largest files at once.
    std::sort(files.rbegin(), files.rend());
    for (std::size_t i = 0; i < files.size() && i < std::size_t(std::max(writers, 1)); ++i)
        f.writing += files[i];
    return f;
}

std::string describeForecast(const MemoryForecast& f) {
    return fmt::format("{} of images, {} of pass scratch and {} of history at '{}', {} this "
                       "process holds already, {} read ahead, {} of a frame's outputs waiting "
                       "for the writers, {} to write files",
                       formatBytes(f.frame.images), formatBytes(f.frame.scratch),
                       formatBytes(f.frame.history), f.frame.peakStep, formatBytes(f.resident),
                       formatBytes(f.readAhead), formatBytes(f.queued), formatBytes(f.writing));
}

nlohmann::json MemoryForecast::toJson() const {
    return {{"totalBytes", total()},
            {"residentBytes", resident},
            {"imageBytes", frame.images},
            {"scratchBytes", frame.scratch},
            {"historyBytes", frame.history},
            {"peakStep", frame.peakStep},
            {"readAheadBytes", readAhead},
            {"queuedBytes", queued},
            {"writingBytes", writing}};
}

std::string formatBytes(uint64_t bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    double v = double(bytes);
    int u = 0;
    while (v >= 1024 && u < 4) {
        v /= 1024;
        ++u;
    }
    return u == 0 ? fmt::format("{} B", bytes) : fmt::format("{:.1f} {}", v, units[u]);
}


void checkMemory(uint64_t peakBytes, const std::string& breakdown, const std::string& value,
                 int dumps) {
    const uint64_t limit =
        value.empty() ? defaultMemoryLimit() : parseByteSize(value, "--max-memory");
    if (!value.empty()) {
        const MemoryAllowance a = readMemoryAllowance();
        const uint64_t most = a.cgroupLimited && a.physical ? std::min(a.physical, a.cgroupLeft)
                              : a.cgroupLimited        ? a.cgroupLeft
                                                       : a.physical;
        if (most > 0 && limit > most)
            logWarning(fmt::format("--max-memory {} is more than this machine {} ({}): it cannot "
                                   "keep the run out of swap or the OOM killer",
                                   value, a.cgroupLimited ? "and its cgroup leave" : "has",
                                   formatBytes(most)));
    }
    if (limit == 0 || peakBytes <= limit)
        return;
    std::string lower = dumps > 0 ? fmt::format("dump fewer buffers ({} --dump now), ", dumps) : "";
    throw UsageError(fmt::format(
        "this needs about {} at its peak ({}), more than the {} allowed ({}); nothing was read. "
        "To lower the peak: {}ask for fewer outputs, or work on images at half resolution (a "
        "quarter of the memory: oiiotool IMAGE --resize 50% -o SMALL). To allow it, raise "
        "--max-memory",
        formatBytes(peakBytes), breakdown, formatBytes(limit),
        value.empty() ? "--max-memory's default: what the process holds + 3/4 of the memory available"
                      : "--max-memory " + value,
        lower));
}

}  // namespace fp::app
