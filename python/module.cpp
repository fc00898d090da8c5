// framepass's Python module (docs/python.md): a thin door onto the application library. Every
// call goes to app/ (Session, runBench, PassCatalogue, compareFiles, compareImages) or io/
// (readCapture, MemoryCapture); nothing here runs a chain, a sweep or an error figure itself.
//
// Images cross as float32 numpy arrays, row 0 the top. The library keeps an image's channels as
// planes laid out one after the other, so the planar layout (channels, height, width) is a view
// over the library's pixels with no copy, kept alive by the array; the interleaved layout
// (height, width, channels) that most Python imaging code expects costs one copy. The GIL is
// released while a frame runs and while pixels are copied, so sessions in Python threads run side
// by side.
#include "app/BenchSweep.h"
#include "app/Compare.h"
#include "app/Invocation.h"
#include "app/PassCatalogue.h"
#include "app/Session.h"
#include "foundation/Cuda.h"
#include "foundation/Error.h"
#include "foundation/Limits.h"
#include "io/CameraIO.h"
#include "io/ExrLayers.h"
#include "io/ExrReader.h"
#include "io/ExrWriter.h"
#include "io/MemoryCapture.h"
#include "io/SafeFiles.h"

#include <dlpack/dlpack.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <fmt/ranges.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <thread>

namespace py = pybind11;
using namespace fp;

namespace {

// nlohmann::json ↔ Python objects, through the json module (exactly what --json prints).
py::object toPython(const nlohmann::json& j) {
    return py::module_::import("json").attr("loads")(j.dump());
}
nlohmann::json fromPython(const py::handle& o) {
    return nlohmann::json::parse(py::module_::import("json").attr("dumps")(o).cast<std::string>());
}

enum class Layout { Interleaved, Planar };

Layout layoutOf(const std::string& name) {
    if (name == "hwc") return Layout::Interleaved;
    if (name == "chw") return Layout::Planar;
    throw py::value_error("layout is 'hwc' (height, width, channels: one copy) or 'chw' "
                          "(channels, height, width: no copy), not '" + name + "'");
}

// (H, W, C): one copy, rows spread over the cores with the GIL released.
py::array_t<float> interleaved(const Image& image) {
    const py::ssize_t h = image.height(), w = image.width(), c = image.channelCount();
    py::array_t<float> a({h, w, c});
    float* out = a.mutable_data();
    py::gil_scoped_release release;
    tbb::parallel_for(tbb::blocked_range<int>(0, int(h)), [&](const tbb::blocked_range<int>& rows) {
        std::vector<const float*> in(static_cast<std::size_t>(c));
        for (int y = rows.begin(); y < rows.end(); ++y) {
            for (py::ssize_t k = 0; k < c; ++k) in[std::size_t(k)] = image.plane(int(k)).row(y);
            float* o = out + std::size_t(y) * std::size_t(w * c);
            for (py::ssize_t x = 0; x < w; ++x)
                for (py::ssize_t k = 0; k < c; ++k) *o++ = in[std::size_t(k)][x];
        }
    });
    return a;
}

// (C, H, W): a read-only view over the image's planes when they lie one after the other (every
// image the library makes), owning a share of them; a copy otherwise.
py::array_t<float> planar(const Image& image) {
    const py::ssize_t h = image.height(), w = image.width(), c = image.channelCount();
    if (const float* data = image.planarData()) {
        const py::ssize_t stride = image.plane(0).stride() * py::ssize_t(sizeof(float));
        auto* owner = new Image(image);  // shares the planes; freed with the last array over it
        py::capsule keepAlive(owner, [](void* p) { delete static_cast<Image*>(p); });
        py::array_t<float> a({c, h, w}, {stride * h, stride, py::ssize_t(sizeof(float))}, data,
                             keepAlive);
        // The library's images are never written after they are made, and a view must not
        // be the way one is: the array is read-only (np.array(a) gives a writable copy).
        a.attr("setflags")(py::arg("write") = false);
        return a;
    }
    py::array_t<float> a({c, h, w});
    auto out = a.mutable_unchecked<3>();
    for (py::ssize_t k = 0; k < c; ++k)
        for (py::ssize_t y = 0; y < h; ++y)
            std::memcpy(out.mutable_data(k, y, 0), image.plane(int(k)).row(int(y)),
                        std::size_t(w) * sizeof(float));
    return a;
}

py::array_t<float> toArray(const Image& image, Layout layout) {
    return layout == Layout::Planar ? planar(image) : interleaved(image);
}

py::dict toArrays(const std::map<std::string, Image>& images, Layout layout) {
    py::dict d;
    for (const auto& [name, image] : images) d[py::str(name)] = toArray(image, layout);
    return d;
}

// An output that stayed on the GPU (a session with device="cuda"): a copy of the library's
// planes made on the GPU when run() hands it over (one device-to-device copy, no trip to the
// host), this object's own, so that a caller writing into it cannot change what the session
// reuses in its next run; shown as (H, W, C) or (C, H, W) by strides alone. CuPy, Numba and
// torch.as_tensor read __cuda_array_interface__ (version 3), torch.from_dlpack and JAX read
// __dlpack__: both are views of this object's memory, no copy (as two numpy views of one array
// share theirs). numpy reads __array__, which copies the pixels to the host. The frame's kernels
// and the copy have finished when run() returns, so neither protocol names a stream to wait on.
class CudaArray {
public:
    /// Takes a copy of `image` (call with the GIL released).
    CudaArray(const DeviceImage& image, Layout layout)
        : mImage(cuda::copyOnDevice(image)), mLayout(layout) {}

    // Shape and strides in elements.
    std::vector<int64_t> shape() const {
        const int64_t c = mImage.channelCount(), h = mImage.height(), w = mImage.width();
        return mLayout == Layout::Planar ? std::vector<int64_t>{c, h, w}
                                         : std::vector<int64_t>{h, w, c};
    }
    std::vector<int64_t> strides() const {
        const int64_t row = mImage.stride(), plane = row * mImage.height();
        return mLayout == Layout::Planar ? std::vector<int64_t>{plane, row, 1}
                                         : std::vector<int64_t>{row, 1, plane};
    }
    std::uintptr_t pointer() const { return reinterpret_cast<std::uintptr_t>(mImage.plane(0).data); }

