#pragma once
/// Memory of an engine as a linear model in its particle and node counts, taken from the sizes of the arrays
/// it allocates, so that a run's memory can be estimated before anything large is allocated.
namespace mpm {

struct MemoryModel {
  double per_particle = 0;  ///< bytes per particle [B]
  double per_node = 0;      ///< bytes per grid node, ghost layers included [B]
  double bytes(double particles, double nodes) const { return per_particle * particles + per_node * nodes; }
};

}  // namespace mpm
