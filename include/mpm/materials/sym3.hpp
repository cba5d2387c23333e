#pragma once
/// Symmetric 3 x 3 tensors for any number type T: one particle (Real) or several in SIMD lanes
/// (simd::RealLanes), with the same operations in the same order, hence the same bits. The rate-form step's
/// pieces that the explicit engine's G2P evaluates in lanes are written once on it (the Hughes-Winget
/// rotation, the hypoelastic trial stress, the contractions).
#include <array>

#include "mpm/core/simd.hpp"
#include "mpm/core/types.hpp"

namespace mpm {

/// Components in SymTensor<3> order: xx, yy, zz, xy, xz, yz.
template <class T>
struct Sym3 {
  std::array<T, 6> c{};

  T& operator()(int a, int b) { return c[SymTensor<3>::index(a, b)]; }
  const T& operator()(int a, int b) const { return c[SymTensor<3>::index(a, b)]; }
};

/// The upper triangle of a symmetric 3 x 3 matrix, and the matrix of one.
inline Sym3<Real> sym3_of(const Mat<3>& m) {
  Sym3<Real> s;
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) s(a, b) = m(a, b);
  return s;
}
inline Mat<3> full(const Sym3<Real>& s) {
  Mat<3> m;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) m(a, b) = s(a, b);
  return m;
}

/// tr a = (a_xx + a_yy) + a_zz.
template <class T>
[[gnu::always_inline]] inline T trace(const Sym3<T>& a) {
  return a.c[0] + a.c[1] + a.c[2];
}

/// a - tr(a) / 3 I. Sulsky & Kaul 2004, Eq. (2.1.17).
template <class T>
[[gnu::always_inline]] inline Sym3<T> deviator(const Sym3<T>& a) {
  const T p = trace(a) / 3;
  Sym3<T> s = a;
  for (int k = 0; k < 3; ++k) s.c[k] = a.c[k] - p;
  return s;
}

/// a : b over all nine components (the off-diagonal ones twice).
template <class T>
[[gnu::always_inline]] inline T contract(const Sym3<T>& a, const Sym3<T>& b) {
  const T diagonal = a.c[0] * b.c[0] + a.c[1] * b.c[1] + a.c[2] * b.c[2];
  const T off = a.c[3] * b.c[3] + a.c[4] * b.c[4] + a.c[5] * b.c[5];
  return diagonal + 2 * off;
}

/// Strain and spin increments of a step whose velocity-gradient increment is dL = dt grad v (3 x 3, zero
/// outside the simulation's dimensions): de = (dL + dL^T) / 2 and the axial vector of dW / 2, dW = (dL -
/// dL^T) / 2 (Sulsky & Kaul 2004, Eq. (2.2.18), Eq. (2.2.19), Eq. (2.2.20)).
template <class T>
struct StrainIncrement {
  Sym3<T> de;
  std::array<T, 3> spin;  ///< a with (dW / 2) x = a cross x
};

template <class T>
[[gnu::always_inline]] inline StrainIncrement<T> strain_increment(const T (&dL)[3][3]) {
  StrainIncrement<T> out;
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) out.de(a, b) = 0.5 * (dL[a][b] + dL[b][a]);
  const auto dW = [&](int a, int b) { return 0.5 * (dL[a][b] - dL[b][a]); };
  out.spin = {0.25 * (dW(2, 1) - dW(1, 2)), 0.25 * (dW(0, 2) - dW(2, 0)), 0.25 * (dW(1, 0) - dW(0, 1))};
  return out;
}

/// The axial vector a of dW / 2 for a skew spin increment dW: (dW / 2) x = a cross x.
inline std::array<Real, 3> spin_of(const Mat<3>& dW) {
  return {0.25 * (dW(2, 1) - dW(1, 2)), 0.25 * (dW(0, 2) - dW(2, 0)), 0.25 * (dW(1, 0) - dW(0, 1))};
}

/// Q sigma Q^T with Q = (I - A)^{-1} (I + A), A = dW / 2 of axial vector a: the midpoint (Cayley) rotation of
/// Hughes & Winget 1980 (the Jaumann rate, Sulsky & Kaul 2004, Sec. 2.2.4). Q is orthogonal to round-off and
/// turns by 2 atan(|a|) about a.
/// In closed form Q = I + G, G = 2 (A + A^2) / (1 + |a|^2) with A^2 = a a^T - |a|^2 I, and Q sigma Q^T =
/// sigma + B + B^T + B G^T with B = G sigma (sigma symmetric): working with the small G keeps the rounding
/// relative to |G| |sigma| rather than |sigma|, so the norm of sigma does not drift by an ulp per step under
/// a steady spin. Without spin sigma is returned as it is.
template <class T>
[[gnu::always_inline]] inline Sym3<T> rotate_jaumann(const Sym3<T>& sigma, const std::array<T, 3>& a) {
  const T a2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
  const T c = 2 / (1 + a2);
  T G[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) G[i][j] = c * (a[i] * a[j] - (i == j ? a2 : T{}));
  G[0][1] -= c * a[2], G[1][0] += c * a[2];
  G[0][2] += c * a[1], G[2][0] -= c * a[1];
  G[1][2] -= c * a[0], G[2][1] += c * a[0];
  T B[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      B[i][j] = G[i][0] * sigma(0, j) + G[i][1] * sigma(1, j) + G[i][2] * sigma(2, j);
  Sym3<T> r;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j)
      r(i, j) =
          sigma(i, j) + (B[i][j] + B[j][i]) + (B[i][0] * G[j][0] + B[i][1] * G[j][1] + B[i][2] * G[j][2]);
  const auto still = a2 == 0;
  for (int k = 0; k < 6; ++k) r.c[k] = still ? sigma.c[k] : r.c[k];
  return r;
}

/// The hypoelastic trial stress of a step: sigma_n rotated by the spin (rotate_jaumann) plus
/// lambda tr(de) I + 2 mu de (Sulsky & Kaul 2004, Eq. (2.2.21)).
template <class T>
[[gnu::always_inline]] inline Sym3<T> hypoelastic_trial(const Sym3<T>& sigma_n,
                                                        const StrainIncrement<T>& step, const T& mu,
                                                        const T& lambda) {
  Sym3<T> trial = rotate_jaumann(sigma_n, step.spin);
  const T two_mu = 2 * mu, dilatation = lambda * trace(step.de);
  for (int k = 0; k < 6; ++k) trial.c[k] += two_mu * step.de.c[k];  // Sulsky & Kaul 2004, Eq. (2.2.21)
  for (int k = 0; k < 3; ++k) trial.c[k] += dilatation;
  return trial;
}

/// The work density of a step done by the mid-step stress, (sigma_n + sigma) / 2 : de
/// (Sulsky & Kaul 2004, Eq. (2.2.16)).
template <class T>
[[gnu::always_inline]] inline T mid_step_work(const Sym3<T>& sigma_n, const Sym3<T>& sigma,
                                              const Sym3<T>& de) {
  Sym3<T> mid;
  for (int k = 0; k < 6; ++k) mid.c[k] = 0.5 * (sigma_n.c[k] + sigma.c[k]);
  return contract(mid, de);  // Sulsky & Kaul 2004, Eq. (2.2.16)
}

}  // namespace mpm
