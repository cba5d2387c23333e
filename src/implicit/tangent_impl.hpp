#pragma once
// The frozen-Jacobian preconditioner of ImplicitSimulation (an improvement not in Sulsky & Kaul 2004, whose
// Krylov solves are unpreconditioned); included by implicit_simulation_impl.hpp.
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <utility>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/materials/material_step.hpp"

namespace mpm {

template <int Dim, class Kernel>
struct ImplicitSimulation<Dim, Kernel>::TangentFactor {
  Eigen::SparseLU<Eigen::SparseMatrix<Real>> lu;
  std::vector<int> outer, inner;  // the sparsity pattern lu has analysed (reused while it stays the same)
  bool factorised = false;
};

// The Jacobian of F at x, assembled from the particles and factorised by sparse LU. Within a step the
// stencils, volumes and start-of-step stresses are fixed, so F depends on the unknowns only through
//   v^L (the unknowns themselves, or in the momentum formulation their re-projection Q P^L, Sulsky & Kaul
//   2004, Eq. (3.2.6), Eq. (3.2.7))
//   -> strain increments de_p = dt sym(sum_j v_j^L (x) grad N_j), plus the hoop term dt v_r / r
//   -> sigma_p(de_p) by material_step -> f_i^L = -sum_p V_p (sigma_p grad N_i + hoop)
//   (Sulsky & Kaul 2004, Eq. (2.2.18), Eq. (2.2.19), Eq. (2.2.20), Eq. (2.2.21), Eq. (2.4.7))
// hence dF/dx = scale (D - theta dt K Q + dt Z A), D = I (momentum) or the nodal masses (velocity), K =
// df^L/dv^L, Q = I in the velocity formulation. The material tangent d sigma / d de is a forward difference
// of material_step at each particle's trial strain, one call per independent strain component; only the
// dependence of the Jaumann spin on v^L is left out (a relative error of order sigma / E). Returns false when
// F cannot be evaluated at x; a singular tangent leaves the solve unpreconditioned.
template <int Dim, class Kernel>
bool ImplicitSimulation<Dim, Kernel>::factorise_tangent(const Eigen::VectorXd& x, Real dt) {
  using SpMat = Eigen::SparseMatrix<Real>;
  if (x.size() != last_x_.size() || x != last_x_) {
    Eigen::VectorXd r;
    ++counters_.residual_evaluations;
    if (!residual_at(x, dt, r)) return false;  // the trial velocity gradients at x
  }
  const ParticleSet<Dim>& p = particles_;
  const std::size_t np = p.size();
  const Geometry geometry = Dim == 2 ? spec_.geometry : Geometry::plane_strain;
  // The independent strain components (a <= b): the in-plane ones, and the hoop strain in axisymmetry.
  std::vector<std::pair<int, int>> basis;
  for (int a = 0; a < Dim; ++a)
    for (int b = a; b < Dim; ++b) basis.emplace_back(a, b);
  if (geometry == Geometry::axisymmetric) basis.emplace_back(2, 2);
  const auto m = static_cast<int>(basis.size());
  const int hoop = geometry == Geometry::axisymmetric ? m - 1 : -1;
  int component[3][3];
  for (int k = 0; k < m; ++k) {
    const auto [a, b] = basis[static_cast<std::size_t>(k)];
    component[a][b] = component[b][a] = k;
  }
  // T[p m + k] = d sigma / d de(a_k, b_k), with de(a, b) and de(b, a) moving together.
  std::vector<Mat3> T(np * static_cast<std::size_t>(m));
  parallel_for(static_cast<std::ptrdiff_t>(np), [&](std::ptrdiff_t i) {
    const Mat<Dim> dL = dt * trial_.grad_v[i];
    const Real hoop_increment = hoop >= 0 ? dt * trial_.v_r[i] / p.x[i][0] : 0;  // as residual_at computed it
    const MaterialState& s = particles_.state;
    const auto stress_at = [&](const Mat<Dim>& dL_k, Real hoop_k) {
      return material_step<Dim>(spec_.materials[p.material[i]], s.sigma[i], s.eps_bar[i], s.stretch3[i],
                                s.internal_at(i), p.V[i], p.V0[i], p.F[i], dL_k, dt, hoop_k, geometry)
          .sigma.full();
    };
    const Mat3 base = stress_at(dL, hoop_increment);
    // A step of 1e-7 of the strain increment (1e-13 at rest): a relative error near 1e-7 from truncation
    // and round-off alike, far below what a preconditioner needs. A symmetric change of dL moves de alone.
    const Mat<Dim> de = 0.5 * (dL + dL.transpose());
    const Real delta = 1e-7 * std::max({de.cwiseAbs().maxCoeff(), std::abs(hoop_increment), 1e-6});
    for (int k = 0; k < m; ++k) {
      const auto [a, b] = basis[static_cast<std::size_t>(k)];
      Mat<Dim> dL_k = dL;
      Real hoop_k = hoop_increment;
      if (k == hoop) {
        hoop_k += delta;
      } else {
        dL_k(a, b) += delta;
        if (a != b) dL_k(b, a) += delta;
      }
      T[static_cast<std::size_t>(i) * m + k] = (stress_at(dL_k, hoop_k) - base) / delta;
    }
  });
  const auto n = static_cast<Eigen::Index>(dof_node_.size());
  std::vector<int> dof_of(grid_.size() * Dim, -1);
  for (Eigen::Index k = 0; k < n; ++k) dof_of[dof_node_[k] * Dim + dof_comp_[k]] = static_cast<int>(k);
  periodic_halo_.for_each_image(
      [&](std::int32_t image, std::int32_t owner) {  // an image stands for its owner's unknowns
        for (int c = 0; c < Dim; ++c) dof_of[image * Dim + c] = dof_of[owner * Dim + c];
      });
  struct Local {
    std::int32_t node;
    Real S;
    Vec<Dim> dS;
  };
  std::vector<Local> local;
  const auto gather = [&](std::size_t i) {
    local.clear();
    for_each_node(stencils().at(i, grid_.geometry, layout_), layout_,
                  [&](std::int32_t node, Real S_ip, const Vec<Dim>& dS_ip) {
                    local.push_back({node, S_ip, dS_ip});
                  });
  };
  // K: a unit v_jc gives de = dt (sym(e_c (x) grad N_j) + [c = r] N_j / r e_hoop), so
  // d sigma = dt (d_c N_j T_cc + sum_{a != c} d_a N_j T_ac / 2 + [c = r] N_j / r T_hoop).
  std::vector<Eigen::Triplet<Real>> entries;
  for (std::size_t i = 0; i < np; ++i) {
    gather(i);
    const Mat3* Ti = &T[i * static_cast<std::size_t>(m)];
    const Real r_p = p.x[i][0];
    for (const Local& j : local)
      for (int c = 0; c < Dim; ++c) {
        const int col = dof_of[j.node * Dim + c];
        if (col < 0) continue;
        Mat3 dsigma = j.dS[c] * Ti[component[c][c]];
        for (int a = 0; a < Dim; ++a)
          if (a != c) dsigma += 0.5 * j.dS[a] * Ti[component[a][c]];
        if (hoop >= 0 && c == 0) dsigma += j.S / r_p * Ti[hoop];
        dsigma *= dt * p.V[i];
        for (const Local& k : local) {
          Vec<Dim> f = -dsigma.template topLeftCorner<Dim, Dim>() * k.dS;
          if (hoop >= 0) f[0] -= dsigma(2, 2) * k.S / r_p;
          for (int a = 0; a < Dim; ++a)
            if (const int row = dof_of[k.node * Dim + a]; row >= 0) entries.emplace_back(row, col, f[a]);
        }
      }
  }
  SpMat K(n, n);
  K.setFromTriplets(entries.begin(), entries.end());
  const bool momentum = spec_.formulation == Formulation::momentum;
  SpMat J(n, n);
  if (momentum) {
    // Q = dv^L/dP^L = M^-1 (sum_p m_p N_i(x_p) N_j(x_p)) M^-1 between free components of the same direction.
    entries.clear();
    for (std::size_t i = 0; i < np; ++i) {
      gather(i);
      for (const Local& a : local)
        for (const Local& b : local)
          for (int c = 0; c < Dim; ++c) {
            const int row = dof_of[a.node * Dim + c], col = dof_of[b.node * Dim + c];
            if (row >= 0 && col >= 0)
              entries.emplace_back(row, col,
                                   p.m[i] * a.S * b.S / (grid_.nodes[a.node].m * grid_.nodes[b.node].m));
          }
    }
    SpMat Q(n, n);
    Q.setFromTriplets(entries.begin(), entries.end());
    J = K * Q;
  } else {
    J = K;
  }
  const Real scale = residual_scale(dt);
  J *= -scale * spec_.theta * dt;
  // The dashpots' dt Z A on the diagonal (through v^L = P^L / m on the node in the momentum formulation, Q's
  // diagonal approximated).
  for (Eigen::Index k = 0; k < n; ++k) {
    const Real m_node = grid_.nodes[dof_node_[k]].m;
    J.coeffRef(k, k) +=
        scale * ((momentum ? 1.0 : m_node) + dt * dof_resistance_[k] * (momentum ? 1 / m_node : 1.0));
  }
  J.makeCompressed();
  if (!tangent_) tangent_ = std::make_shared<TangentFactor>();
  TangentFactor& t = *tangent_;
  const std::vector<int> outer(J.outerIndexPtr(), J.outerIndexPtr() + n + 1);
  const std::vector<int> inner(J.innerIndexPtr(), J.innerIndexPtr() + J.nonZeros());
  if (outer != t.outer || inner != t.inner) {
    t.lu.analyzePattern(J);
    t.outer = outer;
    t.inner = inner;
  }
  t.lu.factorize(J);
  t.factorised = t.lu.info() == Eigen::Success;
  ++counters_.preconditioner_builds;
  return true;
}

}  // namespace mpm
