#pragma once
/// CPDI2 (Sadeghirad, Brannon & Guilkey 2013): the particle's domain is the quadrilateral (2-D) or hexahedron
/// (3-D) spanned by its 2^D corners, which move with the grid velocity; its function is the corners'
/// multilinear interpolation of the grid's hats over that domain:
///   S_ip = sum_c w_c N_i(x_c),  grad S_ip = sum_c g_c N_i(x_c),
///   w_c = (1/V) int M_c dV,  g_c = (1/V) int grad M_c dV,  V = int dV,
/// M_c the corner's multilinear function of the reference cube [-1, 1]^D mapped onto the domain. With the
/// Jacobian J of that map, M_c det J and cof(J) grad_xi M_c (cof(J) = det J J^-T) are polynomials of degree
/// at most 3 in each reference coordinate, so the 2^D-point Gauss rule (points +-1/sqrt 3) integrates them
/// exactly; no inverse is needed. Corner c sits at reference signs s_ck = bit k of c (CpdiKernel::sign). The
/// corners move with the grid velocity, x_c += dt sum_i N_i(x_c) v_i (Sadeghirad et al. 2013; the transfer's
/// g2p_corners), and the particle sits at its domain's centroid sum_c w_c x_c, where the weights' first
/// moments put it (sum_i S_ip x_i = sum_c w_c x_c): its position follows the corners, not the other way.
#include <cmath>

#include "mpm/core/types.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/cpdi.hpp"

namespace mpm {

/// The weights w_c, gradient weights g_c (per unit of the corners' coordinates) and volume V of the domain
/// spanned by corners x[c][d], for one domain (T = Real) or lanes of them.
template <int Dim, class T>
struct CornerDomain {
  static constexpr int C = 1 << Dim;
  T w[C], g[C][Dim], V;

  explicit CornerDomain(const T (&x)[C][Dim]) {
    const Real a = 1 / std::sqrt(Real{3});  // the 2-point Gauss abscissa; both weights 1
    V = T{};
    for (int c = 0; c < C; ++c) {
      w[c] = T{};
      for (int d = 0; d < Dim; ++d) g[c][d] = T{};
    }
    for (int q = 0; q < C; ++q) {  // Gauss point q at reference a s_q
      Real xi[Dim], M[C], dM[C][Dim];
      for (int k = 0; k < Dim; ++k) xi[k] = a * CpdiKernel<Dim>::sign(q, k);
      for (int c = 0; c < C; ++c) {
        M[c] = 1;
        for (int k = 0; k < Dim; ++k) M[c] *= 0.5 * (1 + CpdiKernel<Dim>::sign(c, k) * xi[k]);
        for (int k = 0; k < Dim; ++k) {
          dM[c][k] = 0.5 * CpdiKernel<Dim>::sign(c, k);
          for (int j = 0; j < Dim; ++j)
            if (j != k) dM[c][k] *= 0.5 * (1 + CpdiKernel<Dim>::sign(c, j) * xi[j]);
        }
      }
      T J[Dim][Dim];  // J[d][k] = d x_d / d xi_k
      for (int d = 0; d < Dim; ++d)
        for (int k = 0; k < Dim; ++k) {
          J[d][k] = T{};
          for (int c = 0; c < C; ++c) J[d][k] += dM[c][k] * x[c][d];
        }
      T cof[Dim][Dim];
      cofactors(J, cof);
      T det = J[0][0] * cof[0][0];
      for (int k = 1; k < Dim; ++k) det += J[0][k] * cof[0][k];
      V += det;
      for (int c = 0; c < C; ++c) {
        w[c] += M[c] * det;
        for (int d = 0; d < Dim; ++d)
          for (int k = 0; k < Dim; ++k) g[c][d] += cof[d][k] * dM[c][k];  // (det J J^-T grad_xi M_c)_d
      }
    }
    const T inv_V = 1 / V;
    for (int c = 0; c < C; ++c) {
      w[c] *= inv_V;
      for (int d = 0; d < Dim; ++d) g[c][d] *= inv_V;
    }
  }
};

/// The CPDI2 kernel over the linear hats, in Dim dimensions: CPDI's block of 4 nodes per axis from floor(xi)
/// - 1 (CpdiKernel), with the domain given by its stored corners instead of F_p diag(l_p0).
template <int Dim>
struct Cpdi2Kernel {
  static constexpr int width = 4;
  static constexpr int ghost = 2;
  static constexpr int corners = 1 << Dim;
  static constexpr bool light_nodes_unbounded = true;
  static constexpr const char* name = "cpdi2";
  template <class T>
  struct AxisOf {
    T t;           ///< the particle's centre from the base node along this axis, in cells, in [1, 2)
    T x[corners];  ///< each corner's place from the centre along this axis, in cells
    T g[corners];  ///< each corner's gradient weight g_c along this axis, per cell
    T w[corners];  ///< each corner's weight w_c (the same on every axis)
  };
  using Axis = AxisOf<Real>;

