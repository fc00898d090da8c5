#pragma once
// Where tests that write files put them: a folder of the build tree's scratch directory, made on
// first use, so a rerun never reads what an older build left in the source tree.
#include <filesystem>
#include <string>

namespace fp::test {

/// <scratch>/<folder>/<name>, with the folder created ("" = the scratch directory itself).
inline std::string scratchPath(const std::string& folder, const std::string& name) {
    const std::filesystem::path dir = std::filesystem::path(FP_TEST_SCRATCH) / folder;
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

}  // namespace fp::test
