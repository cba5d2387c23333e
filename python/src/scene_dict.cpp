// mpm.Scene: a scene read from a TOML file or built from a dict, with the reader's keys and checks.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <toml++/toml.h>

#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "bindings.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/scene/scene.hpp"

namespace py = pybind11;

namespace mpm::python {

namespace {

/// The deepest a dict or list may nest, as the scene reader's keys may (src/scene/section.hpp,
/// max_key_depth): a dict that contains itself, or one nested thousands deep, is refused instead of
/// overflowing the stack.
constexpr int max_depth = 64;

toml::array to_array(py::handle seq, const std::string& key, int depth);

toml::table to_table(py::handle dict, const std::string& key, int depth);

/// A Python value at nesting `depth` as a TOML value: bool, integer, float, str, a sequence (array) or a dict
/// (table). `key` names it in the ValueError for anything else.
template <class Put>
void put_value(py::handle v, const std::string& key, int depth, Put&& put) {
  if (depth > max_depth)
    throw InputError(key.substr(0, 200) + (key.size() > 200 ? "...: " : ": ") + "nested deeper than " +
                     std::to_string(max_depth) + " levels (a dict or list that contains itself?)");
  if (py::isinstance<py::bool_>(v)) return put(v.cast<bool>());
  if (py::isinstance<py::str>(v)) return put(v.cast<std::string>());
  if (py::isinstance<py::dict>(v)) return put(to_table(v, key, depth + 1));
  if (py::isinstance<py::float_>(v)) return put(v.cast<double>());
  if (py::hasattr(v, "__index__")) {  // int, numpy's integers
    try {
      return put(v.cast<std::int64_t>());
    } catch (const py::cast_error&) {
      throw InputError(key + ": expected an integer of at most 64 bits (|n| < 9.2e18), got " + short_repr(v));
    }
  }
  if (py::hasattr(v, "__float__")) return put(v.cast<double>());  // numpy's floats
  if (py::isinstance<py::sequence>(v)) return put(to_array(v, key, depth + 1));
  throw InputError(key + ": expected a number, string, list or dict, got a value of type " +
                   std::string(py::str(v.get_type().attr("__name__"))));
}

toml::array to_array(py::handle seq, const std::string& key, int depth) {
  toml::array out;
  std::size_t k = 0;
  for (py::handle item : seq)
    put_value(item, key + "[" + std::to_string(k++) + "]", depth,
              [&](auto&& value) { out.push_back(std::move(value)); });
  return out;
}

toml::table to_table(py::handle dict, const std::string& key, int depth) {
  toml::table out;
  for (auto [k, v] : py::reinterpret_borrow<py::dict>(dict)) {
    if (!py::isinstance<py::str>(k)) throw InputError(key + ": expected string keys");
    const std::string name = k.cast<std::string>();
    put_value(v, key.empty() ? name : key + "." + name, depth,
              [&](auto&& value) { out.insert(name, std::move(value)); });
  }
  return out;
}

/// A Python value in TOML syntax, as one would write it after --set: 0.5, "usl", [20, 20], { E = 1e7 }.
std::string toml_text(py::handle v, const std::string& key) {
  std::string out;
  put_value(v, key, 0, [&](auto&& value) {
    using T = std::decay_t<decltype(value)>;
    if constexpr (std::is_same_v<T, bool>) {
      out = value ? "true" : "false";
    } else if constexpr (std::is_same_v<T, std::string>) {
      out = "\"";
      for (const char c : value) out += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
      out += "\"";
    } else if constexpr (std::is_same_v<T, toml::table>) {
      out = "{ ";
      bool first = true;
      for (auto [k, item] : py::reinterpret_borrow<py::dict>(v)) {
        out += (first ? "" : ", ") + std::string(py::str(k)) + " = " +
               toml_text(item, key + "." + std::string(py::str(k)));
        first = false;
      }
      out += " }";
    } else if constexpr (std::is_same_v<T, toml::array>) {
      out = "[";
      std::size_t k = 0;
      for (py::handle item : v) {
        if (k > 0) out += ", ";
        out += toml_text(item, key + "[" + std::to_string(k) + "]");
        ++k;
      }
      out += "]";
    } else {
      out = py::str(py::repr(py::float_(static_cast<double>(value))));  // the shortest exact text of a float
      if constexpr (std::is_integral_v<T>) out = std::to_string(value);
    }
  });
  return out;
}

/// "key.path=value" assignments (the command's --set) with the values in TOML syntax.
std::vector<std::string> assignments(const py::dict& overrides) {
  std::vector<std::string> out;
  for (auto [k, v] : overrides) {
    const std::string key = py::str(k);
    out.push_back(key + "=" + toml_text(v, key));
  }
  return out;
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene")
      .def_static(
          "from_toml",
          [](const std::filesystem::path& path, const py::dict& overrides) {
            return std::make_shared<Scene>(read_scene(path, assignments(overrides)));
          },
          py::arg("path"), py::arg("overrides") = py::dict())
      .def_static(
          "from_dict",
          [](const py::dict& scene, const std::string& name, const py::dict& overrides) {
            std::ostringstream text;
            text << toml::toml_formatter(to_table(scene, "", 0));
            return std::make_shared<Scene>(read_scene_text(text.str(), name, assignments(overrides)));
          },
          py::arg("scene"), py::arg("name") = "<dict>", py::arg("overrides") = py::dict())
      .def_property_readonly("dim", [](const Scene& s) { return s.dim; })
      .def_property_readonly("end_time", [](const Scene& s) { return s.end_time; })
      .def_property_readonly("file", [](const Scene& s) { return s.file.string(); })
      .def_property_readonly("text", [](const Scene& s) { return s.text; });
}

}  // namespace mpm::python
