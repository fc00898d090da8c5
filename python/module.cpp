// framepass's Python module (docs/python.md): a thin door onto the application library. Every
// call goes to app/ (Session, PassCatalogue, Compare) or io/; nothing here runs a chain itself.
// Images cross as float32 numpy arrays of shape (height, width, channels), row 0 the top: the
// library keeps channels in planes, so each crossing is one copy. The GIL is released while a
// frame runs, so sessions in Python threads run side by side.
#include "app/Compare.h"
#include "app/Invocation.h"
#include "app/PassCatalogue.h"
#include "app/Session.h"
#include "foundation/Error.h"
#include "io/ExrLayers.h"
#include "io/ExrReader.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>

namespace py = pybind11;
using namespace fp;

namespace {

// nlohmann::json → Python objects, through the json module (exactly what --json prints).
py::object toPython(const nlohmann::json& j) {
    return py::module_::import("json").attr("loads")(j.dump());
}

py::array_t<float> toArray(const Image& image) {
    const py::ssize_t h = image.height(), w = image.width(), c = image.channelCount();
    py::array_t<float> a({h, w, c});
    auto out = a.mutable_unchecked<3>();
    for (py::ssize_t k = 0; k < c; ++k)
        for (py::ssize_t y = 0; y < h; ++y) {
            const float* row = image.plane(int(k)).row(int(y));
            for (py::ssize_t x = 0; x < w; ++x) out(y, x, k) = row[x];
        }
    return a;
}

py::dict toArrays(std::map<std::string, Image>& images) {
    py::dict d;
    for (auto& [name, image] : images) d[py::str(name)] = toArray(image);
    return d;
}

// A value as --cvar and --set read it: Python's bool, int and float spelled as JSON.
std::string valueText(const py::handle& v) {
    if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
    if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v) || py::isinstance<py::str>(v))
        return py::str(v).cast<std::string>();
    throw py::type_error("a setting is a bool, an int, a float or a str");
}

class PySession {
public:
    PySession(const std::string& config, const std::string& capture, const std::string& profile,
              const std::string& device, const std::string& frames) {
        app::SetupOptions o;
        o.config = config;
        o.capture = capture;
        o.profile = profile;
        o.device = device;
        o.frames = frames;
        mSession = std::make_unique<app::Session>(o);
    }
    void setCvar(const std::string& name, const py::handle& value) {
        mSession->setCvar(name, valueText(value));
    }
    void set(const std::string& passParam, const py::handle& value) {
        mSession->setParam(passParam, valueText(value));
    }
    py::dict run(std::optional<int> frame, const std::vector<std::string>& outputs) {
        const int f = frame ? *frame : mSession->frames().front();
        app::FrameResult r;
        {
            py::gil_scoped_release release;
            r = mSession->run(f, outputs);
        }
        return toArrays(r.images);
    }
    py::object plan(const std::vector<std::string>& outputs) {
        const app::RunSetup& setup = mSession->setup(outputs);
        return toPython(setup.plan().toJson(setup.extent()));
    }
    py::object report() const {
        const auto& r = mSession->lastReport();
        return r ? toPython(r->toJson()) : py::object(py::none());
    }
    std::vector<int> frames() const { return mSession->frames(); }
    void cancel() { mSession->cancel(); }

private:
    std::unique_ptr<app::Session> mSession;
};

py::dict readExr(const std::string& path, const std::vector<std::string>& layers) {
    io::ExrReader file(path);
    std::map<std::string, Image> images;
    for (const auto& info : io::listLayers(file))
        if (layers.empty() || std::find(layers.begin(), layers.end(), info.name) != layers.end())
            images[info.name] = io::readLayer(file, info);
    for (const auto& name : layers)
        if (!images.count(name))
            throw UsageError(fmt::format("{} has no layer '{}'", path, name));
    return toArrays(images);
}

}  // namespace

PYBIND11_MODULE(_framepass, m) {
    m.doc() = "framepass: Unreal Engine's lighting passes re-run on captured GBuffers.";

    // Errors: fp::UsageError (a bad config, option or input: exit 2 on the command line) is
    // ConfigError; a frame that fails (a bad capture, a pass's error) is CaptureError; both
    // derive from framepass.Error, and carry the command line's message.
    static py::exception<Error> error(m, "Error");
    static py::exception<UsageError> configError(m, "ConfigError", error.ptr());
    static py::exception<Error> captureError(m, "CaptureError", error.ptr());
    static py::exception<Cancelled> cancelled(m, "Cancelled", error.ptr());
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const UsageError& e) {
            configError(e.what());
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

    py::class_<PySession>(m, "Session", R"doc(
A config on its capture, held open while its settings change.

    s = framepass.Session("examples/cornell/config.json", capture="out/demo/cornell.exr")
    s.set_cvar("r.SSGI.Quality", 2)
    s.set("ssgi_denoise.temporalAccumulation", False)
    out = s.run(frame=1, outputs=["ssgi_denoise.diffuse"])

Runs are incremental: after a change only the passes downstream of it run again (report()
says which were reused). Frames run in order carry the temporal passes' history.
)doc")
        .def(py::init<const std::string&, const std::string&, const std::string&,
                      const std::string&, const std::string&>(),
             py::arg("config"), py::kw_only(), py::arg("capture") = "", py::arg("profile") = "",
             py::arg("device") = "", py::arg("frames") = "",
             "Reads the config and the first capture's header and plans; ConfigError lists the "
             "config's problems. capture, profile, device and frames override the config's.")
        .def("set_cvar", &PySession::setCvar, py::arg("name"), py::arg("value"),
             "Sets an Unreal cvar, as --cvar NAME=VALUE.")
        .def("set", &PySession::set, py::arg("param"), py::arg("value"),
             "Sets a pass parameter PASS.PARAM, as --set.")
        .def("run", &PySession::run, py::arg("frame") = py::none(),
             py::arg("outputs") = std::vector<std::string>{},
             "Runs a frame (default: the config's first) and returns {name: float32 array of "
             "shape (height, width, channels)} for each of outputs ('pass.port' or a capture "
             "buffer; 'all' or none: every output the chain writes and every pass output asked "
             "for). The GIL is released while it runs.")
        .def("plan", &PySession::plan, py::arg("outputs") = std::vector<std::string>{},
             "The resolved chain as a dict (what `framepass plan --json` prints).")
        .def("report", &PySession::report,
             "The last run's report: each pass's seconds, work and metrics, and 'reused' for "
             "the passes a change did not reach; None before the first run.")
        .def_property_readonly("frames", &PySession::frames, "The config's frames.")
        .def("cancel", &PySession::cancel,
             "Stops the run in flight (from another thread) between passes: it raises "
             "framepass.Cancelled.");

    m.def("passes", [] { return toPython(app::passCatalogue()); },
          "The pass catalogue: every pass type's ports, parameters and cvars "
          "(`framepass passes --json`).");
    m.def("read_exr", &readExr, py::arg("path"), py::arg("layers") = std::vector<std::string>{},
          "The layers of an EXR (all, or those named) as {layer: float32 array (H, W, C)}.");
    m.def(
        "compare",
        [](const std::string& a, const std::string& b, const std::string& layer,
           const std::string& refLayer) {
            app::CompareOptions o;
            o.a = a;
            o.b = b;
            o.layer = layer;
            o.refLayer = refLayer;
            return toPython(app::compareFiles(o).toJson(o));
        },
        py::arg("a"), py::arg("b"), py::kw_only(), py::arg("layer") = "",
        py::arg("ref_layer") = "",
        "The error of file a against reference b: the figures `framepass compare --json` "
        "prints.");
}
