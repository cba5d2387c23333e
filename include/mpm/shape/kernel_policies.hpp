#pragma once
/// The kernel policies both engines are compiled for, in one list: cmake/instantiate.cmake reads it to
/// generate the engine library's units (a few entries each), and with_kernel dispatches a KernelKind to the
/// entry its registry line names.
#include <cstddef>
#include <tuple>
#include <utility>

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

static_assert(
    [] {
      for (const KernelEntry& e : kernel_registry)
        if (e.policy >= std::tuple_size_v<KernelPolicies<1>>) return false;
      return true;
    }(),
    "every kernel of kernel_registry names an entry of KernelPolicies");

/// Call fn.template operator()<KernelPolicy<Dim, policy>>() (entry `policy` of KernelPolicies, I and beyond).
template <int Dim, std::size_t I = 0, class Fn>
decltype(auto) with_policy(std::size_t policy, Fn&& fn) {
  if constexpr (I + 1 < std::tuple_size_v<KernelPolicies<Dim>>)
    if (policy != I) return with_policy<Dim, I + 1>(policy, std::forward<Fn>(fn));
  return fn.template operator()<KernelPolicy<Dim, I>>();
}

/// Call fn.template operator()<Kernel>() with the kernel policy of a kernel kind in Dim dimensions (its
/// registry entry's; a coarse run-time choice).
template <int Dim, class Fn>
decltype(auto) with_kernel(KernelKind k, Fn&& fn) {
  return with_policy<Dim>(kernel_entry(k).policy, std::forward<Fn>(fn));
}

}  // namespace mpm
