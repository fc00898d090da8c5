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

/// The default limit: 3/4 of the memory available now (MemAvailable in /proc/meminfo), capped
/// by the cgroup's memory.max where the job runs under one (Slurm, containers). 0 when unknown.
uint64_t defaultMemoryLimit();

/// "1.2 GiB"
std::string formatBytes(uint64_t bytes);

/// Throws fp::UsageError when `peakBytes` is over the limit `value` asks for ("" = the default),
/// giving both figures and what would lower the peak.
void checkMemory(uint64_t peakBytes, const std::string& value, int dumps);

}  // namespace fp::app
