#pragma once
// The parts of the compiled module mpm._core, each binding one facade of the library.
#include <pybind11/pybind11.h>

namespace mpm::python {

void bind_scene(pybind11::module_& m);    ///< Scene: from_toml, from_dict (scene_dict.cpp)
void bind_session(pybind11::module_& m);  ///< Session: one scene run driven step by step (session.cpp)
void bind_study(pybind11::module_& m);    ///< verify and converge (study.cpp)

}  // namespace mpm::python
