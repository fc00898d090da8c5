#pragma once
// Two runs writing the same frames into one folder would interleave their files with nothing
// said, the later one's bytes winning file by file. Each run takes, without waiting, a lock on
// the frames it writes: POSIX byte-range locks on <folder>/.framepass.lock, one byte per frame.
// Chunks of a farm job that write disjoint frames into one folder do not conflict; a run whose
// frames overlap another live run's is refused, naming that run's process. The kernel drops the
// locks when the process ends, however it ends, so a killed run leaves nothing stale behind.
#include <string>
#include <vector>

namespace fp::io {

class OutputLock {
public:
    /// Locks `frames` in `folder` (created if missing). Throws fp::UsageError naming the folder,
    /// the first frame in conflict and the process holding it.
    OutputLock(const std::string& folder, const std::vector<int>& frames);
    ~OutputLock();
    OutputLock(const OutputLock&) = delete;
    OutputLock& operator=(const OutputLock&) = delete;

    static constexpr const char* kFileName = ".framepass.lock";

private:
    int mFd = -1;
};

}  // namespace fp::io
