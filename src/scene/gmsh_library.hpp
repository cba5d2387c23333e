#pragma once
// Gmsh, loaded from its shared library when a scene first reads a mesh: linked, it and the ~80 libraries it
// needs would load into every run of the program and every Python import (45 MB more resident memory and
// 0.14 s more at each start, measured). Wraps the few calls of Gmsh's C API that read a mesh.
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mpm::scene_reading {

/// Gmsh could not be loaded, or a call failed: what Gmsh said.
struct GmshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One Gmsh session (Gmsh's state is global: one at a time; a file Gmsh failed on leaves its session
/// unusable, so each file gets its own), silent on the terminal. Every call throws GmshError on failure.
class GmshSession {
 public:
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

  void open(const std::string& file) const;
  /// (dim, tag) of the model's entities, or physical groups, of dimension `dim`.
  std::vector<std::pair<int, int>> entities(int dim) const;
  std::vector<std::pair<int, int>> physical_groups(int dim) const;
  std::string physical_name(int dim, int tag) const;
  std::vector<int> physical_groups_of_entity(int dim, int tag) const;
  std::vector<int> element_types(int dim, int tag) const;
  /// The element type's name, e.g. "Triangle 3".
  std::string element_name(int type) const;
  /// Gmsh's integration rule `rule` (e.g. "Gauss2") on the element type: local coordinates (3 per point) and
  /// weights.
  std::pair<std::vector<double>, std::vector<double>> integration_points(int type,
                                                                         const std::string& rule) const;
  /// The Jacobian determinants and positions (3 per point) at the local points of every element of the type
  /// on entity `tag`, element by element.
  std::pair<std::vector<double>, std::vector<double>> jacobians(int type, std::vector<double> local,
                                                                int tag) const;
  /// The tags of the elements of the type on entity `tag`, in the order `jacobians` gives them.
  std::vector<std::size_t> elements(int type, int tag) const;
};

}  // namespace mpm::scene_reading