    py::dict cudaArrayInterface() const {
        py::list byteStrides;
        for (const int64_t s : strides()) byteStrides.append(s * int64_t(sizeof(float)));
        py::dict d;
        d["shape"] = py::tuple(py::cast(shape()));
        d["strides"] = py::tuple(byteStrides);
        d["typestr"] = "<f4";
        d["data"] = py::make_tuple(pointer(), false);  // writable: this object's own copy
        d["version"] = 3;
        d["stream"] = py::none();  // nothing to wait for: see above
        return d;
    }

    // A DLPack capsule (the legacy, unversioned DLManagedTensor, which every consumer takes)
    // over this object's memory: the manager context holds a share of it until the consumer (or
    // the unconsumed capsule's destructor) calls the deleter.
    py::capsule dlpack() const {
        struct Held {
            DeviceImage image;
            std::vector<int64_t> shape, strides;
            DLManagedTensor tensor;
        };
        auto* held = new Held{mImage, shape(), strides(), {}};
        DLTensor& t = held->tensor.dl_tensor;
        t.data = reinterpret_cast<void*>(pointer());
        t.device = {kDLCUDA, 0};  // framepass runs on the first GPU
        t.ndim = 3;
        t.dtype = {kDLFloat, 32, 1};
        t.shape = held->shape.data();
        t.strides = held->strides.data();
        t.byte_offset = 0;
        held->tensor.manager_ctx = held;
        held->tensor.deleter = [](DLManagedTensor* self) { delete static_cast<Held*>(self->manager_ctx); };
        return py::capsule(&held->tensor, "dltensor", [](PyObject* capsule) {
            // Not consumed (a consumer renames it "used_dltensor" and calls the deleter itself).
            if (PyCapsule_IsValid(capsule, "dltensor"))
                if (auto* m = static_cast<DLManagedTensor*>(PyCapsule_GetPointer(capsule, "dltensor")))
                    m->deleter(m);
        });
    }

    // The pixels copied to the host, in this array's layout.
    py::array_t<float> toHost() const {
        Image host;
        {
            py::gil_scoped_release release;
            host = cuda::download(DeviceTexture({mImage})).image();
        }
        return toArray(host, mLayout);
    }

    std::string repr() const {
        const auto s = shape();
        return fmt::format("framepass.CudaArray(shape=({}, {}, {}), dtype=float32, channels {}, "
                           "on cuda:0)",
                           s[0], s[1], s[2], fmt::join(mImage.channels(), ""));
    }
    const std::vector<std::string>& channels() const { return mImage.channels(); }

private:
    DeviceImage mImage;
    Layout mLayout;
};

// The input limits of every image framepass reads (foundation/Limits.h), checked on the shape
// before an array is converted: a broadcast array of 10⁶ × 10⁶ must not become a copy.
void checkSize(const std::string& what, const py::array& a) {
    const py::ssize_t h = a.shape(0), w = a.shape(1);
    if (h > limits::kMaxImageDimension || w > limits::kMaxImageDimension ||
        int64_t(h) * int64_t(w) > limits::kMaxImagePixels)
        throw py::value_error(fmt::format("{}: {}×{} is larger than framepass reads (at most {} "
                                          "pixels a side, {} in all)",
                                          what, w, h, limits::kMaxImageDimension, limits::kMaxImagePixels));
    if (a.ndim() == 3 && a.shape(2) > 64)
        throw py::value_error(fmt::format("{}: {} channels is more than any image has", what,
                                          a.shape(2)));
}

// The array as C-ordered float32: itself when it is one, else a copy. ensure() gives a null
// array when numpy cannot make one (out of memory, say): an error here, never a null read.
py::array_t<float, py::array::c_style | py::array::forcecast> asFloat32(const std::string& what, const py::array& raw) {
    auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(raw);
    if (!a)
        throw py::value_error(fmt::format("{}: cannot be read as float32 (not enough memory for "
                                          "the copy?)",
                                          what));
    return a;
}

// An array of shape (H, W) or (H, W, C), checked against the input limits, copied into the
// library's planes with the channel names `names(C)` gives.
Image planarCopy(const std::string& what, const py::array& raw,
                 const std::function<std::vector<std::string>(int)>& names) {
    checkSize(what, raw);
    const auto a = asFloat32(what, raw);
    const int h = int(a.shape(0)), w = int(a.shape(1)), c = a.ndim() == 3 ? int(a.shape(2)) : 1;
    if (h <= 0 || w <= 0 || c <= 0)
        throw py::value_error(fmt::format("{}: {}×{} with {} channels is empty", what, w, h, c));
    Image image(w, h, names(c));
    const float* in = a.data();
    for (int y = 0; y < h; ++y)
        for (int k = 0; k < c; ++k) {
            float* row = image.plane(k).row(y);
            const float* p = in + std::size_t(y) * std::size_t(w) * c + k;
            for (int x = 0; x < w; ++x) row[x] = p[std::size_t(x) * c];
        }
    return image;
}

// An array another library holds (a torch tensor, a JAX or CuPy array on the host) taken
// through DLPack as a numpy view of the same memory, no copy; anything else as it is.
py::object viaDlpack(const std::string& what, const py::handle& value) {
    py::object o = py::reinterpret_borrow<py::object>(value);
    if (py::isinstance<py::array>(o) || !py::hasattr(o, "__dlpack__")) return o;
    try {
        return py::module_::import("numpy").attr("from_dlpack")(o);
    } catch (py::error_already_set& e) {
        throw py::value_error(fmt::format("{}: its DLPack tensor cannot be read on the host ({}); "
                                          "copy it to the CPU first",
                                          what, e.what()));
    }
}

// A numpy array as a capture buffer: (H, W) is one channel, (H, W, C) C channels; floating
// dtypes (and integers for the id buffers) are read as float32. ValueError names the buffer.
Image toImage(const std::string& buffer, const py::handle& given) {
    const py::object value = viaDlpack(fmt::format("buffer '{}'", buffer), given);
    if (!py::isinstance<py::array>(value) && !py::isinstance<py::buffer>(value) &&
        !py::isinstance<py::list>(value))
        throw py::value_error(fmt::format("buffer '{}': expected a numpy array, got {}", buffer,
                                          py::str(py::type::of(value)).cast<std::string>()));
    const py::array raw = py::array::ensure(value);
    if (!raw) throw py::value_error(fmt::format("buffer '{}': not an array", buffer));
    const char kind = raw.dtype().kind();
    const bool idBuffer = buffer == "ShadingModel" || buffer == "InstanceId";
    if (!(kind == 'f' || (idBuffer && (kind == 'i' || kind == 'u'))))
        throw py::value_error(fmt::format(
            "buffer '{}': dtype {} is not a floating type (float16, float32 or float64{})",
            buffer, py::str(raw.dtype()).cast<std::string>(),
            idBuffer ? ", or an integer type for an id buffer" : ""));
    if (raw.ndim() != 2 && raw.ndim() != 3)
        throw py::value_error(fmt::format("buffer '{}': shape {} is not (height, width) or "
                                          "(height, width, channels)",
                                          buffer, py::str(py::tuple(raw.attr("shape")))
                                                      .cast<std::string>()));
    try {
        return planarCopy(fmt::format("buffer '{}'", buffer), raw, [&](int channels) {
            return io::MemoryCapture::channelNames(buffer, channels);
        });
    } catch (const UsageError& e) {
        throw py::value_error(e.what());
    }
}

// A plain image (compare's arrays): (H, W) or (H, W, C), any real dtype.
Image plainImage(const char* what, const py::handle& given) {
    const py::array raw = py::array::ensure(viaDlpack(what, given));
    const std::string numeric = "fiub";  // float, int, unsigned, bool
    if (!raw || numeric.find(raw.dtype().kind()) == std::string::npos ||
        (raw.ndim() != 2 && raw.ndim() != 3))
        throw py::value_error(fmt::format("{}: expected a real array of shape (height, width) or "
                                          "(height, width, channels)",
                                          what));
    return planarCopy(what, raw, [](int channels) {
        std::vector<std::string> names;
        for (int k = 0; k < channels; ++k) names.push_back(fmt::format("C{}", k));
        return names;
    });
}

// A setting's value as Python gives it, typed as the planner takes it: a bool, an integer (int or
// anything with __index__, numpy's integers), a real (float or anything with __float__) or a str.
nlohmann::json settingValue(const std::string& call, const py::handle& v) {
    if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
    if (py::isinstance<py::str>(v)) return v.cast<std::string>();
    const py::object o = py::reinterpret_borrow<py::object>(v);
    if (py::hasattr(o, "__index__")) return py::int_(o).cast<int64_t>();
    if (py::isinstance<py::float_>(o) || py::hasattr(o, "__float__"))
        return py::float_(o).cast<double>();
    throw py::type_error(fmt::format("{}: a setting's value is a bool, an int, a float or a str, "
                                     "not {}",
                                     call, py::str(py::type::of(v).attr("__name__")).cast<std::string>()));
}

// The camera of a capture: exact as the library holds it (what read_capture found), or made
// from a sidecar's JSON (a dict) for a capture's size.
struct PyCamera {
    FrameCamera camera;
    py::object toDict() const { return toPython(io::frameCameraToJson(camera)); }
};

struct PyCapture {
    std::shared_ptr<io::MemoryCapture> capture;

