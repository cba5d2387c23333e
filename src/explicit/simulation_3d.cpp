#include "simulation_impl.hpp"

namespace mpm {
template class Simulation<3, LinearKernel>;
template class Simulation<3, GimpKernel>;
template class Simulation<3, WideGimpKernel>;
template class Simulation<3, QuadraticBSplineKernel>;
template class Simulation<3, CubicBSplineKernel>;
template class Simulation<3, CpdiKernel<3>>;
template class Simulation<3, Cpdi2Kernel<3>>;
}  // namespace mpm
