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
    return available / 4 * 3;
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


void checkMemory(uint64_t peakBytes, const std::string& value, int dumps) {
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
        "this plan needs about {} of images at its peak, more than the {} allowed ({}); nothing "
        "was read. To lower the peak: {}ask for fewer outputs, or run on a capture at half "
        "resolution (a quarter of the memory: oiiotool CAPTURE --resize 50% -o SMALL). To allow "
        "it, raise --max-memory",
        formatBytes(peakBytes), formatBytes(limit),
        value.empty() ? "--max-memory's default, 3/4 of the memory available"
                      : "--max-memory " + value,
        lower));
}

}  // namespace fp::app
