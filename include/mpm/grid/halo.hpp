#pragma once
/// The communication points of a grid split into boxes, one per process. They are named and called by both
/// engines in one process too, where every node is owned and there is no halo: both calls do nothing, and the
/// distributed run fills them in without touching the physics.
#include "mpm/grid/grid.hpp"

namespace mpm {

template <int Dim>
class Halo {
 public:
  /// After P2G: add the contributions the halo nodes received into their owners' nodes.
  void sum_into_owners(Grid<Dim>& /*grid*/) const {}
  /// Before G2P: copy the owners' node values to the halo nodes.
  void copy_to_ghosts(Grid<Dim>& /*grid*/) const {}
};

}  // namespace mpm
