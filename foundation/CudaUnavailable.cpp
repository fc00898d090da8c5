// Cuda.h in a build without the CUDA backend (CMake found no nvcc): every use says so.
#include "foundation/Cuda.h"
#include "foundation/Error.h"

namespace fp::cuda {

namespace {
[[noreturn]] void noBackend() {
    throw UsageError(
        "this build of framepass has no GPU backend (CUDA's nvcc was not found when it was "
        "configured); rebuild with CUDA installed, or run with --device cpu");
}
}  // namespace

bool built() {
    return false;
}
std::string unavailableReason() {
    return "this build of framepass has no GPU backend (CUDA was not found when it was configured)";
}
std::string deviceName() {
    return "";
}
DeviceTexture allocate(const std::vector<Extent>&, const std::vector<std::string>&, bool) {
    noBackend();
}
std::shared_ptr<void> allocateBytes(std::size_t) {
    noBackend();
}
void usePinnedHostMemory() {
    noBackend();
}
std::shared_ptr<void> uploadBytes(const void*, std::size_t) {
    noBackend();
}
DeviceTexture upload(const Texture&) {
    noBackend();
}
DeviceTexture uploadAsync(const Texture&) {
    noBackend();
}
void awaitUpload(const DeviceTexture&) {}
void finishUploads() {}
Texture download(const DeviceTexture&) {
    noBackend();
}
DeviceImage copyOnDevice(const DeviceImage&) {
    noBackend();
}
void synchronize(const char*) {
    noBackend();
}
unsigned long long* counterBuffer(int) {
    noBackend();
}
unsigned long long* hostCounterBuffer(int) {
    noBackend();
}
void checkStatus(int, const char*) {
    noBackend();
}
double timeBareTraversal(const BvhView&, const std::vector<Ray>&, bool, int, uint64_t&) {
    noBackend();
}
TransferTotals transferTotals() {
    return {};
}
struct EventTimer::Events {};
EventTimer::EventTimer() {
    noBackend();
}
EventTimer::~EventTimer() = default;
void EventTimer::start() {}
void EventTimer::stop() {}
double EventTimer::seconds() {
    return 0.0;
}

}  // namespace fp::cuda
