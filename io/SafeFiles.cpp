#include "io/SafeFiles.h"

#include "io/ExrWriter.h"
#include "passes/core/Error.h"

#include <cerrno>
#include <csignal>
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

void checkWritable(const std::string& path, const std::string& flag) {
    std::error_code ec;
    if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
        throw UsageError(fmt::format("{} {}: exists and is not a regular file", flag, path));
    const auto parent = fs::path(path).parent_path();
    if (!parent.empty()) fs::create_directories(parent, ec);
    const std::string tmp = temporaryPathFor(path);
    const bool ok = std::ofstream(tmp, std::ios::binary).good();
    fs::remove(tmp, ec);
    if (!ok)
        throw UsageError(fmt::format("{} {}: cannot create a file in {}", flag, path,
                                     parent.empty() ? "." : parent.string()));
}

void writeTextAtomically(const std::string& path, const std::string& text) {
    std::error_code ec;
    if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
        throw Error(fmt::format("{}: exists and is not a regular file; not writing over it", path));
    const auto parent = fs::path(path).parent_path();
    if (!parent.empty()) fs::create_directories(parent, ec);
    const std::string tmp = temporaryPathFor(path);
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out << text;
        out.flush();
        if (!out) {
            fs::remove(tmp, ec);
            throw Error(fmt::format("{}: could not write {}", path, tmp));
        }
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
