#pragma once
/// One-dimensional shape-function policies. Each gives its stencil width, the ghost layers it needs, what a
/// stencil keeps per axis (`Axis`: as little as reproduces the weights cheaply), `locate` (base node and
/// Axis data of a position) and `weights_at` (weights and gradients of the `width` consecutive nodes starting
/// at the base). Positions are in grid units (xi = (x - lo)/h), gradients per grid unit; multi-D weights are
/// tensor products. `Axis` is `AxisOf<Real>`; `weights_at` also takes `AxisOf<simd::RealLanes>`, whose
/// members are the same Reals of several particles in SIMD lanes (LaneStencil).
#include <algorithm>
#include <cmath>

#include "mpm/core/simd.hpp"
#include "mpm/core/types.hpp"

namespace mpm {

/// Adds `weights(xi, half_length, w, dw)` (locate, then weights_at) to a kernel policy.
template <class Kernel>
struct KernelWeights {
  static int weights(Real xi, Real half_length, Real* w, Real* dw) {
    typename Kernel::Axis a;
    const int base = Kernel::locate(xi, half_length, a);
    Kernel::weights_at(a, w, dw);
    return base;
  }
};

/// The Axis of a kernel whose stencil keeps its `Width` weights and gradients (GIMP's, costly to evaluate),
/// and their weights_at.
template <int Width>
struct StoredWeights {
  template <class T>
  struct AxisOf {
    T w[Width], dw[Width];
  };
  using Axis = AxisOf<Real>;
  template <class T>
  static void weights_at(const AxisOf<T>& a, T* w, T* dw) {
    for (int k = 0; k < Width; ++k) {
      w[k] = a.w[k];
      dw[k] = a.dw[k];
    }
  }
};

/// Piecewise-linear hat functions of classic MPM. Wallstedt & Guilkey 2008, Eq. (2).
struct LinearKernel : KernelWeights<LinearKernel> {
  static constexpr int width = 2;
  static constexpr int ghost = 1;
  /// The hat's gradient does not vanish at the edge of its support, so a node that a particle barely reaches
  /// (weight S_ip -> 0) gets an acceleration f_i / m_i ~ 1 / S_ip whose gradient term dt a_i (x) grad S_ip is
  /// unbounded (Wallstedt & Guilkey 2008, Eq. (39)). GIMP and B-spline gradients vanish with the weight, so
  /// |grad S|^2 / S stays bounded and they need no treatment of light nodes.
  static constexpr bool light_nodes_unbounded = true;
  static constexpr const char* name = "linear";
  template <class T>
  struct AxisOf {
    T r;  ///< offset from the base node, in [0, 1)
  };
  using Axis = AxisOf<Real>;

  template <class T>
  static auto locate(const T& xi, const T& /*half_length*/, AxisOf<T>& a) {
    const auto base = simd::floor_index(xi);
    a.r = xi - simd::to_real(base);
    return base;
  }
  template <class T>
  static void weights_at(const AxisOf<T>& a, T* w, T* dw) {
    w[0] = 1 - a.r;
    w[1] = a.r;
    dw[0] = T{} - 1;
    dw[1] = T{} + 1;
  }
};

/// GIMP: the linear hat convolved with a top-hat particle of half-length l_p (in grid units, 0 < l_p <= 1/2).
/// Wallstedt & Guilkey 2008, Eq. (5), Eq. (6), written in q = |r| with r = xi - x_i:
///   S = max(0, 1 - q - v^2/(2l) + u^2/(4l)),  dS/dq = -1 + v/l + u/(2l),
///   v = max(0, l - q),  u = clamp(q - 1 + l, 0, 2l).
/// For q <= l this is 1 - (q^2 + l^2)/(2l); for l < q <= 1 - l, 1 - q; for 1 - l < q <= 1 + l,
/// (1 + l - q)^2/(4l); beyond, 0. With the base node at distance r in [1/2, 3/2), the outer two nodes have
/// q >= 1/2 >= l (no v term) and the middle one q <= 1/2 <= 1 - l (no u term).
struct GimpKernel : KernelWeights<GimpKernel>, StoredWeights<3> {
  static constexpr int width = 3;
  static constexpr int ghost = 1;
  static constexpr Real max_half_length = 0.5;  ///< in cells: the support h + l_p then spans 3 nodes
  static constexpr const char* name = "gimp";

