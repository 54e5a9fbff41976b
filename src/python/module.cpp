// The Python module `pathtracer` (docs/python.md): scenes loaded once and edited in place,
// renders with the command line's options as keywords, images as numpy arrays. The work is
// src/scripting/'s; this file is the glue: keywords, the GIL (released while rendering),
// Ctrl-C (checked between waves), exceptions and warnings.
#include <mutex>
#include <optional>

#include <pybind11/stl.h>

#include "src/app/run.h"
#include "src/io/image_io.h"
#include "src/python/convert.h"
#include "src/scripting/script_render.h"
#include "src/scripting/script_scene.h"

namespace pt::python {
namespace {

const AppBackends& Backends() {
  static const AppBackends backends = [] {
    AppBackends b;
    b.cpuSession = &MakeCpuSession;
    b.cpuDenoiser = &MakeCpuDenoiser;
#if defined(PT_HAVE_CUDA)
    b.cudaSession = &MakeCudaSession;
    b.cudaDenoiser = &MakeCudaDenoiser;
#endif
    b.cudaDeviceCount = &CudaDeviceCount;
    return b;
  }();
  return backends;
}

void Warn(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) {
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 2) != 0) throw py::error_already_set();
  }
}

// pathtracer.Scene: the scene and a lock held while it renders (edits wait for no render).
struct PyScene {
  std::unique_ptr<ScriptScene> scene;
  std::mutex busy;

  // For an edit: the scene, or a clear error while another thread renders it.
  template <typename F>
  auto Edit(F&& edit) {
    std::unique_lock<std::mutex> lock(busy, std::try_to_lock);
    if (!lock) throw std::logic_error("the scene is being rendered by another thread");
    return edit(*scene);
  }
};

std::unique_ptr<PyScene> MakeScene(const py::object& source, std::optional<std::string> camera,
                                   std::optional<py::object> baseDir) {
  auto out = std::make_unique<PyScene>();
  std::string pick = camera.value_or("");
  if (py::isinstance<py::dict>(source)) {
    std::string dir = baseDir ? OptionText(*baseDir) : std::string(".");
    std::string text = ToJsonText(source);
    py::gil_scoped_release release;
    out->scene = ScriptScene::FromText(text, "<dict>", dir, pick);
  } else if (py::isinstance<py::str>(source) || py::hasattr(source, "__fspath__")) {
    std::string path = OptionText(source);
    py::gil_scoped_release release;
    out->scene = ScriptScene::Load(path, pick);
  } else {
    throw py::type_error("Scene() takes a scene file's path or a dict of the scene format");
  }
  Warn(out->scene->TakeWarnings());
  return out;
}

// The keywords as the CLI's options; aovs is the module's own.
ScriptRequest MakeRequest(const py::kwargs& kwargs, bool* aovs) {
  ScriptRequest request;
  for (auto [key, value] : kwargs) {
    std::string name = py::str(key).cast<std::string>();
    if (name == "aovs") {
      *aovs = value.cast<bool>();
      continue;
    }
    if (value.is_none()) continue;  // None: the default
    request.keywords.emplace_back(name, OptionText(value));
  }
  request.cli = OptionsFromKeywords(request.keywords);
  request.featureBuffers = *aovs;
  return request;
}

// Polled between waves with the GIL released: Ctrl-C (any pending signal handler that raises)
// stops the render; the exception stays set for the caller to raise.
bool PollSignals() {
  py::gil_scoped_acquire gil;
  return PyErr_CheckSignals() != 0;
}

// pathtracer.Result. Its arrays are made on first use (numpy is imported then), so a script
// that only saves images runs without numpy.
struct PyResult {
  std::shared_ptr<FilmImage> film;
  py::object stats;
  mutable py::object image, aovs;

  explicit PyResult(ScriptResult&& r)
      : film(std::make_shared<FilmImage>(std::move(r.image))), stats(FromJson(r.stats)) {}

  py::object Image() const {
    if (!image) image = FilmArray(film, film->rgb, 3);
    return image;
  }

  py::object Aovs() const {
    if (aovs) return aovs;
    py::dict extra;
    extra["variance"] = FilmArray(film, film->variance, 3);
    extra["samples"] = CountArray(film);
    if (!film->albedo.empty()) {
      extra["albedo"] = FilmArray(film, film->albedo, 3);
      extra["normal"] = FilmArray(film, film->normal, 3);
      extra["depth"] = FilmArray(film, film->depth, 1);
    }
    if (!film->denoised.empty()) extra["denoised"] = FilmArray(film, film->denoised, 3);
    aovs = extra;
    return aovs;
  }

