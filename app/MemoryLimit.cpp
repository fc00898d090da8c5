#include "app/MemoryLimit.h"

#include "foundation/Error.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
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

uint64_t defaultMemoryLimit() {
    uint64_t available = 0;
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    uint64_t kib = 0;
    std::string unit;
    while (meminfo >> key >> kib >> unit)
        if (key == "MemAvailable:")
            available = kib * 1024;
    // Under a cgroup v2 limit (a Slurm job, a container) the job's own allowance is what counts.
    std::ifstream cgroupMax("/sys/fs/cgroup/memory.max"),
        cgroupNow("/sys/fs/cgroup/memory.current");
    std::string maxText;
    uint64_t current = 0;
    if (cgroupMax >> maxText && maxText != "max" && cgroupNow >> current) {
        const uint64_t limit = std::stoull(maxText);
        const uint64_t left = limit > current ? limit - current : 0;
        available = available ? std::min(available, left) : left;
    }
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
