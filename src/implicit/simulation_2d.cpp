// Explicit instantiation of the 2-D implicit simulation for every kernel.
#include "simulation_impl.hpp"

namespace mpm {
template class ImplicitSimulation<2, LinearKernel>;
template class ImplicitSimulation<2, GimpKernel>;
template class ImplicitSimulation<2, WideGimpKernel>;
template class ImplicitSimulation<2, QuadraticBSplineKernel>;
template class ImplicitSimulation<2, CubicBSplineKernel>;
template class ImplicitSimulation<2, CpdiKernel<2>>;
template class ImplicitSimulation<2, Cpdi2Kernel<2>>;
}  // namespace mpm
