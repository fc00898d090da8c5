#pragma once
// What every fuzz target shares: the bytes as a file (framepass's readers take paths), and the
// rule that decides what a finding is. A clean fp::Error (a message naming the file or JSON
// pointer, exit 1 or 2) is the expected answer to bad input; any other exception would reach
// the user as "internal error", so it aborts the run like a crash or a sanitizer report does.
#include "foundation/Error.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>

namespace fp::fuzz {

/// Writes the input to a per-process scratch file with `suffix` and returns its path.
inline std::string asFile(const uint8_t* data, size_t size, const std::string& suffix,
                          const std::string& name = "input") {
    const std::string path = "/tmp/framepass-fuzz-" + std::to_string(::getpid()) + "-" + name + suffix;
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path;
}

/// Runs `f`; fp::Error is fine, anything else is a finding.
template <typename F>
int expectCleanErrors(F&& f) {
    try {
        f();
    } catch (const fp::Error&) {
    } catch (const std::exception& e) {
        std::fprintf(stderr, "finding: an exception that is not fp::Error: %s\n", e.what());
        std::abort();
    }
    return 0;
}

}  // namespace fp::fuzz
