#include "simulation_impl.hpp"

namespace mpm {
template class Simulation<1, LinearKernel>;
template class Simulation<1, GimpKernel>;
template class Simulation<1, QuadraticBSplineKernel>;
template class Simulation<1, CubicBSplineKernel>;
}  // namespace mpm