  template <class T>
  static auto locate(const T& xi, const T& l, AxisOf<T>& a) {
    const auto base = simd::floor_index(xi - 0.5);
    const T inv_l = 1 / l;
    // Outer nodes: q = r (base) and q = 2 - r (base + 2), tail correction u only.
    auto outer = [&](const T& q, T& w, T& dS_dq) {
      const T u = simd::min(simd::max(T{}, q - 1 + l), 2 * l);
      w = simd::max(T{}, 1 - q + 0.25 * u * u * inv_l);
      dS_dq = -1 + 0.5 * u * inv_l;
    };
    const T r = xi - simd::to_real(base);
    T dS_dq;
    outer(r, a.w[0], dS_dq);
    a.dw[0] = dS_dq;  // r > 0
    outer(2 - r, a.w[2], dS_dq);
    a.dw[2] = -dS_dq;  // r - 2 < 0
    // Middle node: r - 1 in [-1/2, 1/2), centre correction v only.
    const T r1 = r - 1, q1 = simd::abs(r1);
    const T v = simd::max(T{}, l - q1);
    a.w[1] = 1 - q1 - 0.5 * v * v * inv_l;
    a.dw[1] = simd::copysign(1 - v * inv_l, -r1);  // sign(r1) dS/dq, and dS/dq = -1 + v/l <= 0
    return base;
  }
};

/// GIMP for half-lengths up to a cell, 0 < l_p <= 1 (grid units): the support |x_p - x_i| < h + l_p then
/// spans 4 nodes from base = floor(xi) - 1. Wallstedt & Guilkey 2008, Eq. (5), Eq. (6) set no bound on l_p;
/// their closed form in q = |r| holds for every node and every l_p <= 1 once both corrections are kept,
///   S = max(0, 1 - q - v^2/(2l) + u^2/(4l)),  dS/dq = -1 + v/l + u/(2l),
///   v = max(0, l - q),  u = clamp(q - 1 + l, 0, 2l)
/// (the hat integrated over [q - l, q + l] as 1 - |s| plus its excess (|s| - 1)_+ beyond a cell; the excess
/// below -1 needs q < l - 1 <= 0). It is GimpKernel's weights on a stencil one node wider.
struct WideGimpKernel : KernelWeights<WideGimpKernel>, StoredWeights<4> {
  static constexpr int width = 4;
  static constexpr int ghost = 2;
  static constexpr Real max_half_length = 1;  ///< in cells
  static constexpr const char* name = "gimp-wide";

  template <class T>
  static auto locate(const T& xi, const T& l, AxisOf<T>& a) {
    const auto base = simd::floor_index(xi) - 1;
    const T inv_l = 1 / l, r = xi - simd::to_real(base);  // r in [1, 2)
    for (int k = 0; k < width; ++k) {
      const T rk = r - k, q = simd::abs(rk);
      const T v = simd::max(T{}, l - q), u = simd::min(simd::max(T{}, q - 1 + l), 2 * l);
      a.w[k] = simd::max(T{}, 1 - q - 0.5 * v * v * inv_l + 0.25 * u * u * inv_l);
      a.dw[k] = simd::copysign(1 - v * inv_l - 0.5 * u * inv_l, -rk);  // sign(r_k) dS/dq, and dS/dq <= 0
    }
    return base;
  }
};

/// Uniform quadratic B-spline (the GIMP basis with l_p = h/2). Steffen et al. 2008, Sec. 3.3 and 4.1.
struct QuadraticBSplineKernel : KernelWeights<QuadraticBSplineKernel> {
  static constexpr int width = 3;
  static constexpr int ghost = 1;
  static constexpr const char* name = "bspline2";
  template <class T>
  struct AxisOf {
    T r;  ///< distance to the base node, in [0.5, 1.5)
  };
  using Axis = AxisOf<Real>;

