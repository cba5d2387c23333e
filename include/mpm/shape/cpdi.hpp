#pragma once
/// CPDI, the convected particle domain interpolation of Sadeghirad, Brannon & Burghardt 2011: a particle's
/// domain is the parallelogram (parallelepiped) about x_p spanned by r_k = F_p r_k^0, r_k^0 = l_p0,k e_k its
/// initial half-edges, and its function is the corners' multilinear interpolation of the grid's hats N_i:
///   S_ip = 2^-D sum_c N_i(x_c),  grad S_ip = sum_c N_i(x_c) a_c / V_p,  x_c = x_p + R s_c,
/// with R = [r_1 ... r_D], s_c in {-1, 1}^D the corner's signs and a_c / V_p = 2^-D R^-T s_c (the integral of
/// the corner function's gradient over the domain, over its volume V_p = 2^D det R). The weights are not a
/// tensor product over the axes but a sum of 2^D of them: the stencil keeps per axis the particle's place and
/// a row of R and of 2^-D R^-T, and the transfers sum the corners' products (CornerWeights) over a block of
/// 4^D nodes.
#include <array>
#include <cstdint>

#include "mpm/core/simd.hpp"
#include "mpm/core/types.hpp"

namespace mpm {

/// The cofactor matrix C of a Dim x Dim matrix A, C_ij = (-1)^(i+j) M_ij, so that A^-T = C / det A and
/// det A = sum_j A_0j C_0j; for one value or lanes.
template <int Dim, class T>
void cofactors(const T (&A)[Dim][Dim], T (&C)[Dim][Dim]) {
  if constexpr (Dim == 1) {
    C[0][0] = T{} + 1;
  } else if constexpr (Dim == 2) {
    C[0][0] = A[1][1];
    C[0][1] = -A[1][0];
    C[1][0] = -A[0][1];
    C[1][1] = A[0][0];
  } else {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        C[i][j] = A[i1][j1] * A[i2][j2] - A[i1][j2] * A[i2][j1];
      }
  }
}

/// The CPDI kernel over the linear hats, in Dim dimensions. A corner is at most one cell from the particle's
/// centre along each axis (see locate), so the nodes of a particle lie in a block of 4 per axis from base =
/// floor(xi) - 1, as the cubic B-spline's.
template <int Dim>
struct CpdiKernel {
  static constexpr int width = 4;
  static constexpr int ghost = 2;
  static constexpr int corners = 1 << Dim;
  /// The hats' gradients do not vanish with their weights at a corner, as for LinearKernel.
  static constexpr bool light_nodes_unbounded = true;
  static constexpr const char* name = "cpdi";
  template <class T>
  struct AxisOf {
    T t;       ///< the particle's centre from the base node along this axis, in cells, in [1, 2)
    T r[Dim];  ///< this axis's row of R / h: corner c is at t + sum_k s_ck r[k] from the base node
    T g[Dim];  ///< this axis's row of 2^-D (R / h)^-T: corner c's gradient weight is sum_k s_ck g[k] per cell
  };
  using Axis = AxisOf<Real>;

  /// The sign of corner c along axis k: bit k of c.
  static constexpr Real sign(int c, int k) { return (c >> k) & 1 ? 1 : -1; }

  /// The base nodes and axis data of particles at xi (in cells) with domain vectors R (in cells, R[a][k] the
  /// component a of r_k), for one particle or lanes. A domain reaching farther than one cell from its centre
  /// along some axis is scaled about the centre, its shape kept, so that this axis reaches exactly one cell
  /// (the lcrit bound of Uintah's CPDI with lcrit = 1): the weights keep the partition of unity and the
  /// linear reproduction, and the particle's volume for its stress stays V_0 det F.
  template <class T>
  static auto locate(const T (&xi)[Dim], T (&R)[Dim][Dim], AxisOf<T> (&a)[Dim]) {
    T extent{};
    for (int d = 0; d < Dim; ++d) {
      T e = simd::abs(R[d][0]);
      for (int k = 1; k < Dim; ++k) e += simd::abs(R[d][k]);
      extent = simd::max(extent, e);
    }
    const T scale = extent > 1 ? 1 / extent : T{} + 1;
    for (int d = 0; d < Dim; ++d)
      for (int k = 0; k < Dim; ++k) R[d][k] *= scale;
    T C[Dim][Dim];
    cofactors(R, C);
    T det = R[0][0] * C[0][0];
    for (int k = 1; k < Dim; ++k) det += R[0][k] * C[0][k];
    const T inv = 1 / (corners * det);  // 2^-D R^-T = C / (2^D det R)
    std::array<decltype(simd::floor_index(xi[0])), Dim> base;
    for (int d = 0; d < Dim; ++d) {
      base[d] = simd::floor_index(xi[d]) - 1;
      a[d].t = xi[d] - simd::to_real(base[d]);
      for (int k = 0; k < Dim; ++k) {
        a[d].r[k] = R[d][k];
        a[d].g[k] = C[d][k] * inv;
      }
    }
    return base;
  }

