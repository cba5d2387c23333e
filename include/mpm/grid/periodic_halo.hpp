#pragma once
/// The communication points of a grid: after P2G, the contributions that nodes outside a box's own range
/// received are added into the nodes that own them; before G2P, the owners' values are copied back out. One
/// process owns every node of a non-periodic grid, and both calls do nothing. Along a periodic axis the nodes
/// beyond the owned range [0, cells - 1] (the node on the high face and the extra layers) are images of owned
/// nodes one period away, so a periodic grid is its own halo; a distributed run adds other ranks' nodes
/// without touching the physics.
#include <cstdint>
#include <vector>

#include "mpm/grid/grid.hpp"

namespace mpm {

template <int Dim>
class PeriodicHalo {
 public:
  explicit PeriodicHalo(const GridGeometry<Dim>& g);

  /// After P2G: add the images' contributions into their owners, and give the images the sums, so that every
  /// copy of a node holds the same fields.
  void sum_into_owners(Grid<Dim>& grid, NodeFields fields) const;
  /// The same for one vector field (a re-projected momentum, a force).
  void sum_into_owners(Grid<Dim>& grid, NodeVelocity<Dim> field) const;
  /// Before G2P: copy the owners' node records to their images.
  void copy_to_ghosts(Grid<Dim>& grid) const;
  /// Call fn(image, owner) for every node that is an image of another, in flat-index order of the images.
  template <class Fn>
  void for_each_image(Fn&& fn) const {
    for (std::size_t k = 0; k < image_.size(); ++k) fn(image_[k], owner_[k]);
  }

 private:
  std::vector<std::int32_t> image_, owner_;  ///< pairs, in flat-index order of the images
};

}  // namespace mpm
