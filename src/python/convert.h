// Python values <-> the renderer's: option values as the command line's text, dicts as JSON
// text, films as numpy arrays that share the film's memory, and C++ exceptions as Python's.
#pragma once

#include <memory>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "src/integrator/render_api.h"
#include "src/io/scene_json.h"

namespace pt::python {

namespace py = pybind11;

// A keyword's value as the CLI would read it: True/False -> on/off, numbers as Python prints
// them (repr: exact), paths and strings as they are, sequences joined by commas (crop).
std::string OptionText(const py::handle& value);

// A dict (or any JSON-able value; numpy arrays and scalars included) as JSON.
std::string ToJsonText(const py::handle& value);
Json ToJson(const py::handle& value);
py::object FromJson(const nlohmann::ordered_json& json);

// One channel group of the film: float32 (H, W, C), or (H, W) when channels is 1, sharing
// `values`' memory (kept alive by `owner`). None when values is empty.
py::object FilmArray(const std::shared_ptr<FilmImage>& owner, std::vector<float>& values,
                     int channels);
py::object CountArray(const std::shared_ptr<FilmImage>& owner);

// Installs the translation of the renderer's exceptions into Python's.
void RegisterExceptions();

}  // namespace pt::python
