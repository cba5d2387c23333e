#include "simulation_impl.hpp"

namespace mpm {
template class Simulation<1, LinearKernel>;
template class Simulation<1, GimpKernel>;
template class Simulation<1, WideGimpKernel>;
template class Simulation<1, QuadraticBSplineKernel>;
template class Simulation<1, CubicBSplineKernel>;
template class Simulation<1, CpdiKernel<1>>;
template class Simulation<1, Cpdi2Kernel<1>>;
}  // namespace mpm
