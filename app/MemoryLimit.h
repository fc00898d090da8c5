#pragma once
// --max-memory: the most bytes of images a run may hold at once. The planner predicts a plan's
// peak before any pixel is read; a run whose prediction is over the limit is refused, so a farm
// node shared with other jobs is never driven into swap or the OOM killer.
#include <cstdint>
#include <string>

namespace fp::app {

/// "8G", "512M", "1.5GiB", "300000000": bytes (K, M, G, T are powers of 1024; a B or iB after
/// them is allowed). Throws fp::UsageError naming `flag` for anything else.
uint64_t parseByteSize(const std::string& text, const std::string& flag);

/// What the machine and the process's control groups allow, read from `procRoot` (/proc) and
/// `cgroupRoot` (/sys/fs/cgroup); 0 for a figure that is not known.
struct MemoryAllowance {
    uint64_t physical = 0;   //!< MemTotal
    uint64_t available = 0;  //!< MemAvailable
    /// The least room left (limit − usage) over the process's cgroup and every cgroup above it:
    /// cgroup v2's memory.max and memory.current at each level of the process's own path (a
    /// Slurm job step nested in its job), or cgroup v1's memory.limit_in_bytes and
    /// memory.usage_in_bytes of its memory controller. 0 when no limit is set.
    uint64_t cgroupLeft = 0;
    bool cgroupLimited = false;
};
MemoryAllowance readMemoryAllowance(const std::string& procRoot = "/proc",
                                    const std::string& cgroupRoot = "/sys/fs/cgroup");

/// The default limit: 3/4 of the memory available now (MemAvailable), capped by what the
/// process's cgroups leave (Slurm, containers). 0 when unknown.
uint64_t defaultMemoryLimit();

/// "1.2 GiB"
std::string formatBytes(uint64_t bytes);

/// Throws fp::UsageError when `peakBytes` is over the limit `value` asks for ("" = the default),
/// giving both figures and what would lower the peak. A `value` above the machine's physical
/// memory (or its cgroup's limit) is a warning: the limit then cannot keep the run out of swap
/// or the OOM killer.
void checkMemory(uint64_t peakBytes, const std::string& value, int dumps);

}  // namespace fp::app