  /// CPDI of an axis-aligned box of half-length l (in cells) along one axis, the corners' trapezoid average
  /// of the hats, a tensor-product kernel: N = (N(xi - l) + N(xi + l)) / 2, dN = (N(xi + l) - N(xi - l)) / (2
  /// l). The stencils of points with half-lengths (rigid bodies) and the base nodes of the decomposition use
  /// it.
  struct Box {
    static constexpr int width = 4;
    static constexpr const char* name = "cpdi-box";
    template <class T>
    struct AxisOf {
      T t;  ///< the centre from the base node, in cells, in [1, 2)
      T l;  ///< the half-length, in cells
    };
    using Axis = AxisOf<Real>;
    template <class T>
    static auto locate(const T& xi, const T& l, AxisOf<T>& a) {
      const auto base = simd::floor_index(xi) - 1;
      a.t = xi - simd::to_real(base);
      a.l = l;
      return base;
    }
    template <class T>
    static void weights_at(const AxisOf<T>& a, T* w, T* dw) {
      for (int k = 0; k < width; ++k) {
        const T lo = hat(a.t - a.l - k), hi = hat(a.t + a.l - k);
        w[k] = 0.5 * (lo + hi);
        dw[k] = a.l > 0 ? (hi - lo) / (2 * a.l) : T{};
      }
    }
  };

  /// The hat N(u) = max(0, 1 - |u|), u in cells. Wallstedt & Guilkey 2008, Eq. (2).
  template <class T>
  static T hat(const T& u) {
    return simd::max(T{}, 1 - simd::abs(u));
  }
};

/// Whether a kernel is CPDI's (its weights a sum over a domain's corners).
template <class Kernel>
inline constexpr bool is_cpdi = requires {
  Kernel::corners;
};

namespace detail {
template <class Kernel>
struct BoxOf {
  using type = Kernel;
};
template <int Dim>
struct BoxOf<CpdiKernel<Dim>> {
  using type = typename CpdiKernel<Dim>::Box;
};
}  // namespace detail

/// The tensor-product kernel of an axis-aligned box with half-lengths l (a point of a rigid body, the
/// decomposition's base nodes): the kernel itself, or CPDI's of a box (CpdiKernel::Box), whose base node is
/// CPDI's.
template <class Kernel>
using BoxKernel = typename detail::BoxOf<Kernel>::type;

/// The weights of one particle's stencil (T = Real) or of lanes of them (T = RealLanes), for CPDI or CPDI2
/// (whose axes carry each corner's place, gradient weight and weight; shape/cpdi2.hpp): the hats of each
/// corner along each axis at the 4 nodes of the block, each corner's gradient weight a_c / V_p [1/m] and, for
/// CPDI2, its weight w_c (CPDI's are all 2^-D).
template <int Dim, class T, class Kernel = CpdiKernel<Dim>>
struct CornerWeights {
  static constexpr int C = Kernel::corners, N = Kernel::width;
  /// Whether each corner has its own weight (CPDI2's w_c).
  static constexpr bool weighted = requires(typename Kernel::Axis a) { a.w; };
  T hat[C][Dim][N], grad[C][Dim], weight[weighted ? C : 1];

  /// From the axes a[d] (Kernel::AxisOf<T>) of a stencil.
  template <class Axes>
  [[gnu::always_inline]] CornerWeights(const Axes& a, Real inv_h) {
    for (int c = 0; c < C; ++c) {
      for (int d = 0; d < Dim; ++d) {
        T t = a[d].t, g{};
        if constexpr (weighted) {
          t += a[d].x[c];
          g = a[d].g[c];
        } else {
          for (int k = 0; k < Dim; ++k) {
            t += Kernel::sign(c, k) * a[d].r[k];
            g += Kernel::sign(c, k) * a[d].g[k];
          }
        }
        for (int n = 0; n < N; ++n) hat[c][d][n] = Kernel::hat(t - n);
        grad[c][d] = g * inv_h;
      }
      if constexpr (weighted) weight[c] = a[0].w[c];
    }
  }

  /// fn(k, N) for every node of the block, k its place along each axis (axis 0 fastest) and N[c] = N_i(x_c) =
  /// prod_d hat_cd(k_d) the node's hat at each corner.
  template <class Fn>
  [[gnu::always_inline]] void visit_hats(Fn&& fn) const {
    constexpr int nodes = Dim == 1 ? N : Dim == 2 ? N * N : N * N * N;
    for (int n = 0; n < nodes; ++n) {
      int k[Dim];
      for (int d = 0, rest = n; d < Dim; ++d, rest /= N) k[d] = rest % N;
      T product[C];
      for (int c = 0; c < C; ++c) {
        product[c] = hat[c][0][k[0]];
        for (int d = 1; d < Dim; ++d) product[c] *= hat[c][d][k[d]];
      }
      fn(k, product);
    }
  }

  /// fn(k, S_ip, grad S_ip) for every node of the block, k its place along each axis (axis 0 fastest):
  /// S_ip = sum_c w_c N_i(x_c) (w_c = 2^-D for CPDI), grad S_ip = sum_c grad_c N_i(x_c).
  template <class Fn>
  [[gnu::always_inline]] void visit(Fn&& fn) const {
    visit_hats([&](const int(&k)[Dim], const T(&product)[C]) __attribute__((always_inline)) {
      T S{}, dS[Dim] = {};
      for (int c = 0; c < C; ++c) {
        if constexpr (weighted)
          S += weight[c] * product[c];
        else
          S += product[c];
        for (int d = 0; d < Dim; ++d) dS[d] += grad[c][d] * product[c];
      }
      if constexpr (!weighted) S *= Real{1} / C;
      fn(k, S, dS);
    });
  }
};

}  // namespace mpm