  static constexpr Real sign(int c, int k) { return CpdiKernel<Dim>::sign(c, k); }
  template <class T>
  static T hat(const T& u) {
    return CpdiKernel<Dim>::hat(u);
  }

  /// The base nodes and axis data of particles at xi (in cells) whose corners are X[c][d] cells from them,
  /// for one particle or lanes. A corner farther than one cell from the centre along some axis scales the
  /// domain about the centre for the weights, as CpdiKernel::locate (lcrit = 1): w_c is unchanged, g_c scales
  /// inversely, and the stored corners keep moving with the grid.
  template <class T>
  static auto locate(const T (&xi)[Dim], T (&X)[corners][Dim], AxisOf<T> (&a)[Dim]) {
    T extent{};
    for (int c = 0; c < corners; ++c)
      for (int d = 0; d < Dim; ++d) extent = simd::max(extent, simd::abs(X[c][d]));
    const T scale = extent > 1 ? 1 / extent : T{} + 1;
    for (int c = 0; c < corners; ++c)
      for (int d = 0; d < Dim; ++d) X[c][d] *= scale;
    const CornerDomain<Dim, T> domain(X);
    std::array<decltype(simd::floor_index(xi[0])), Dim> base;
    for (int d = 0; d < Dim; ++d) {
      base[d] = simd::floor_index(xi[d]) - 1;
      a[d].t = xi[d] - simd::to_real(base[d]);
      for (int c = 0; c < corners; ++c) {
        a[d].x[c] = X[c][d];
        a[d].g[c] = domain.g[c][d];
        a[d].w[c] = domain.w[c];
      }
    }
    return base;
  }
};

/// Whether a kernel's domain is its stored corners (CPDI2's), moved with the grid velocity.
template <class Kernel>
inline constexpr bool moves_corners = false;
template <int Dim>
inline constexpr bool moves_corners<Cpdi2Kernel<Dim>> = true;

namespace detail {
template <int Dim>
struct BoxOf<Cpdi2Kernel<Dim>> {  // an axis-aligned box's CPDI2 domain is CPDI's
  using type = typename CpdiKernel<Dim>::Box;
};
}  // namespace detail

/// The smallest Jacobian determinant det(d x / d xi) of the domain's map at its corners, for one domain or
/// lanes: positive at every corner for a domain that is not folded (in 2-D: a convex quadrilateral, its
/// corners in the order of the reference square's).
template <int Dim, class T>
T min_corner_jacobian(const T (&x)[1 << Dim][Dim]) {
  constexpr int C = 1 << Dim;
  T least{};
  for (int q = 0; q < C;
       ++q) {  // at corner q, d x / d xi_k is half the edge from its neighbour across axis k
    T J[Dim][Dim];
    for (int k = 0; k < Dim; ++k) {
      const int other = q ^ (1 << k);
      for (int d = 0; d < Dim; ++d) J[d][k] = 0.5 * CpdiKernel<Dim>::sign(q, k) * (x[q][d] - x[other][d]);
    }
    T cof[Dim][Dim];
    cofactors(J, cof);
    T det = J[0][0] * cof[0][0];
    for (int k = 1; k < Dim; ++k) det += J[0][k] * cof[0][k];
    least = q == 0 ? det : simd::min(least, det);
  }
  return least;
}

/// The centroid sum_c w_c x_c of corners x_c, for one domain (T = Real) or lanes of them, taken about `near`
/// (a point close to them, for the rounding), and whether the domain is unfolded (min_corner_jacobian > 0).
template <int Dim, class T>
[[gnu::always_inline]] inline auto corner_centroid(const T (&x)[1 << Dim][Dim], const T (&near)[Dim],
                                                   T (&centroid)[Dim]) {
  T offset[1 << Dim][Dim];
  for (int c = 0; c < (1 << Dim); ++c)
    for (int d = 0; d < Dim; ++d) offset[c][d] = x[c][d] - near[d];
  const CornerDomain<Dim, T> domain(offset);
  for (int d = 0; d < Dim; ++d) {
    centroid[d] = near[d];
    for (int c = 0; c < (1 << Dim); ++c) centroid[d] += domain.w[c] * offset[c][d];
  }
  return min_corner_jacobian<Dim>(offset) > 0;
}

/// The corners of particles whose domains are their CPDI parallelograms x_p + F_p diag(l_p0) s_c (Sadeghirad
/// et al. 2011), where a CPDI2 run starts: its seeded particles, undeformed, are their GIMP boxes.
template <int Dim>
void place_corners(ParticleSet<Dim>& p) {
  p.corners.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Mat<Dim> R = p.F[i] * p.l0[i].asDiagonal();
    for (int c = 0; c < (1 << Dim); ++c) {
      Vec<Dim> s;
      for (int k = 0; k < Dim; ++k) s[k] = CpdiKernel<Dim>::sign(c, k);
      p.corners[i].col(c) = p.x[i] + R * s;
    }
  }
}

}  // namespace mpm
