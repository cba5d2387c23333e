#include "mpm/grid/periodic_halo.hpp"

namespace mpm {

template <int Dim>
PeriodicHalo<Dim>::PeriodicHalo(const GridGeometry<Dim>& g) {
  bool any = false;
  for (int d = 0; d < Dim; ++d) any = any || g.periodic[d];
  if (!any) return;
  const auto count = static_cast<std::ptrdiff_t>(g.node_count());
  for (std::ptrdiff_t f = 0; f < count; ++f) {
    IVec<Dim> i = g.coords(f);
    bool image = false;
    for (int d = 0; d < Dim; ++d)
      if (g.periodic[d] && (i[d] < 0 || i[d] >= g.cells[d])) {
        i[d] = ((i[d] % g.cells[d]) + g.cells[d]) % g.cells[d];
        image = true;
      }
    if (image) {
      image_.push_back(static_cast<std::int32_t>(f));
      owner_.push_back(static_cast<std::int32_t>(g.flat(i)));
    }
  }
}

template <int Dim>
void PeriodicHalo<Dim>::sum_into_owners(Grid<Dim>& grid, NodeFields fields) const {
  if (fields == NodeFields::force) return sum_into_owners(grid, &GridNode<Dim>::a);
  for (std::size_t k = 0; k < image_.size(); ++k) grid.nodes[owner_[k]].m += grid.nodes[image_[k]].m;
  for (std::size_t k = 0; k < image_.size(); ++k) grid.nodes[image_[k]].m = grid.nodes[owner_[k]].m;
  sum_into_owners(grid, &GridNode<Dim>::v);
}

template <int Dim>
void PeriodicHalo<Dim>::sum_into_owners(Grid<Dim>& grid, NodeVelocity<Dim> field) const {
  // Each image adds into its owner in flat-index order, whatever the thread count: the sums are
  // deterministic.
  for (std::size_t k = 0; k < image_.size(); ++k)
    grid.nodes[owner_[k]].*field += grid.nodes[image_[k]].*field;
  for (std::size_t k = 0; k < image_.size(); ++k) grid.nodes[image_[k]].*field = grid.nodes[owner_[k]].*field;
}

template <int Dim>
void PeriodicHalo<Dim>::copy_to_ghosts(Grid<Dim>& grid) const {
  for (std::size_t k = 0; k < image_.size(); ++k) grid.nodes[image_[k]] = grid.nodes[owner_[k]];
}

template class PeriodicHalo<1>;
template class PeriodicHalo<2>;
template class PeriodicHalo<3>;

}  // namespace mpm