    static PyCapture fromArrays(const py::dict& buffers, const py::object& camera, int64_t frame,
                                const std::string& name) {
        if (frame < -limits::kMaxFrameNumber || frame > limits::kMaxFrameNumber)
            throw py::value_error(fmt::format("frame {} is not a frame number (at most {} digits)",
                                              frame, 9));
        auto c = std::make_shared<io::MemoryCapture>(name, frame);
        for (const auto& [key, value] : buffers) {
            const std::string buffer = py::str(key).cast<std::string>();
            Image image = toImage(buffer, value);
            try {
                c->add(buffer, std::move(image));
            } catch (const UsageError& e) {
                throw py::value_error(e.what());
            }
        }
        if (c->buffers().empty()) throw py::value_error("from_arrays: no buffers given");
        if (py::isinstance<PyCamera>(camera)) {
            c->setCamera(camera.cast<const PyCamera&>().camera);
        } else if (py::isinstance<py::dict>(camera)) {
            std::vector<std::string> assumptions;
            c->setCamera(io::cameraFromSidecarJson(fromPython(camera), c->extent(), "camera",
                                                   assumptions));
            for (const auto& a : assumptions) c->note(a);
        } else if (!camera.is_none()) {
            throw py::type_error("camera is a framepass.Camera, a dict as a camera sidecar "
                                 "holds it, or None");
        }
        return PyCapture{std::move(c)};
    }
    py::dict buffers(Layout layout) const { return toArrays(capture->buffers(), layout); }
    py::array_t<float> buffer(const std::string& name, Layout layout) const {
        auto it = capture->buffers().find(name);
        if (it == capture->buffers().end())
            throw py::key_error(fmt::format("{} has no buffer '{}'", capture->name(), name));
        return toArray(it->second, layout);
    }
};

class PySession {
public:
    PySession(const std::string& config, const py::object& capture, const std::string& profile,
              const std::string& device, const std::string& frames, int threads) {
        app::SetupOptions o;
        o.config = config;
        if (py::isinstance<PyCapture>(capture))
            o.memoryCapture = capture.cast<const PyCapture&>().capture;
        else if (py::isinstance<py::str>(capture))
            o.capture = capture.cast<std::string>();
        else if (!capture.is_none())
            throw py::type_error("capture is a path (str), a framepass.Capture or None");
        o.profile = profile;
        o.device = device;
        o.frames = frames;
        if (threads < 0 || threads > limits::kMaxThreads)
            throw py::value_error(fmt::format("threads is 0 (every core) to {}", limits::kMaxThreads));
        if (threads > 0) mArena = std::make_unique<tbb::task_arena>(threads);
        // A setting is named in messages by the call that made it.
        o.settings.cvarOrigin = "set_cvar('{}')";
        o.settings.setOrigin = "set('{}')";
        o.settings.inputOrigin = "set_input('{}')";
        o.dumpOrigin = "outputs=['{}']";
        mConfig = config;
        mSession = std::make_unique<app::Session>(o);
        // Ctrl-C: after each pass, a run on Python's main thread lets Python's signal handlers
        // run; a KeyboardInterrupt (or whatever a handler raised) stops the run there and is
        // raised by run() once the frame has unwound.
        mSession->onPass = [this](int, int, const PassReport&) {
            if (!mCheckSignals) return;
            py::gil_scoped_acquire gil;
            if (PyErr_CheckSignals() == 0) return;
            PyErr_Fetch(&mRaised[0], &mRaised[1], &mRaised[2]);
            throw Cancelled("interrupted");
        };
    }
    void setCvar(const std::string& name, const py::handle& value) {
        nlohmann::json v = settingValue(fmt::format("set_cvar('{}')", name), value);
        py::gil_scoped_release release;  // it plans: a run in flight on another thread goes on
        mSession->setCvar(name, std::move(v));
    }
    void set(const std::string& passParam, const py::handle& value) {
        nlohmann::json v = settingValue(fmt::format("set('{}')", passParam), value);
        py::gil_scoped_release release;
        mSession->setParam(passParam, std::move(v));
    }
    void setInput(const std::string& passInput, std::string source) {
        py::gil_scoped_release release;
        mSession->setInput(passInput, std::move(source));
    }
    py::dict run(std::optional<int> frame, const std::vector<std::string>& outputs,
                 const std::string& layout, std::optional<bool> onDevice) {
        const Layout l = layoutOf(layout);
        const int f = frame ? *frame : mSession->frames().front();
        // By default a CUDA session's outputs stay where its passes made them.
        const bool keep = onDevice ? *onDevice : mSession->setup()->plan().device == Device::Cuda;
        app::FrameResult r;
        const py::module_ threading = py::module_::import("threading");
        const bool mainThread =
            threading.attr("current_thread")().is(threading.attr("main_thread")());
        try {
            py::gil_scoped_release release;
            auto once = [&] { r = mSession->run(f, outputs, keep); };
            // One run at a time checks signals: runs on other threads wait for the session.
            std::lock_guard<std::mutex> one(mRunMutex);
            mCheckSignals = mainThread;
            if (mArena) mArena->execute(once);
            else once();
        } catch (const Cancelled&) {
            if (mRaised[0]) {
                PyErr_Restore(mRaised[0], mRaised[1], mRaised[2]);
                mRaised[0] = mRaised[1] = mRaised[2] = nullptr;
                throw py::error_already_set();
            }
            throw;
        }
        py::dict d = toArrays(r.images, l);
        for (const auto& [name, image] : r.deviceImages) {
            std::optional<CudaArray> own;
            {
                py::gil_scoped_release release;
                own.emplace(image, l);
            }
            d[py::str(name)] = std::move(*own);
        }
        return d;
    }
    py::object plan(const std::vector<std::string>& outputs) {
        std::shared_ptr<const app::RunSetup> setup;
        {
            py::gil_scoped_release release;
            setup = mSession->setup(outputs);
        }
        return toPython(setup->plan().toJson(setup->extent()));
    }
    py::object report() const {
        const std::optional<FrameReport> r = mSession->lastReport();
        return r ? toPython(r->toJson()) : py::object(py::none());
    }
    std::string repr() const {
        const app::Settings settings = mSession->settings();
        const auto& frames = mSession->frames();
        return fmt::format("framepass.Session('{}', frames {}{}, {} cvar{}, {} parameter{} and "
                           "{} input{} set)",
                           mConfig, frames.front(),
                           frames.size() > 1 ? fmt::format("-{}", frames.back()) : "",
                           settings.cvars.size(), settings.cvars.size() == 1 ? "" : "s",
                           settings.sets.size(), settings.sets.size() == 1 ? "" : "s",
                           settings.inputs.size(), settings.inputs.size() == 1 ? "" : "s");
    }
    py::object cvarValue(const std::string& name) const {
        return toPython(mSession->cvarValue(name));
    }
    std::vector<std::string> cvarNames() const { return mSession->cvarNames(); }
    std::vector<int> frames() const { return mSession->frames(); }
    void cancel() { mSession->cancel("cancelled by Session.cancel()"); }

private:
    std::string mConfig;
    std::unique_ptr<tbb::task_arena> mArena;
    std::unique_ptr<app::Session> mSession;
    std::mutex mRunMutex;
    bool mCheckSignals = false;  // the run in flight is on Python's main thread
    PyObject* mRaised[3] = {nullptr, nullptr, nullptr};  // what a signal handler raised
};

// Channel names for an array of C channels written as a layer: what read_exr reads back in the
// same order (Y; R G B; R G B A; else C0, C1, ...).
std::vector<std::string> layerChannels(int channels) {
    if (channels == 1) return {"Y"};
    if (channels == 3) return {"R", "G", "B"};
    if (channels == 4) return {"R", "G", "B", "A"};
    std::vector<std::string> names;
    for (int k = 0; k < channels; ++k) names.push_back(fmt::format("C{:02}", k));
    return names;
}

void writeExrFile(const std::string& path, const py::dict& layers, const py::object& half,
                  const py::object& metadata, const std::string& compression,
                  std::optional<int64_t> frame) {
    if (layers.empty()) throw py::value_error("write_exr(): layers is empty: nothing to write");
    std::vector<std::string> halfLayers;
    bool allHalf = false;
    if (py::isinstance<py::bool_>(half)) allHalf = half.cast<bool>();
    else if (!half.is_none()) {
        if (py::isinstance<py::str>(half) || !py::isinstance<py::iterable>(half))
            throw py::type_error("write_exr(): half is a bool or a list of layer names");
        for (const auto& h : half) halfLayers.push_back(py::str(h).cast<std::string>());
    }
    io::ExrMetadata meta;
    if (!metadata.is_none()) {
        if (!py::isinstance<py::dict>(metadata))
            throw py::type_error("write_exr(): metadata is a dict {str: str}");
        for (const auto& [k, v] : metadata.cast<py::dict>()) {
            if (!py::isinstance<py::str>(k) || !py::isinstance<py::str>(v))
                throw py::type_error("write_exr(): metadata is a dict {str: str}");
            meta.strings[k.cast<std::string>()] = v.cast<std::string>();
        }
    }
    if (frame) {
        if (*frame < -limits::kMaxFrameNumber || *frame > limits::kMaxFrameNumber)
            throw py::value_error(fmt::format("write_exr(): frame {} is not a frame number", *frame));
        meta.frame = *frame;
    }
    const io::ExrCompression codec = [&] {
        try {
            return io::parseCompression(compression);
        } catch (const UsageError& e) {
            throw py::value_error(fmt::format("write_exr(): {}", e.what()));
        }
    }();
    std::vector<Image> images;  // kept while the parts point at them
    std::vector<std::string> names;
    images.reserve(layers.size());
    for (const auto& [k, v] : layers) {
        if (!py::isinstance<py::str>(k)) throw py::type_error("write_exr(): a layer's name is a str");
        const std::string name = k.cast<std::string>();
        const std::string what = fmt::format("write_exr(): layer '{}'", name);
        const py::array raw = py::array::ensure(viaDlpack(what, v));
        if (!raw || (raw.ndim() != 2 && raw.ndim() != 3) || raw.dtype().kind() != 'f')
            throw py::value_error(fmt::format("{}: a float array (height, width) or (height, "
                                              "width, channels)",
                                              what));
        images.push_back(planarCopy(what, raw, layerChannels));
        names.push_back(name);
    }
    io::ExrPart part;
    for (std::size_t i = 0; i < images.size(); ++i) {
        if (images[i].width() != images[0].width() || images[i].height() != images[0].height())
            throw py::value_error(fmt::format("write_exr(): layer '{}' is {}×{}, layer '{}' {}×{}: "
                                              "one file's layers have one size",
                                              names[i], images[i].width(), images[i].height(),
                                              names[0], images[0].width(), images[0].height()));
        const bool asHalf = allHalf || std::find(halfLayers.begin(), halfLayers.end(), names[i]) !=
                                           halfLayers.end();
        part.layers.push_back({names[i], &images[i], asHalf});
    }
    for (const auto& h : halfLayers)
        if (std::find(names.begin(), names.end(), h) == names.end())
            throw py::value_error(fmt::format("write_exr(): half names '{}', which is not a layer", h));
    py::gil_scoped_release release;
    io::writeExr(path, {part}, meta, codec);
}

// The string attributes of an EXR's header (what write_exr's metadata= writes), and its frame.
py::dict exrMetadata(const std::string& path) {
    io::ExrReader file(path);
    py::dict out;
    const Imf::Header& header = file.header();
    for (auto it = header.begin(); it != header.end(); ++it) {
        if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
            out[py::str(it.name())] = s->value();
        else if (const auto* i = dynamic_cast<const Imf::IntAttribute*>(&it.attribute()))
            out[py::str(it.name())] = i->value();
    }
    return out;
}

py::dict readExr(const std::string& path, const std::vector<std::string>& layers,
                 const std::string& layout) {
    const Layout l = layoutOf(layout);
    io::ExrReader file(path);
    std::map<std::string, Image> images;
    for (const auto& info : io::listLayers(file))
        if (layers.empty() || std::find(layers.begin(), layers.end(), info.name) != layers.end())
            images[info.name] = io::readLayer(file, info);
    for (const auto& name : layers)
        if (!images.count(name))
            throw UsageError(fmt::format("{} has no layer '{}'", path, name));
    return toArrays(images, l);
}

py::object compare(const py::object& a, const py::object& b, const std::string& layer,
                   const std::string& refLayer, const std::optional<std::string>& metric,
                   const std::vector<std::string>& masks, const py::object& mask,
                   double tolerance, const std::string& profile, const std::string& refProfile,
                   const std::string& heatmap, const std::string& flip, double pixelsPerDegree) {
    nlohmann::json figures;
    if (py::isinstance<py::str>(a) && py::isinstance<py::str>(b)) {
        if (!mask.is_none())
            throw py::type_error("mask= (an array) is for arrays; files take masks=[...]");
        app::CompareOptions o;
        o.a = a.cast<std::string>();
        o.b = b.cast<std::string>();
        o.layer = layer;
        o.refLayer = refLayer;
        o.masks = masks;
        o.tolerance = tolerance;
        o.profile = profile;
        o.refProfile = refProfile;
        o.heatmap = heatmap;
        o.flip = flip;
        o.pixelsPerDegree = pixelsPerDegree;
        app::CompareResult r;
        {
            py::gil_scoped_release release;
            r = app::compareFiles(o);
        }
        figures = r.toJson(o);
    } else if (!py::isinstance<py::str>(a) && !py::isinstance<py::str>(b)) {
        if (!layer.empty() || !refLayer.empty() || !heatmap.empty())
            throw py::type_error("layer, ref_layer and heatmap are for files; arrays are "
                                 "compared as they are");
        const Image imgA = plainImage("a", a), imgB = plainImage("b", b);
        std::optional<Image> kept;
        if (!mask.is_none()) kept = plainImage("mask", mask);
        if (imgA.channelCount() != imgB.channelCount() || imgA.width() != imgB.width() ||
            imgA.height() != imgB.height() ||
            (kept && (kept->width() != imgA.width() || kept->height() != imgA.height())))
            throw py::value_error(fmt::format(
                "a is {}×{}×{}, b is {}×{}×{}{}: they must have one shape (and the mask its "
                "height and width)",
                imgA.height(), imgA.width(), imgA.channelCount(), imgB.height(), imgB.width(),
                imgB.channelCount(),
                kept ? fmt::format(", the mask {}×{}", kept->height(), kept->width()) : ""));
        ErrorStats stats;
        std::optional<FlipResult> flipped;
        {
            py::gil_scoped_release release;
            stats = app::compareImages(imgA, imgB, kept ? &*kept : nullptr, nullptr, tolerance);
            // Arrays say nothing of their encoding: auto takes them as linear (HDR-FLIP).
            flipped = app::compareFlip(imgA, imgB, kept ? &*kept : nullptr, flip, false,
                                       pixelsPerDegree);
        }
        figures = stats.toJson();
        app::addFlipFigures(figures, flipped, pixelsPerDegree);
    } else {
        throw py::type_error("compare two files (paths) or two arrays, not one of each");
    }
    if (!metric) return toPython(figures);
    if (!figures.contains(*metric) || !figures[*metric].is_number()) {
        std::vector<std::string> names;
        for (const auto& [k, v] : figures.items())
            if (v.is_number() && k != "pixels" && k != "maskedPixels" && k != "tolerance")
                names.push_back(k);
        throw py::value_error(fmt::format("metric '{}' is none of {}", *metric,
                                          fmt::join(names, ", ")));
    }
    return toPython(figures[*metric]);
}

// bench's cvars=, set= or inputs= ({name: value}), each value typed as settings are and handed
// to `add`.
void addSettings(const py::object& values, const char* what,
                 const std::function<void(const std::string&, nlohmann::json)>& add) {
    if (values.is_none()) return;
    if (!py::isinstance<py::dict>(values))
        throw py::type_error(fmt::format("bench(): {}= is a dict {{name: value}}", what));
    for (const auto& [k, v] : values.cast<py::dict>()) {
        const std::string name = py::str(k).cast<std::string>();
        add(name, settingValue(fmt::format("bench(): {}['{}']", what, name), v));
    }
}

py::object bench(const std::string& config, const py::object& sweep, int runs, int warmup,
                 const std::string& capture, const std::string& profile,
                 const std::string& device, const std::string& frames, const py::object& cvars,
                 const py::object& sets, const py::object& inputs, int decomposeRays,
                 const std::string& incremental, const std::string& html) {
    app::BenchOptions o;
    o.session.config = config;
    o.session.capture = capture;
    o.session.profile = profile;
    o.session.device = device;
    o.session.frames = frames;
    o.session.settings.cvarOrigin = "bench(): cvars['{}']";
    o.session.settings.setOrigin = "bench(): set['{}']";
    o.session.settings.inputOrigin = "bench(): inputs['{}']";
    app::Settings& settings = o.session.settings;
    addSettings(cvars, "cvars", [&](const std::string& n, nlohmann::json v) { settings.setCvar(n, v); });
    addSettings(sets, "set", [&](const std::string& n, nlohmann::json v) { settings.setParam(n, v); });
    addSettings(inputs, "inputs", [&](const std::string& n, nlohmann::json v) {
        if (!v.is_string())
            throw py::type_error(fmt::format("bench(): inputs['{}'] is a source's name (str): "
                                             "'pass.port' or 'capture:Buffer'",
                                             n));
        settings.setInput(n, v.get<std::string>());
    });
    if (runs < 1 || warmup < 0) throw py::value_error("runs is 1 or more, warmup 0 or more");
    o.runs = runs;
    o.warmup = warmup;
    o.decomposeRays = decomposeRays;
    if (py::isinstance<py::dict>(sweep)) {
        for (const auto& [k, v] : sweep.cast<py::dict>()) {
            const std::string name = py::str(k).cast<std::string>();
            if (py::isinstance<py::str>(v) || !py::isinstance<py::iterable>(v))
                throw py::type_error(fmt::format("bench(): sweep['{}'] is a list of values", name));
            app::SweepAxis axis{name, {}};
            for (const auto& value : v)
                axis.values.push_back(settingValue(fmt::format("bench(): sweep['{}']", name), value));
            o.sweeps.push_back(std::move(axis));
        }
    } else if (!sweep.is_none()) {
        // 'NAME=V1,V2' strings, as --sweep spells them.
        for (const auto& s : sweep) o.sweeps.push_back(app::parseSweep(py::str(s).cast<std::string>()));
    }
    if (!html.empty()) io::checkWritable(html, "html");
    app::BenchResult result;
    {
        py::gil_scoped_release release;
        result = app::runBench(o, incremental);
        if (!html.empty()) io::writeFileAtomically(html, app::benchHtml(result));
    }
    return toPython(result.toJson());
}

}  // namespace

