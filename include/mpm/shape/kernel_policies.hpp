#pragma once
/// The kernel policies both engines are compiled for, in one list: the engine library holds one translation unit
/// per engine, dimension and entry (CMakeLists.txt, mpm_instantiate, whose names follow this order), and
/// with_kernel dispatches a KernelKind to its entry.
#include <cstddef>
#include <tuple>

#include "mpm/shape/cpdi.hpp"
#include "mpm/shape/cpdi2.hpp"
#include "mpm/shape/kernel_kind.hpp"
#include "mpm/shape/kernels.hpp"

namespace mpm {

template <int Dim>
using KernelPolicies = std::tuple<LinearKernel, GimpKernel, WideGimpKernel, QuadraticBSplineKernel,
                                  CubicBSplineKernel, CpdiKernel<Dim>, Cpdi2Kernel<Dim>>;

/// Entry I of KernelPolicies<Dim>.
template <int Dim, std::size_t I>
using KernelPolicy = std::tuple_element_t<I, KernelPolicies<Dim>>;

/// Call fn.template operator()<Kernel>() with the kernel policy for a kernel kind in Dim dimensions (coarse run-time
/// choice).
template <int Dim, class Fn>
decltype(auto) with_kernel(KernelKind k, Fn&& fn) {
  switch (k) {
    case KernelKind::cpdi:
      return fn.template operator()<CpdiKernel<Dim>>();
    case KernelKind::cpdi2:
      return fn.template operator()<Cpdi2Kernel<Dim>>();
    case KernelKind::linear:
      return fn.template operator()<LinearKernel>();
    case KernelKind::ugimp:
    case KernelKind::cpgimp:
      return fn.template operator()<GimpKernel>();
    case KernelKind::ugimp_wide:
    case KernelKind::cpgimp_wide:
      return fn.template operator()<WideGimpKernel>();
    case KernelKind::bspline2:
    case KernelKind::bspline2_clamped:
      return fn.template operator()<QuadraticBSplineKernel>();
    case KernelKind::bspline3:
    case KernelKind::bspline3_clamped:
      break;
  }
  return fn.template operator()<CubicBSplineKernel>();
}

}  // namespace mpm
