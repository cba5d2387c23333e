// Explicit instantiation of the 1-D implicit simulation for every kernel.
#include "simulation_impl.hpp"

namespace mpm {
template class ImplicitSimulation<1, LinearKernel>;
template class ImplicitSimulation<1, GimpKernel>;
template class ImplicitSimulation<1, WideGimpKernel>;
template class ImplicitSimulation<1, QuadraticBSplineKernel>;
template class ImplicitSimulation<1, CubicBSplineKernel>;
template class ImplicitSimulation<1, CpdiKernel<1>>;
template class ImplicitSimulation<1, Cpdi2Kernel<1>>;
}  // namespace mpm
