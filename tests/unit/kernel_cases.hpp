#pragma once
// The kernel x dimension cases of the typed transfer tests, and their names in the test list.
#include <gtest/gtest.h>

#include <string>

#include "mpm/shape/cpdi2.hpp"
#include "mpm/shape/kernels.hpp"

namespace mpm::testing {

template <class K, int D>
struct KernelCase {
  using Kernel = K;
  static constexpr int dim = D;
};

/// Every kernel in 2-D and 3-D.
using KernelCases2D3D = ::testing::Types<
    KernelCase<LinearKernel, 2>, KernelCase<LinearKernel, 3>, KernelCase<GimpKernel, 2>,
    KernelCase<GimpKernel, 3>, KernelCase<QuadraticBSplineKernel, 2>, KernelCase<QuadraticBSplineKernel, 3>,
    KernelCase<CubicBSplineKernel, 2>, KernelCase<CubicBSplineKernel, 3>, KernelCase<CpdiKernel<2>, 2>,
    KernelCase<CpdiKernel<3>, 3>, KernelCase<WideGimpKernel, 2>, KernelCase<WideGimpKernel, 3>,
    KernelCase<Cpdi2Kernel<2>, 2>, KernelCase<Cpdi2Kernel<3>, 3>>;

/// Every kernel in 1-D, 2-D and 3-D.
using KernelCases1D2D3D =
    ::testing::Types<KernelCase<LinearKernel, 1>, KernelCase<LinearKernel, 2>, KernelCase<LinearKernel, 3>,
                     KernelCase<GimpKernel, 1>, KernelCase<GimpKernel, 2>, KernelCase<GimpKernel, 3>,
                     KernelCase<QuadraticBSplineKernel, 1>, KernelCase<QuadraticBSplineKernel, 2>,
                     KernelCase<QuadraticBSplineKernel, 3>, KernelCase<CubicBSplineKernel, 1>,
                     KernelCase<CubicBSplineKernel, 2>, KernelCase<CubicBSplineKernel, 3>,
                     KernelCase<CpdiKernel<1>, 1>, KernelCase<CpdiKernel<2>, 2>, KernelCase<CpdiKernel<3>, 3>,
                     KernelCase<WideGimpKernel, 1>, KernelCase<WideGimpKernel, 2>,
                     KernelCase<WideGimpKernel, 3>, KernelCase<Cpdi2Kernel<1>, 1>,
                     KernelCase<Cpdi2Kernel<2>, 2>, KernelCase<Cpdi2Kernel<3>, 3>>;

/// "bspline2_3d" and so on.
struct KernelCaseName {
  template <class C>
  static std::string GetName(int) {
    return std::string(C::Kernel::name) + "_" + std::to_string(C::dim) + "d";
  }
};

}  // namespace mpm::testing
