// --max-memory's allowance read from /proc and /sys/fs/cgroup: trees written here in the layouts
// cgroup v2 (a Slurm job step nested in its job) and v1 (the memory controller's hierarchy) give.
#include "app/MemoryLimit.h"
#include "tests/support/Scratch.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

using namespace fp;
namespace fs = std::filesystem;

namespace {
void write(const fs::path& file, const std::string& text) {
    fs::create_directories(file.parent_path());
    std::ofstream(file) << text;
}
// A fake root with /proc/meminfo (16 GiB, 10 GiB available) and /proc/self/cgroup.
fs::path fakeRoot(const std::string& name, const std::string& selfCgroup) {
    const fs::path root = test::scratchPath("memory_limit", name);
    fs::remove_all(root);
    write(root / "proc/meminfo", "MemTotal:       16777216 kB\nMemFree: 1 kB\nMemAvailable:   10485760 kB\n");
    write(root / "proc/self/cgroup", selfCgroup);
    return root;
}
constexpr uint64_t kGiB = uint64_t(1) << 30;
}  // namespace

TEST_SUITE("app") {

TEST_CASE("memory allowance: physical memory, and no cgroup limit") {
    const fs::path root = fakeRoot("none", "0::/user.slice\n");
    write(root / "sys/user.slice/memory.max", "max\n");
    const app::MemoryAllowance a =
        app::readMemoryAllowance((root / "proc").string(), (root / "sys").string());
    CHECK(a.physical == 16 * kGiB);
    CHECK(a.available == 10 * kGiB);
    CHECK_FALSE(a.cgroupLimited);
}

TEST_CASE("memory allowance: cgroup v2, the job's limit counts for a step nested in it") {
    // The step has no limit of its own; its job allows 8 GiB and uses 1 GiB.
    const fs::path root = fakeRoot("v2", "0::/job_42/step_0\n");
    write(root / "sys/job_42/step_0/memory.max", "max\n");
    write(root / "sys/job_42/step_0/memory.current", "536870912\n");
    write(root / "sys/job_42/memory.max", std::to_string(8 * kGiB) + "\n");
    write(root / "sys/job_42/memory.current", std::to_string(kGiB) + "\n");
    const app::MemoryAllowance a =
        app::readMemoryAllowance((root / "proc").string(), (root / "sys").string());
    REQUIRE(a.cgroupLimited);
    CHECK(a.cgroupLeft == 7 * kGiB);
    // A tighter limit on the step wins.
    write(root / "sys/job_42/step_0/memory.max", std::to_string(2 * kGiB) + "\n");
    CHECK(app::readMemoryAllowance((root / "proc").string(), (root / "sys").string()).cgroupLeft ==
          kGiB + kGiB / 2);
}

TEST_CASE("memory allowance: cgroup v1's memory controller, and its 'no limit'") {
    const fs::path root = fakeRoot("v1", "12:cpu,cpuacct:/slurm/uid_0\n5:memory:/slurm/uid_0/job_7\n");
    write(root / "sys/memory/slurm/uid_0/job_7/memory.limit_in_bytes", std::to_string(4 * kGiB));
    write(root / "sys/memory/slurm/uid_0/job_7/memory.usage_in_bytes", std::to_string(kGiB));
    app::MemoryAllowance a = app::readMemoryAllowance((root / "proc").string(), (root / "sys").string());
    REQUIRE(a.cgroupLimited);
    CHECK(a.cgroupLeft == 3 * kGiB);
    // v1 writes 2^63 rounded to a page for "unlimited".
    write(root / "sys/memory/slurm/uid_0/job_7/memory.limit_in_bytes", "9223372036854771712");
    a = app::readMemoryAllowance((root / "proc").string(), (root / "sys").string());
    CHECK_FALSE(a.cgroupLimited);
}

}  // TEST_SUITE