PYBIND11_MODULE(_framepass, m) {
    m.doc() = "framepass: Unreal Engine's lighting passes re-run on captured GBuffers.";
    m.attr("__version__") = FP_VERSION;
    // OpenEXR decompresses a file's chunks on its own pool, which is off until sized (the command
    // line sizes it to --threads): every core, as the passes' pool has.
    if (Imf::globalThreadCount() == 0)
        Imf::setGlobalThreadCount(int(std::max(1u, std::thread::hardware_concurrency())));

    // Errors: fp::UsageError (a bad config, option or input: exit 2 on the command line) is
    // ConfigError, with the config's path and each problem's JSON pointer; a frame that fails
    // (a bad capture, a pass's error) is CaptureError; both derive from framepass.Error and
    // carry the command line's message.
    static py::exception<Error> error(m, "Error");
    static py::exception<UsageError> configError(m, "ConfigError", error.ptr());
    static py::exception<Error> captureError(m, "CaptureError", error.ptr());
    static py::exception<Cancelled> cancelled(m, "Cancelled", error.ptr());
    configError.attr("path") = py::none();
    configError.attr("pointer") = py::none();
    configError.attr("problems") = py::list();
    // A setting refused when it is made is a ConfigError and the error Python raises for its kind
    // of wrong: an unknown name a KeyError, a value of the wrong type a TypeError, a value the
    // setting does not take a ValueError. Made with two bases, which py::exception cannot.
    auto settingClass = [&](const char* name, PyObject* pythonBase, const char* doc) {
        py::tuple bases = py::make_tuple(configError, py::handle(pythonBase));
        py::object cls = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
            (std::string("framepass.") + name).c_str(), doc, bases.ptr(), nullptr));
        if (!cls) throw py::error_already_set();
        m.attr(name) = cls;
        return cls.release();  // kept for the translator, as the module keeps it
    };
    static py::handle settingValueError = settingClass(
        "SettingValueError", PyExc_ValueError, "A setting's value is not one it takes (out of range, "
        "not one of its choices, an input rebound to a source that does not fit).");
    static py::handle unknownSettingError = settingClass(
        "UnknownSettingError", PyExc_KeyError, "No cvar, pass or parameter of that name.");
    static py::handle settingTypeError = settingClass(
        "SettingTypeError", PyExc_TypeError, "A setting's value has the wrong type (a str for a "
        "number, a number for a bool).");
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const SettingError& e) {
            const py::handle cls = e.kind() == SettingError::Kind::UnknownName ? unknownSettingError
                                    : e.kind() == SettingError::Kind::WrongType ? settingTypeError
                                                                                : settingValueError;
            py::object exc = cls(e.what());
            py::list problems;
            for (const auto& problem : e.problems())
                problems.append(py::make_tuple(problem.pointer, problem.message));
            exc.attr("problems") = problems;
            PyErr_SetObject(cls.ptr(), exc.ptr());
        } catch (const UsageError& e) {
            py::object exc = py::reinterpret_borrow<py::object>(configError.ptr())(e.what());
            if (!e.path().empty()) exc.attr("path") = e.path();
            py::list problems;
            for (const auto& problem : e.problems())
                problems.append(py::make_tuple(problem.pointer, problem.message));
            exc.attr("problems") = problems;
            // A JSON pointer into the config; a problem of a call's argument has none.
            if (!e.problems().empty() && e.problems().front().pointer.starts_with("/"))
                exc.attr("pointer") = e.problems().front().pointer;
            PyErr_SetObject(configError.ptr(), exc.ptr());
        } catch (const Cancelled& e) {
            cancelled(e.what());
        } catch (const Error& e) {
            captureError(e.what());
        }
    });

    // Messages go to Python's logging (logger "framepass") instead of stderr.
    app::setLogHandler([](app::LogKind kind, const std::string& line) {
        if (kind == app::LogKind::Progress) return;
        py::gil_scoped_acquire gil;
        py::object logger = py::module_::import("logging").attr("getLogger")("framepass");
        logger.attr(kind == app::LogKind::Warning ? "warning" : "info")(line);
    });

    py::class_<PyCamera>(m, "Camera", R"doc(
A frame's camera as framepass holds it (double precision; this frame and, when known, the last).
read_capture gives it exactly; to_dict() spells it as a camera sidecar (<capture>.camera.json)
does, which Capture.from_arrays(camera=...) also takes.
)doc")
        .def("to_dict", &PyCamera::toDict,
             "The camera as sidecar JSON: position, forward, up, fovYDegrees, near, width, "
             "height, sceneUnitsPerMeter and, when known, previous.")
        .def("__repr__", [](const PyCamera& c) {
            return "framepass.Camera(" + io::frameCameraToJson(c.camera).dump() + ")";
        });

    py::class_<PyCapture>(m, "Capture", R"doc(
A capture in memory: its buffers (SceneDepth, WorldNormal, BaseColor, ... and Truth.* layers)
by their canonical names, its camera and its frame number. A Session runs on it as on a file:

    c = framepass.read_capture("out/demo/cornell.exr")        # or, from arrays:
    c = framepass.Capture.from_arrays({"SceneDepth": depth, "WorldNormal": normals, ...},
                                      camera={"position": [0, 100, -300], "target": [0, 100, 0],
                                              "fovYDegrees": 40})
    s = framepass.Session("examples/cornell/config.json", capture=c)
)doc")
        .def_static("from_arrays", &PyCapture::fromArrays, py::arg("buffers"), py::kw_only(),
                    py::arg("camera") = py::none(), py::arg("frame") = 1,
                    py::arg("name") = "<arrays>",
                    "A capture from {buffer: array}: each (height, width) or (height, width, "
                    "channels), float16/32/64 (integers for ShadingModel and InstanceId), as "
                    "wide as the buffer is (docs/captures.md) and all one size. The pixels are "
                    "copied and pass the input policy a file's do (non-finite colour → 0, depth "
                    "≤ 0 → sky, normals renormalised; see notes). camera: a Camera, or a dict "
                    "as a camera sidecar holds it. ValueError names the buffer that is wrong.")
        .def_property_readonly("name", [](const PyCapture& c) { return c.capture->name(); })
        .def_property_readonly("frame", [](const PyCapture& c) { return c.capture->frame(); })
        .def_property_readonly("width",
                               [](const PyCapture& c) { return c.capture->extent().width; })
        .def_property_readonly("height",
                               [](const PyCapture& c) { return c.capture->extent().height; })
        .def_property_readonly(
            "camera",
            [](const PyCapture& c) -> py::object {
                if (!c.capture->camera()) return py::none();
                return py::cast(PyCamera{*c.capture->camera()});
            },
            "The frame's camera, or None.")
        .def_property_readonly(
            "notes", [](const PyCapture& c) { return c.capture->notes(); },
            "What was assumed or replaced on the way in, as a run would warn.")
        .def("keys",
             [](const PyCapture& c) {
                 std::vector<std::string> names;
                 for (const auto& [name, image] : c.capture->buffers()) names.push_back(name);
                 return names;
             },
             "The buffers' names.")
        .def("__contains__",
             [](const PyCapture& c, const std::string& name) {
                 return c.capture->buffers().count(name) > 0;
             })
        .def("__getitem__",
             [](const PyCapture& c, const std::string& name) {
                 return c.buffer(name, Layout::Interleaved);
             },
             "A buffer as a float32 array (height, width, channels).")
        .def(
            "buffers",
            [](const PyCapture& c, const std::string& layout) {
                return c.buffers(layoutOf(layout));
            },
            py::arg("layout") = "hwc",
            "Every buffer as {name: float32 array}; layout 'hwc' (one copy) or 'chw' (a "
            "read-only view, no copy).")
        .def("__repr__", [](const PyCapture& c) {
            return fmt::format("framepass.Capture('{}', frame {}, {}×{}, {} buffers)",
                               c.capture->name(), c.capture->frame(), c.capture->extent().width,
                               c.capture->extent().height, c.capture->buffers().size());
        });

    py::class_<CudaArray>(m, "CudaArray", R"doc(
An output left on the GPU by a session running on "cuda": float32 pixels in GPU memory, this
object's own copy (the session's next run cannot change them, nor writing into them the
session), (height, width, channels) or (channels, height, width) as the run's layout asked, by
strides alone. torch.as_tensor(a, device="cuda"), cupy.asarray(a) (__cuda_array_interface__),
torch.from_dlpack(a) and jax.dlpack (__dlpack__) view it without a copy; numpy.asarray(a) and
a.numpy() copy it to the host.)doc")
        .def_property_readonly("shape", [](const CudaArray& a) { return py::tuple(py::cast(a.shape())); })
        .def_property_readonly("dtype", [](const CudaArray&) { return py::dtype::of<float>(); })
        .def_property_readonly("channels", &CudaArray::channels, "The channels' names.")
        .def_property_readonly("__cuda_array_interface__", &CudaArray::cudaArrayInterface)
        .def("__dlpack__", [](const CudaArray& a, const py::args&, const py::kwargs&) { return a.dlpack(); },
             "A DLPack capsule over the array's memory (stream and the other keywords are "
             "taken and need nothing: the pixels are ready).")
        .def("__dlpack_device__", [](const CudaArray&) { return py::make_tuple(int(kDLCUDA), 0); })
        .def("__array__", [](const CudaArray& a, const py::args&, const py::kwargs&) { return a.toHost(); },
             "The pixels copied to the host as a numpy array.")
        .def("numpy", &CudaArray::toHost, "The pixels copied to the host as a numpy array.")
        .def("__repr__", &CudaArray::repr);

    py::class_<PySession>(m, "Session", R"doc(
A config on its capture, held open while its settings change.

    s = framepass.Session("examples/cornell/config.json", capture="out/demo/cornell.exr")
    s.set_cvar("r.SSGI.Quality", 2)              # or s.cvars["r.SSGI.Quality"] = 2
    s.set("ssgi_denoise.temporalAccumulation", False)
    out = s.run(frame=1, outputs=["ssgi_denoise.diffuse"])

Runs are incremental: after a change only the passes downstream of it run again (report()
says which were reused). Frames run in order carry the temporal passes' history.
)doc")
        .def(py::init<const std::string&, const py::object&, const std::string&,
                      const std::string&, const std::string&, int>(),
             py::arg("config"), py::kw_only(), py::arg("capture") = py::none(),
             py::arg("profile") = "", py::arg("device") = "", py::arg("frames") = "",
             py::arg("threads") = 0,
             "Reads the config and the first capture's header and plans; ConfigError lists the "
             "config's problems. capture (a path or pattern, or a Capture in memory), profile, "
             "device and frames override the config's; threads limits this session's runs to "
             "that many cores (0: all; the bits do not change).")
        .def("set_cvar", &PySession::setCvar, py::arg("name"), py::arg("value"),
             "Sets an Unreal cvar, as --cvar NAME=VALUE.")
        .def("set", &PySession::set, py::arg("param"), py::arg("value"),
             "Sets a pass parameter PASS.PARAM, as --set.")
        .def("set_input", &PySession::setInput, py::arg("input"), py::arg("source"),
             "Rebinds input PASS.INPUT to a source ('pass.port' or 'capture:Buffer'), as "
             "--input.")
        .def("run", &PySession::run, py::arg("frame") = py::none(),
             py::arg("outputs") = std::vector<std::string>{}, py::arg("layout") = "hwc",
             py::kw_only(), py::arg("on_device") = py::none(),
             "Runs a frame (default: the config's first) and returns {name: float32 array} for "
             "each of outputs ('pass.port' or a capture buffer; 'all' or none: every output the "
             "chain writes and every pass output asked for). layout 'hwc': (height, width, "
             "channels), one copy; 'chw': (channels, height, width), a read-only view over the "
             "library's pixels, no copy. on_device (default: whether the session runs on "
             "'cuda'): the outputs of passes that ran on the GPU stay there as CudaArray views "
             "in either layout, no copy. The GIL is released while it runs.")
        .def("plan", &PySession::plan, py::arg("outputs") = std::vector<std::string>{},
             "The resolved chain as a dict (what `framepass plan --json` prints).")
        .def("report", &PySession::report,
             "The last run's report: each pass's seconds, work and metrics, and 'reused' for "
             "the passes a change did not reach; None before the first run.")
        .def("cvar", &PySession::cvarValue, py::arg("name"),
             "The value a cvar has in this session: as set, else as the config gives it, else "
             "the default of the parameter it sets. ConfigError for an unknown cvar.")
        .def("cvar_names", &PySession::cvarNames, "Every cvar framepass knows.")
        .def_property_readonly("frames", &PySession::frames, "The config's frames.")
        .def("__repr__", &PySession::repr)
        .def("cancel", &PySession::cancel,
             "Stops the run in flight (from another thread) between passes: it raises "
             "framepass.Cancelled('cancelled by Session.cancel()').");

    m.def("passes", [] { return toPython(app::passCatalogue()); },
          "The pass catalogue: every pass type's ports, parameters and cvars "
          "(`framepass passes --json`).");
    m.def("read_exr", &readExr, py::arg("path"), py::arg("layers") = std::vector<std::string>{},
          py::arg("layout") = "hwc",
          "The layers of an EXR (all, or those named) as {layer: float32 array}, (height, width, "
          "channels) or, with layout='chw', (channels, height, width).");
    m.def("write_exr", &writeExrFile, py::arg("path"), py::arg("layers"), py::kw_only(),
          py::arg("half") = false, py::arg("metadata") = py::none(),
          py::arg("compression") = "zip", py::arg("frame") = py::none(),
          "Writes {layer: float array} as one multi-layer EXR, as framepass writes its own: "
          "each array (height, width) or (height, width, channels), all one size; channels named "
          "Y; R G B; R G B A; else C00, C01, ... under the layer's name ('' for none). half: "
          "True (every layer), False (float32), or a list of the layers stored as half. "
          "metadata: {str: str} header attributes; frame: the framepass:frame attribute; "
          "compression: zip, zips, piz or none. Written through a temporary file renamed into "
          "place. read_exr reads it back (float32 bit for bit; half as float16 rounds).");
    m.def("exr_metadata", &exrMetadata, py::arg("path"),
          "An EXR header's string and integer attributes as a dict (what write_exr's metadata= "
          "and frame= wrote among them).");
    m.def(
        "read_capture",
        [](const std::string& path, const std::string& profile) {
            io::CaptureProfile p = io::CaptureProfile::load(profile);
            py::gil_scoped_release release;
            return PyCapture{std::make_shared<io::MemoryCapture>(io::readCapture(path, p))};
        },
        py::arg("path"), py::arg("profile") = "canonical",
        "A capture file read through its profile (a name such as 'blender', or a profile "
        "JSON): every buffer decoded and sanitised as a run reads it, its camera and frame "
        "number.");
    m.def("compare", &compare, py::arg("a"), py::arg("b"), py::kw_only(), py::arg("layer") = "",
          py::arg("ref_layer") = "", py::arg("metric") = py::none(),
          py::arg("masks") = std::vector<std::string>{"sky"}, py::arg("mask") = py::none(),
          py::arg("tolerance") = 0.1, py::arg("profile") = "canonical",
          py::arg("ref_profile") = "", py::arg("heatmap") = "", py::arg("flip") = "auto",
          py::arg("ppd") = kFlipDefaultPixelsPerDegree,
          "The error of a against reference b: two files (paths; layer, ref_layer, masks, "
          "profiles, heatmap, flip and ppd as `framepass compare` takes them) or two arrays of "
          "one shape (mask: an array, > 0 where a pixel counts; flip='auto' takes arrays as "
          "linear, HDR-FLIP). Returns the figures `compare --json` prints, or with "
          "metric='rmse' (relMse, smape, mae, bias, maxError, overTolerance, flip) that one "
          "number.");
    m.def("bench", &bench, py::arg("config"), py::kw_only(), py::arg("sweep") = py::none(),
          py::arg("runs") = 5, py::arg("warmup") = 1, py::arg("capture") = "",
          py::arg("profile") = "", py::arg("device") = "", py::arg("frames") = "",
          py::arg("cvars") = py::none(), py::arg("set") = py::none(),
          py::arg("inputs") = py::none(), py::arg("decompose_rays") = 256, py::arg("incremental") = "", py::arg("html") = "",
          "Times the config's chain as `framepass bench` does and returns what `bench --json` "
          "prints. sweep: {name: [values]} (a cvar, PASS.PARAM or PASS.INPUT per axis; several "
          "make a grid) or a list of 'NAME=V1,V2' strings; cvars, set and inputs: {name: value} "
          "for every point; incremental: 'NAME=A,B'; html: also write the HTML report there.");
}
