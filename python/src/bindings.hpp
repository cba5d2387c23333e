#pragma once
// The parts of the compiled module mpm._core, each binding one facade of the library.
#include <pybind11/pybind11.h>

#include <string>

namespace mpm::python {

/// A value as Python writes it, cut to 40 characters, for messages.
inline std::string short_repr(pybind11::handle v) {
  const std::string text = pybind11::repr(v);
  return text.size() > 40 ? text.substr(0, 37) + "..." : text;
}

void bind_scene(pybind11::module_& m);    ///< Scene: from_toml, from_dict (scene_dict.cpp)
void bind_session(pybind11::module_& m);  ///< Session: one scene run driven step by step (session.cpp)
void bind_study(pybind11::module_& m);    ///< verify and converge (study.cpp)

}  // namespace mpm::python
