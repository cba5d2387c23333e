#pragma once
/// Small fixed-size vectors and tensors used throughout the engine. Eigen's Core with LU (inverse and
/// determinant): the decompositions of <Eigen/Dense> are included only where they are used.
#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <cstdint>

namespace mpm {

using Real = double;

/// A point or vector in Dim-dimensional space.
template <int Dim>
using Vec = Eigen::Matrix<Real, Dim, 1>;

/// A second-order tensor (deformation gradient, velocity gradient).
template <int Dim>
using Mat = Eigen::Matrix<Real, Dim, Dim>;

/// Integer grid coordinates.
template <int Dim>
using IVec = std::array<int, Dim>;

/// Number of independent components of a symmetric Dim x Dim tensor.
template <int Dim>
inline constexpr int sym_size = Dim*(Dim + 1) / 2;

/// A symmetric tensor stored by its independent components: xx, yy, zz, then xy, xz, yz (2-D: xx, yy, xy).
template <int Dim>
struct SymTensor {
  std::array<Real, sym_size<Dim>> c{};

  static constexpr int index(int a, int b) {
    if (a == b) return a;
    if constexpr (Dim == 2) return 2;
    const int lo = a < b ? a : b, hi = a < b ? b : a;
    return lo == 0 ? (hi == 1 ? 3 : 4) : 5;
  }
  Real operator()(int a, int b) const { return c[index(a, b)]; }
  Real& operator()(int a, int b) { return c[index(a, b)]; }

  Mat<Dim> full() const {
    Mat<Dim> m;
    for (int a = 0; a < Dim; ++a)
      for (int b = 0; b < Dim; ++b) m(a, b) = (*this)(a, b);
    return m;
  }
};

}  // namespace mpm
