#pragma once
// Writing files a farm can trust: never over an input, atomically (a temporary beside the target,
// then a rename, so a killed process leaves either the old file or the new one), and the
// temporaries a killed process left behind removed by the next run.
#include <string>
#include <vector>

namespace fp::io {

/// Throws fp::UsageError when `output` names the same file as one of `inputs` (by identity when
/// both exist, else by path). `flag` says where the output came from ("--report").
void refuseToOverwriteInputs(const std::string& output, const std::vector<std::string>& inputs,
                             const std::string& flag);

/// Fails early (fp::UsageError naming `flag`) when `path` cannot be written atomically: it
/// exists but is not a regular file, or its folder takes no new file (/proc, read-only).
void checkWritable(const std::string& path, const std::string& flag);

/// Writes `text` to `path` atomically. A target that exists but is not a regular file
/// (/proc/version, a folder) is an error, not "written".
void writeTextAtomically(const std::string& path, const std::string& text);

/// Removes the temporaries (".<name>.<pid>.tmp", see temporaryPathFor) in `folder` whose
/// process no longer runs. Returns how many it removed.
int removeStaleTemporaries(const std::string& folder);

}  // namespace fp::io
