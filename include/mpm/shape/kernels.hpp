#pragma once
/// One-dimensional shape-function policies. Each gives its stencil width, the ghost layers it needs, and the
/// weights and gradients of the `width` consecutive nodes starting at `base`. Positions are in grid units
/// (xi = (x - lo)/h), gradients are per grid unit; multi-D weights are tensor products.
#include <algorithm>
#include <cmath>

#include "mpm/core/types.hpp"

namespace mpm {

/// floor(v) as an int for v > -16, without a libm call on baseline x86-64. Stencil positions are in grid
/// units with particles inside the grid, so v >= -1 always holds there. Rounding in v + 16 can only overshoot
/// by one (just below an integer), which the comparison corrects.
inline int floor_index(Real v) {
  const int b = static_cast<int>(v + 16) - 16;
  return b - (v < b);
}

/// Piecewise-linear hat functions of classic MPM. Wallstedt & Guilkey 2008, Eq. (2).
struct LinearKernel {
  static constexpr int width = 2;
  static constexpr int ghost = 1;
  static constexpr const char* name = "linear";

  static int weights(Real xi, Real /*half_length*/, Real* w, Real* dw) {
    const int base = floor_index(xi);
    const Real r = xi - base;  // in [0, 1)
    w[0] = 1 - r;
    w[1] = r;
    dw[0] = -1;
    dw[1] = 1;
    return base;
  }
};

/// GIMP: the linear hat convolved with a top-hat particle of half-length l_p (in grid units, 0 < l_p <= 1/2).
/// Wallstedt & Guilkey 2008, Eqs (5) and (6), written in q = |r| as one branch-free expression:
///   S = max(0, 1 - q - v^2/(2l) + u^2/(4l)),  dS/dq = -1 + v/l + u/(2l),
///   v = max(0, l - q),  u = clamp(q - 1 + l, 0, 2l).
/// For q <= l this is 1 - (q^2 + l^2)/(2l); for l < q <= 1 - l, 1 - q; for 1 - l < q <= 1 + l,
/// (1 + l - q)^2/(4l); beyond, 0 (both corrections cannot be active at once because l <= 1/2).
struct GimpKernel {
  static constexpr int width = 3;
  static constexpr int ghost = 1;
  static constexpr const char* name = "gimp";

  /// Weight and gradient of the node at signed distance r = xi - i, for half-length l (inv_l = 1 / l).
  static void node(Real r, Real l, Real inv_l, Real& w, Real& dw) {
    const Real q = std::abs(r);
    const Real v = std::max(Real(0), l - q);
    const Real u = std::min(std::max(Real(0), q - 1 + l), 2 * l);
    w = std::max(Real(0), 1 - q - 0.5 * v * v * inv_l + 0.25 * u * u * inv_l);
    dw = std::copysign(Real(1), r) * (-1 + v * inv_l + 0.5 * u * inv_l);
  }

  static int weights(Real xi, Real half_length, Real* w, Real* dw) {
    const int base = floor_index(xi - 0.5);
    const Real inv_l = 1 / half_length;
    for (int k = 0; k < width; ++k) node(xi - (base + k), half_length, inv_l, w[k], dw[k]);
    return base;
  }
};

/// Uniform quadratic B-spline (the GIMP basis with l_p = h/2). Steffen et al. 2008, Sec. 3.3 and 4.1.
struct QuadraticBSplineKernel {
  static constexpr int width = 3;
  static constexpr int ghost = 1;
  static constexpr const char* name = "bspline2";

  static int weights(Real xi, Real /*half_length*/, Real* w, Real* dw) {
    const int base = floor_index(xi - 0.5);
    const Real r = xi - base;  // distance to the base node, in [0.5, 1.5)
    const Real a = 1.5 - r, b = r - 1, c = r - 0.5;
    w[0] = 0.5 * a * a;
    w[1] = 0.75 - b * b;
    w[2] = 0.5 * c * c;
    dw[0] = -a;
    dw[1] = -2 * b;
    dw[2] = c;
    return base;
  }
};

/// Uniform cubic B-spline. Steffen et al. 2008, Eq. (19) with four convolutions.
struct CubicBSplineKernel {
  static constexpr int width = 4;
  static constexpr int ghost = 2;
  static constexpr const char* name = "bspline3";

  static int weights(Real xi, Real /*half_length*/, Real* w, Real* dw) {
    const int base = floor_index(xi) - 1;
    const Real t = xi - (base + 1);  // in [0, 1)
    const Real s = 1 - t;
    w[0] = s * s * s / 6;
    w[1] = (3 * t * t * t - 6 * t * t + 4) / 6;
    w[2] = (3 * s * s * s - 6 * s * s + 4) / 6;
    w[3] = t * t * t / 6;
    dw[0] = -0.5 * s * s;
    dw[1] = 1.5 * t * t - 2 * t;
    dw[2] = -1.5 * s * s + 2 * s;
    dw[3] = 0.5 * t * t;
    return base;
  }
};

}  // namespace mpm
