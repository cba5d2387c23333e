#include "simulation_impl.hpp"

namespace mpm {
template class Simulation<2, LinearKernel>;
template class Simulation<2, GimpKernel>;
template class Simulation<2, WideGimpKernel>;
template class Simulation<2, QuadraticBSplineKernel>;
template class Simulation<2, CubicBSplineKernel>;
template class Simulation<2, CpdiKernel<2>>;
template class Simulation<2, Cpdi2Kernel<2>>;
}  // namespace mpm
