#include "src/python/convert.h"

#include <new>

#include "src/app/app_failure.h"
#include "src/app/cli.h"
#include "src/app/run.h"
#include "src/io/image_io.h"
#include "src/io/scene_loader.h"
#include "src/scripting/script_options.h"

namespace pt::python {

std::string OptionText(const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "on" : "off";
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::int_>(value)) return py::str(value).cast<std::string>();
  if (py::isinstance<py::float_>(value)) return py::repr(value).cast<std::string>();
  if (py::hasattr(value, "__fspath__")) {
    return py::module_::import("os").attr("fspath")(value).cast<std::string>();
  }
  if (py::hasattr(value, "item") && py::hasattr(value, "dtype") &&
      py::len(value.attr("shape")) == 0) {
    return OptionText(value.attr("item")());  // a numpy scalar
  }
  if (py::isinstance<py::sequence>(value) || py::hasattr(value, "tolist")) {
    py::object list = py::hasattr(value, "tolist") ? value.attr("tolist")()
                                                   : py::reinterpret_borrow<py::object>(value);
    std::string text;
    for (py::handle item : list) text += (text.empty() ? "" : ",") + OptionText(item);
    return text;
  }
  return py::str(value).cast<std::string>();
}

std::string ToJsonText(const py::handle& value) {
  // numpy arrays and scalars through tolist()/item(); anything else json refuses (TypeError).
  py::object convert = py::cpp_function([](py::handle v) -> py::object {
    if (py::hasattr(v, "tolist")) return v.attr("tolist")();
    if (py::hasattr(v, "__fspath__")) return py::module_::import("os").attr("fspath")(v);
    throw py::type_error("a scene value of type " +
                         py::str(py::type::handle_of(v).attr("__name__")).cast<std::string>() +
                         " is not JSON (use numbers, strings, lists and dicts)");
  });
  return py::module_::import("json").attr("dumps")(value, py::arg("default") = convert,
                                                   py::arg("allow_nan") = false)
      .cast<std::string>();
}

Json ToJson(const py::handle& value) { return Json::parse(ToJsonText(value)); }

py::object FromJson(const nlohmann::ordered_json& json) {
  return py::module_::import("json").attr("loads")(json.dump());
}

namespace {

py::capsule Keeper(const std::shared_ptr<FilmImage>& owner) {
  return py::capsule(new std::shared_ptr<FilmImage>(owner), [](void* p) {
    delete static_cast<std::shared_ptr<FilmImage>*>(p);
  });
}

}  // namespace

py::object FilmArray(const std::shared_ptr<FilmImage>& owner, std::vector<float>& values,
                     int channels) {
  if (values.empty()) return py::none();
  std::vector<py::ssize_t> shape = {owner->height, owner->width};
  if (channels > 1) shape.push_back(channels);
  return py::array_t<float>(shape, values.data(), Keeper(owner));
}

py::object CountArray(const std::shared_ptr<FilmImage>& owner) {
  if (owner->samples.empty()) return py::none();
  std::vector<py::ssize_t> shape = {owner->height, owner->width};
  return py::array_t<uint32_t>(shape, owner->samples.data(), Keeper(owner));
}

void RegisterExceptions() {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const UnknownOptionError& e) {
      PyErr_SetString(PyExc_TypeError, e.what());
    } catch (const SceneError& e) {  // a bad scene: the CLI's exit status 2
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const CliError& e) {  // a bad option: the CLI's exit status 1
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const AppFailure& f) {  // the CLI's exit status and message
      PyErr_SetString(f.status == kExitRuntimeFailure ? PyExc_RuntimeError : PyExc_ValueError,
                      f.message.c_str());
    } catch (const BackendUnavailable& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    } catch (const OutOfDeviceMemory& e) {
      PyErr_SetString(PyExc_MemoryError,
                      (std::string(e.what()) + " (lower max_paths, the image size or crop)").c_str());
    } catch (const ImageError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const std::invalid_argument& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const std::logic_error& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
}

}  // namespace pt::python
