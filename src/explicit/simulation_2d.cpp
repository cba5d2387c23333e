#include "simulation_impl.hpp"

namespace mpm {
template class Simulation<2, LinearKernel>;
template class Simulation<2, GimpKernel>;
template class Simulation<2, QuadraticBSplineKernel>;
template class Simulation<2, CubicBSplineKernel>;
}  // namespace mpm
