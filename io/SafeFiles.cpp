#include "io/SafeFiles.h"

#include "io/ExrWriter.h"
#include "foundation/Error.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace fp::io {

namespace fs = std::filesystem;

namespace {
bool sameFile(const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
    return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}
}  // namespace

void refuseToOverwriteInputs(const std::string& output, const std::vector<std::string>& inputs,
                             const std::string& flag) {
    for (const auto& in : inputs)
        if (!in.empty() && sameFile(output, in))
            throw UsageError(fmt::format("{} {}: that is an input of this command ({}); refusing "
                                         "to overwrite it",
                                         flag, output, in));
}

void createFolder(const std::string& folder, const std::string& flag) {
    if (folder.empty()) return;
    std::error_code ec;
    if (fs::is_directory(folder, ec)) return;
    fs::create_directories(folder, ec);
    if (ec)
        throw UsageError(fmt::format("{}{}: cannot create the folder: {}",
                                     flag.empty() ? "" : flag + " ", folder, ec.message()));
}

void createParentFolder(const std::string& path) {
    const auto parent = fs::path(path).parent_path();
    if (parent.empty()) return;
    std::error_code ec;
    if (fs::is_directory(parent, ec)) return;
    fs::create_directories(parent, ec);
    if (ec)
        throw Error(fmt::format("{}: cannot create its folder {}: {}", path, parent.string(),
                                ec.message()));
}

namespace {
// A fixed table rather than a container: a signal handler may read it at any moment, so it holds
// no pointer to heap memory and a slot becomes readable (state 2) only once its path is whole.
constexpr int kInFlightSlots = 256;
constexpr std::size_t kInFlightPathMax = 4096;
std::atomic<int> gInFlightState[kInFlightSlots];  // 0 free, 1 being filled, 2 readable
char gInFlightPath[kInFlightSlots][kInFlightPathMax];
}  // namespace

InFlightTemporary::InFlightTemporary(const std::string& tmp) {
    if (tmp.size() >= kInFlightPathMax) return;
    for (int i = 0; i < kInFlightSlots; ++i) {
        int expected = 0;
        if (gInFlightState[i].compare_exchange_strong(expected, 1)) {
            std::memcpy(gInFlightPath[i], tmp.c_str(), tmp.size() + 1);
            gInFlightState[i].store(2);
            slot_ = i;
            return;
        }
    }
}

InFlightTemporary::~InFlightTemporary() {
    if (slot_ >= 0) gInFlightState[slot_].store(0);
}

int removeInFlightTemporaries() noexcept {
    int removed = 0;
    for (int i = 0; i < kInFlightSlots; ++i)
        if (gInFlightState[i].load() == 2 && ::unlink(gInFlightPath[i]) == 0) ++removed;
    return removed;
}

void removeTemporary(const std::string& tmp) {
    std::error_code ec;
    fs::remove(tmp, ec);  // on a read-only file system the temporary was never made
}

namespace {
// 0 when a new file can be made in `folder` (and is removed again), else the errno.
int tryCreateFileIn(const std::string& folder) {
    const std::string tmp = temporaryPathFor((fs::path(folder) / "check").string());
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return errno;
    ::close(fd);
    removeTemporary(tmp);
    return 0;
}
}  // namespace

void checkWritable(const std::string& path, const std::string& flag) {
    std::error_code ec;
    if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
        throw UsageError(fmt::format("{} {}: exists and is not a regular file", flag, path));
    const auto parent = fs::path(path).parent_path();
    const std::string folder = parent.empty() ? "." : parent.string();
    createFolder(folder, flag + " " + path + ":");
    if (const int err = tryCreateFileIn(folder))
        throw UsageError(fmt::format("{} {}: cannot create a file in {}: {}", flag, path, folder,
                                     std::strerror(err)));
}

void checkFolderWritable(const std::string& folder, const std::string& flag) {
    createFolder(folder, flag);
    if (const int err = tryCreateFileIn(folder))
        throw UsageError(fmt::format("{}{}: cannot create a file there: {}",
                                     flag.empty() ? "" : flag + " ", folder, std::strerror(err)));
}

void writeFileAtomically(const std::string& path, std::string_view text, bool sync) {
    std::error_code ec;
    if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
        throw Error(fmt::format("{}: exists and is not a regular file; not writing over it", path));
    createParentFolder(path);
    const std::string tmp = temporaryPathFor(path);
    const InFlightTemporary inFlight(tmp);
    // POSIX calls rather than a stream, so a failure carries its reason (ENOSPC, EROFS, EDQUOT).
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        throw Error(fmt::format("{}: could not create {}: {}", path, tmp, std::strerror(errno)));
    std::size_t done = 0;
    int err = 0;
    while (done < text.size() && !err) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno != EINTR) err = errno;
        if (n > 0) done += std::size_t(n);
    }
    if (!err && sync && ::fsync(fd) != 0 && errno != EINVAL) err = errno;
    if (::close(fd) != 0 && !err) err = errno;
    if (err) {
        removeTemporary(tmp);
        throw Error(fmt::format("{}: could not write {}: {}", path, tmp, std::strerror(err)));
    }
    commitFile(tmp, path);
}

int removeStaleTemporaries(const std::string& folder) {
    int removed = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(folder, ec)) {
        // ".<name>.<pid>.tmp": the pid is the last number before ".tmp".
        const std::string name = e.path().filename().string();
        if (name.size() < 7 || name[0] != '.' || !name.ends_with(".tmp")) continue;
        const std::string stem = name.substr(0, name.size() - 4);
        const auto dot = stem.rfind('.');
        if (dot == std::string::npos || dot == 0) continue;
        const std::string digits = stem.substr(dot + 1);
        if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos ||
            digits.size() > 9)
            continue;
        const pid_t pid = pid_t(std::stol(digits));
        if (pid <= 0 || (::kill(pid, 0) == -1 && errno == ESRCH)) {
            if (fs::remove(e.path(), ec)) ++removed;
        }
    }
    return removed;
}

}  // namespace fp::io
