#include "io/OutputLock.h"

#include "io/SafeFiles.h"
#include "foundation/Error.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace fp::io {

namespace {

// Frame numbers may be negative: byte offsets are frame + 2³¹, so every int has its own byte.
off_t byteOf(int frame) {
    return off_t(frame) + (off_t(1) << 31);
}

}  // namespace

OutputLock::OutputLock(const std::string& folder, const std::vector<int>& frames) {
    createFolder(folder, "-o");
    const std::string path = (std::filesystem::path(folder) / kFileName).string();
    mFd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (mFd < 0)
        throw UsageError(fmt::format("-o {}: cannot create the lock file {}: {}", folder, path,
                                     std::strerror(errno)));
    std::vector<int> sorted = frames;
    std::sort(sorted.begin(), sorted.end());
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    // One lock per run of consecutive frames.
    for (std::size_t i = 0; i < sorted.size();) {
        std::size_t j = i + 1;
        while (j < sorted.size() && sorted[j] == sorted[j - 1] + 1)
            ++j;
        struct flock lock {};
        lock.l_type = F_WRLCK;
        lock.l_whence = SEEK_SET;
        lock.l_start = byteOf(sorted[i]);
        lock.l_len = off_t(j - i);
        if (::fcntl(mFd, F_SETLK, &lock) != 0) {
            const int err = errno;
            struct flock holder = lock;
            const bool known = ::fcntl(mFd, F_GETLK, &holder) == 0 && holder.l_type != F_UNLCK;
            const int first =
                known ? int(std::max(holder.l_start, lock.l_start) - byteOf(0)) : sorted[i];
            ::close(mFd);
            mFd = -1;
            if (err != EACCES && err != EAGAIN)
                throw UsageError(
                    fmt::format("-o {}: cannot lock {}: {}", folder, path, std::strerror(err)));
            throw UsageError(fmt::format(
                "-o {}: another framepass run{} is writing frame {} into this folder; two runs "
                "writing the same frames would mix their files. Wait for it, or give this run "
                "another -o or frames it does not write (chunks of one shot may share a folder)",
                folder, known ? fmt::format(" (process {})", holder.l_pid) : "", first));
        }
        i = j;
    }
}

OutputLock::~OutputLock() {
    if (mFd >= 0)
        ::close(mFd);
}

}  // namespace fp::io