  void Save(const py::object& path) const {
    std::string file = OptionText(path);
    ImageFormat format;
    if (!ImageFormatFromPath(file, &format)) {
      throw std::invalid_argument(file + ": unknown image format (use .png, .exr or .pfm)");
    }
    py::gil_scoped_release release;
    bool exr = format == ImageFormat::kExr;
    if (!exr && !film->denoised.empty()) {  // denoise=True: as the CLI's -o, the denoised image
      FilmImage shown;
      shown.width = film->width;
      shown.height = film->height;
      shown.rgb = film->denoised;
      WriteImage(file, shown, false);
      return;
    }
    WriteImage(file, *film, exr);  // an EXR keeps variance and AOVs (and denoised.R/G/B)
  }

  double Spp() const { return stats["spp_mean"].cast<double>(); }
};

// KeyboardInterrupt (set by PollSignals) when the render was stopped; then the loader's
// warnings; then the result.
PyResult Finish(ScriptResult&& result, ScriptScene& scene) {
  if (result.stopped) throw py::error_already_set();
  Warn(scene.TakeWarnings());
  return PyResult(std::move(result));
}

PyResult Render(PyScene& scene, const py::kwargs& kwargs) {
  bool aovs = true;
  ScriptRequest request = MakeRequest(kwargs, &aovs);
  request.shouldStop = &PollSignals;
  ScriptResult result;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(scene.busy);
    result = RenderScript(*scene.scene, request, Backends());
  }
  return Finish(std::move(result), *scene.scene);
}

// The iterator render_progressive returns.
class PyProgressive {
 public:
  PyProgressive(py::object sceneObject, std::optional<std::vector<uint32_t>> steps,
                const py::kwargs& kwargs)
      : sceneObject_(std::move(sceneObject)), scene_(sceneObject_.cast<PyScene&>()) {
    bool aovs = true;
    ScriptRequest request = MakeRequest(kwargs, &aovs);
    request.shouldStop = &PollSignals;
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(scene_.busy);
    render_ = std::make_unique<ProgressiveScript>(*scene_.scene, std::move(request), Backends(),
                                                  steps.value_or(std::vector<uint32_t>{}));
  }

  PyResult Next() {
    ScriptResult result;
    bool more;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(scene_.busy);
      more = render_->Next(&result);
    }
    if (!more) throw py::stop_iteration();
    return Finish(std::move(result), *scene_.scene);
  }

 private:
  py::object sceneObject_;  // keeps the scene alive
  PyScene& scene_;
  std::unique_ptr<ProgressiveScript> render_;
};

py::array_t<double> MatrixArray(const glm::dmat4& m) {
  py::array_t<double> out({4, 4});
  auto a = out.mutable_unchecked<2>();
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) a(row, col) = m[col][row];  // glm is column-major
  return out;
}

// A 4x4 array-like becomes the scene format's {"matrix": [16 numbers, row-major]}; a dict is
// taken as the transform object itself.
Json TransformJson(const py::object& transform) {
  if (py::isinstance<py::dict>(transform)) return ToJson(transform);
  py::object rows = py::hasattr(transform, "tolist") ? transform.attr("tolist")() : transform;
  Json matrix = Json::array();
  for (py::handle row : rows) {
    if (!py::isinstance<py::sequence>(row)) {
      throw py::type_error("a transform is a 4x4 matrix (rows) or a dict of the scene format");
    }
    for (py::handle v : row) matrix.push_back(ToJson(v));
  }
  return Json{{"matrix", matrix}};
}

