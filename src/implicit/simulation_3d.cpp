// Explicit instantiation of the 3-D implicit simulation for every kernel.
#include "simulation_impl.hpp"

namespace mpm {
template class ImplicitSimulation<3, LinearKernel>;
template class ImplicitSimulation<3, GimpKernel>;
template class ImplicitSimulation<3, WideGimpKernel>;
template class ImplicitSimulation<3, QuadraticBSplineKernel>;
template class ImplicitSimulation<3, CubicBSplineKernel>;
template class ImplicitSimulation<3, CpdiKernel<3>>;
template class ImplicitSimulation<3, Cpdi2Kernel<3>>;
}  // namespace mpm
