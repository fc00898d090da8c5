#pragma once
// --max-memory: the most memory a run's process may hold at once. Before any pixel is read the
// forecast adds what the process holds now (code, libraries, what was read) to the plan's peak
// (images, pass scratch, histories), the next frame's capture read ahead and the largest output
// file's copy as it is written; a run whose forecast is over the limit is refused, so a farm node
// shared with other jobs is never driven into swap or the OOM killer. The report sets the
// forecast beside the peak the process reached.
#include "framework/Planner.h"

#include <nlohmann/json.hpp>

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

/// The default limit on the process's peak: what it holds now + 3/4 of the memory available now
/// (MemAvailable), capped by what the process's cgroups leave (Slurm, containers). 0 when
/// unknown.
uint64_t defaultMemoryLimit();

/// "1.2 GiB"
std::string formatBytes(uint64_t bytes);

/// This process's resident memory now, and the most it has held (getrusage); 0 where unknown.
uint64_t residentBytes();
uint64_t peakResidentBytes();

/// What a run's process will hold at its peak.
struct MemoryForecast {
    uint64_t resident = 0;        //!< the process before its first frame
    Plan::MemoryEstimate frame;   //!< a frame's images, the peak step's scratch, the histories
    uint64_t readAhead = 0;       //!< the next frames' capture buffers, read while one runs
    /// The previous frame's outputs, held by the writers while the next frame computes.
    uint64_t queued = 0;
    /// The half-float copies of the files being written at once (the largest, one a writer).
    uint64_t writing = 0;
    uint64_t total() const { return resident + frame.peak() + readAhead + queued + writing; }
    nlohmann::json toJson() const;
};

/// The forecast of `plan` on frames of `frame` pixels; `halfColor` as the writer stores colour.
/// `frames`: how many the run computes (from the second on, the histories are held);
/// `readAhead`: frames read ahead; `writers`: threads writing files (RunOptions).
MemoryForecast forecastMemory(const Plan& plan, Extent frame, int frames, int readAhead,
                              bool halfColor, int writers);

/// "1.1 GiB of images, 96 MiB of pass scratch, …" for messages.
std::string describeForecast(const MemoryForecast& f);

/// Throws fp::UsageError when `peakBytes` is over the limit `value` asks for ("" = the default),
/// giving both figures and what would lower the peak. A `value` above the machine's physical
/// memory (or its cgroup's limit) is a warning: the limit then cannot keep the run out of swap
/// or the OOM killer.
/// `breakdown` says what the figure is made of, for the message.
void checkMemory(uint64_t peakBytes, const std::string& breakdown, const std::string& value,
                 int dumps);

}  // namespace fp::app