void BindScene(py::module_& m) {
  py::class_<PyScene>(m, "Scene", "A scene loaded once and kept, BVH included, between renders.")
      .def(py::init(&MakeScene), py::arg("source"), py::arg("camera") = py::none(),
           py::arg("base_dir") = py::none())
      .def_property_readonly("name", [](PyScene& s) { return s.scene->Name(); })
      .def_property_readonly("camera", [](PyScene& s) { return FromJson(s.scene->CameraJson()); })
      .def("set_camera", [](PyScene& s, const py::kwargs& fields) {
        Json json = ToJson(fields);
        s.Edit([&](ScriptScene& scene) { scene.EditCamera(json); });
      })
      .def_property_readonly("materials", [](PyScene& s) { return s.scene->MaterialNames(); })
      .def("material", [](PyScene& s, const std::string& name) {
        return FromJson(s.Edit([&](ScriptScene& scene) { return scene.MaterialJson(name); }));
      })
      .def("set_material", [](PyScene& s, const std::string& name, const py::kwargs& fields) {
        Json json = ToJson(fields);
        s.Edit([&](ScriptScene& scene) { scene.EditMaterial(name, json); });
      })
      .def_property_readonly("instance_count", [](PyScene& s) { return s.scene->InstanceCount(); })
      .def("instance_transform", [](PyScene& s, size_t index) {
        return MatrixArray(s.scene->InstanceTransform(index));
      })
      .def("set_instance_transform", [](PyScene& s, size_t index, const py::object& transform) {
        Json json = TransformJson(transform);
        s.Edit([&](ScriptScene& scene) { scene.SetInstanceTransform(index, json); });
      })
      .def_property_readonly("settings", [](PyScene& s) {
        const RenderSettings& r = s.scene->SceneSettings();
        py::dict d;
        d["width"] = r.width, d["height"] = r.height, d["spp"] = r.spp;
        d["max_depth"] = r.maxDepth, d["seed"] = r.seed;
        d["adaptive"] = r.adaptive.enabled;
        return d;
      })
      .def("to_json", [](PyScene& s) {
        return s.Edit([](ScriptScene& scene) { return scene.Text(); });
      })
      .def("__repr__", [](PyScene& s) { return "<pathtracer.Scene " + s.scene->Name() + ">"; });
}

void BindResult(py::module_& m) {
  py::class_<PyResult>(m, "Result", "An image, its AOVs and the render's statistics.")
      .def_property_readonly("image", &PyResult::Image)
      .def_property_readonly("aovs", &PyResult::Aovs)
      .def_readonly("stats", &PyResult::stats)
      .def_property_readonly("spp", &PyResult::Spp)
      .def_property_readonly("width", [](const PyResult& r) { return r.film->width; })
      .def_property_readonly("height", [](const PyResult& r) { return r.film->height; })
      .def("save", &PyResult::Save, py::arg("path"))
      .def("__repr__", [](const PyResult& r) {
        return "<pathtracer.Result " + std::to_string(r.film->width) + "x" +
               std::to_string(r.film->height) + ", " + py::str(py::float_(r.Spp())).cast<std::string>() +
               " spp>";
      });
  py::class_<PyProgressive>(m, "ProgressiveRender")
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__", &PyProgressive::Next);
}

py::array_t<float> ReadImage(const py::object& path) {
  std::string file = OptionText(path);
  int width = 0, height = 0;
  std::vector<float> rgb;
  {
    py::gil_scoped_release release;
    ReadImageRgb(file, &width, &height, &rgb);
  }
  py::array_t<float> out({height, width, 3});
  std::copy(rgb.begin(), rgb.end(), out.mutable_data());
  return out;
}

}  // namespace

}  // namespace pt::python

using namespace pt;
using namespace pt::python;

PYBIND11_MODULE(pathtracer, m) {
  m.doc() = "pathtracer: render scenes from Python (docs/python.md)";
  m.attr("__version__") = PT_VERSION;
  RegisterExceptions();
  BindScene(m);
  BindResult(m);
  m.def("render", &Render, py::arg("scene"),
        "render(scene, **options) -> Result. Options are the command line's (max_depth for "
        "--max-depth), plus aovs=True (first-hit albedo, normal and depth); denoise=True adds "
        "aovs['denoised'].");
  m.def("render_progressive",
        [](py::object scene, std::optional<std::vector<uint32_t>> steps, const py::kwargs& kw) {
          return std::make_unique<PyProgressive>(std::move(scene), std::move(steps), kw);
        },
        py::arg("scene"), py::arg("steps") = py::none(),
        "render_progressive(scene, steps=None, **options): a Result after each step of samples "
        "(1, 2, 4, ... spp by default).");
  m.def("read_image", &ReadImage, py::arg("path"), "An .exr or .pfm image as float32 (H, W, 3).");
  m.def("cuda_available", [] { return CudaBackendBuilt() && CudaDeviceCount() > 0; },
        "Whether backend='cuda' can render here (built with CUDA, and a GPU present).");
}

