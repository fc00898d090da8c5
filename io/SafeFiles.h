#pragma once
// Writing files a farm can trust: never over an input, atomically (a temporary beside the target,
// then a rename, so a killed process leaves either the old file or the new one), and the
// temporaries a killed process left behind removed by the next run.
#include <string>
#include <string_view>
#include <vector>

namespace fp::io {

/// Throws fp::UsageError when `output` names the same file as one of `inputs` (by identity when
/// both exist, else by path). `flag` says where the output came from ("--report").
void refuseToOverwriteInputs(const std::string& output, const std::vector<std::string>& inputs,
                             const std::string& flag);

/// Fails early (fp::UsageError naming `flag`) when `path` cannot be written atomically: it
/// exists but is not a regular file, or its folder takes no new file (/proc, read-only).
void checkWritable(const std::string& path, const std::string& flag);
/// Creates `folder` and checks it takes a new file, before any work: fp::UsageError naming
/// `flag`, the folder and the system's reason otherwise.
void checkFolderWritable(const std::string& folder, const std::string& flag);

/// Creates `folder` and its parents; fp::UsageError naming `flag`, the folder and the reason.
void createFolder(const std::string& folder, const std::string& flag);
/// Creates the folder that will hold `path`; fp::Error naming both and the reason.
void createParentFolder(const std::string& path);
/// Removes a temporary file, ignoring failure (a read-only file system never held it): the error
/// that made the caller give up is the one to report.
void removeTemporary(const std::string& tmp);

/// Marks a temporary as being written for as long as it lives, so that a second stop signal,
/// which ends the process at once, can still remove it (removeInFlightTemporaries).
class InFlightTemporary {
public:
    explicit InFlightTemporary(const std::string& tmp);
    ~InFlightTemporary();
    InFlightTemporary(const InFlightTemporary&) = delete;
    InFlightTemporary& operator=(const InFlightTemporary&) = delete;

private:
    int slot_ = -1;  //!< -1: the registry was full or the path too long; not removable then
};

/// Unlinks every temporary an InFlightTemporary marks and returns how many. Async-signal-safe
/// (a fixed table and unlink only): the second-signal handler calls it.
int removeInFlightTemporaries() noexcept;

/// Writes `bytes` to `path` atomically. A target that exists but is not a regular file
/// (/proc/version, a folder) is an error, not "written". `sync`: flushed to the disk before the
/// rename (a report: small, and read by the farm after the job); images are not, as OpenEXR's
/// own writer never did.
void writeFileAtomically(const std::string& path, std::string_view bytes, bool sync = true);

/// Removes the temporaries (".<name>.<pid>.tmp", see temporaryPathFor) in `folder` whose
/// process no longer runs. Returns how many it removed.
int removeStaleTemporaries(const std::string& folder);

}  // namespace fp::io