  template <class T>
  static auto locate(const T& xi, const T& /*half_length*/, AxisOf<T>& ax) {
    const auto base = simd::floor_index(xi - 0.5);
    ax.r = xi - simd::to_real(base);
    return base;
  }
  /// Move the base node by `shift` nodes (a clamped face, stencil.hpp's locate_axis): r stays the distance to
  /// it.
  template <class T>
  static void rebase(AxisOf<T>& ax, const T& shift) {
    ax.r += shift;
  }
  template <class T>
  static void weights_at(const AxisOf<T>& ax, T* w, T* dw) {
    const T r = ax.r;
    const T a = 1.5 - r, b = r - 1, c = r - 0.5;
    w[0] = 0.5 * a * a;
    w[1] = 0.75 - b * b;
    w[2] = 0.5 * c * c;
    dw[0] = -a;
    dw[1] = -2 * b;
    dw[2] = c;
    // Clamped knots (Steffen et al. 2008, Sec. 4.3): within half a cell of a clamped face the base node is
    // the face's (r < 1/2 at a lower face, r > 3/2 at an upper one), and the ghost node's function is folded
    // into the face's two nodes by linear extrapolation, N_0 + 2 N_-1 and N_1 - N_-1: there the basis is the
    // hat.
    const auto lower = r<0.5, upper = r> 1.5;
    const T zero{}, one = zero + 1;
    w[0] = lower ? 1 - r : upper ? zero : w[0];
    w[1] = lower ? r : upper ? 2 - r : w[1];
    w[2] = lower ? zero : upper ? r - 1 : w[2];
    dw[0] = lower ? -one : upper ? zero : dw[0];
    dw[1] = lower ? one : upper ? -one : dw[1];
    dw[2] = lower ? zero : upper ? one : dw[2];
  }
};

/// Uniform cubic B-spline. Steffen et al. 2008, Eq. (19) with four convolutions.
struct CubicBSplineKernel : KernelWeights<CubicBSplineKernel> {
  static constexpr int width = 4;
  static constexpr int ghost = 2;
  static constexpr const char* name = "bspline3";
  template <class T>
  struct AxisOf {
    T t;  ///< offset from the second node of the stencil, in [0, 1)
  };
  using Axis = AxisOf<Real>;

  template <class T>
  static auto locate(const T& xi, const T& /*half_length*/, AxisOf<T>& a) {
    const auto base = simd::floor_index(xi) - 1;
    a.t = xi - simd::to_real(base + 1);
    return base;
  }
  /// Move the base node by `shift` nodes (a clamped face, stencil.hpp's locate_axis).
  template <class T>
  static void rebase(AxisOf<T>& a, const T& shift) {
    a.t += shift;
  }
  template <class T>
  static void weights_at(const AxisOf<T>& a, T* w, T* dw) {
    const T t = a.t;
    const T s = 1 - t;
    w[0] = s * s * s / 6;
    w[1] = (3 * t * t * t - 6 * t * t + 4) / 6;
    w[2] = (3 * s * s * s - 6 * s * s + 4) / 6;
    w[3] = t * t * t / 6;
    dw[0] = -0.5 * s * s;
    dw[1] = 1.5 * t * t - 2 * t;
    dw[2] = -1.5 * s * s + 2 * s;
    dw[3] = 0.5 * t * t;
    // Clamped knots (Steffen et al. 2008, Sec. 4.3): within a cell of a clamped face the base node is the
    // face's (t < 0 at a lower face, t > 1 at an upper one), and the ghost node's function is folded into the
    // face's two nodes by linear extrapolation, N_0 + 2 N_-1 and N_1 - N_-1. With q the distance to the face
    // in cells: N_0 = 1 - q + q^3/6, N_1 = q - q^3/3, N_2 = q^3/6, the natural cubic spline's end (N'' = 0 on
    // the face).
    const auto lower = t<0, upper = t> 1;
    const T q = lower ? t + 1 : 2 - t, q2 = q * q, q3 = q2 * q;
    const T zero{}, end = 1 - q + q3 / 6, next = q - q3 / 3, third = q3 / 6;
    const T d_end = 0.5 * q2 - 1, d_next = 1 - q2, d_third = 0.5 * q2;  // d/dq
    w[0] = lower ? end : upper ? zero : w[0];
    w[1] = lower ? next : upper ? third : w[1];
    w[2] = lower ? third : upper ? next : w[2];
    w[3] = lower ? zero : upper ? end : w[3];
    dw[0] = lower ? d_end : upper ? zero : dw[0];  // dq/dxi = +1 at a lower face, -1 at an upper one
    dw[1] = lower ? d_next : upper ? -d_third : dw[1];
    dw[2] = lower ? d_third : upper ? -d_next : dw[2];
    dw[3] = lower ? zero : upper ? -d_end : dw[3];
  }
};

}  // namespace mpm
