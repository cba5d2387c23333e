#pragma once
// The consistent mass matrix of an implicit step (Sulsky & Kaul 2004, Eq. (2.2.6)), as an option of the
// velocity formulation: its product with a node field, and the projection of the particles' momentum to the
// node velocities it defines. Included by simulation_impl.hpp.
#include <sstream>

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/numerics/newton_krylov.hpp"
#include "mpm/transfer/g2p.hpp"
#include "mpm/transfer/p2g.hpp"

namespace mpm {

// (M u)_i = sum_p m_p N_i(x_p) sum_j N_j(x_p) u_j (Sulsky & Kaul 2004, Eq. (2.2.6)) for u on the owned nodes,
// in place: u is given to the mirrored and periodic images first, and the product is folded and summed as the
// lumped mass is. Uses GridNode::a as scratch.
template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::consistent_mass_times(std::vector<Vec<Dim>>& u) {
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()), [&](std::ptrdiff_t n) { grid_.nodes[n].a = u[n]; });
  constraints_.mirror(grid_, &GridNode<Dim>::a);
  periodic_halo_.for_each_image(
      [&](std::int32_t image, std::int32_t owner) { grid_.nodes[image].a = grid_.nodes[owner].a; });
  g2p_interpolate(stencils(), grid_, &GridNode<Dim>::a, u_p_);
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()),
               [&](std::ptrdiff_t n) { grid_.nodes[n].a.setZero(); });
  p2g_add(stencils(), order_, grid_, Momentum<Dim, NodeSlots<Dim>::a, false>{particles_.m, u_p_});
  periodic_halo_.sum_into_owners(grid_, &GridNode<Dim>::a);
  constraints_.fold_and_mirror(grid_, &GridNode<Dim>::a);
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()), [&](std::ptrdiff_t n) { u[n] = grid_.nodes[n].a; });
}

// The node velocities v^k with M v^k = sum_p m_p v_p N_i(x_p) (Sulsky & Kaul 2004, Eq. (2.2.5) with the
// consistent mass of Eq. (2.2.6) in place of the lumped one of Eq. (2.2.14)), on the owned nodes that carry
// mass, by CG preconditioned with the lumped mass; GridNode::v holds the lumped projection on entry and the
// result on exit. M is singular where few particles share a node's support, but the momentum lies in its
// range (it is the mass matrix's own product with the particle velocities), so CG converges there too
// (measured with one particle per cell). Throws SimulationFailure when CG does not converge.
template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::project_consistent(Real dt) {
  std::vector<std::int32_t> active;
  for (std::size_t n = 0; n < grid_.size(); ++n)
    if (!mirrored_[n] && grid_.nodes[n].m > min_node_mass_) active.push_back(static_cast<std::int32_t>(n));
  const auto size = static_cast<Eigen::Index>(active.size() * Dim);
  Eigen::VectorXd b(size), x(size);
  for (std::size_t k = 0; k < active.size(); ++k)
    for (int c = 0; c < Dim; ++c) {
      const GridNode<Dim>& node = grid_.nodes[active[k]];
      // the momentum (Sulsky & Kaul 2004, Eq. (2.2.14))
      b[static_cast<Eigen::Index>(k * Dim + c)] = node.m * node.v[c];
      x[static_cast<Eigen::Index>(k * Dim + c)] = node.v[c];  // the lumped solution as the first guess
    }
  std::vector<Vec<Dim>> u(grid_.size());
  const auto apply = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
    for (Vec<Dim>& un : u) un.setZero();
    for (std::size_t k = 0; k < active.size(); ++k)
      for (int c = 0; c < Dim; ++c) u[active[k]][c] = in[static_cast<Eigen::Index>(k * Dim + c)];
    consistent_mass_times(u);
    out.resize(in.size());
    for (std::size_t k = 0; k < active.size(); ++k)
      for (int c = 0; c < Dim; ++c) out[static_cast<Eigen::Index>(k * Dim + c)] = u[active[k]][c];
  };
  const auto lumped = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
    out.resize(in.size());
    for (std::size_t k = 0; k < active.size(); ++k)
      for (int c = 0; c < Dim; ++c)
        out[static_cast<Eigen::Index>(k * Dim + c)] =
            in[static_cast<Eigen::Index>(k * Dim + c)] / grid_.nodes[active[k]].m;
  };
  const numerics::LinearStats stats =
      numerics::conjugate_gradient(apply, b, x, 1e-13, 10 * static_cast<int>(size) + 10, lumped);
  if (!stats.converged) {
    std::ostringstream os;
    os.precision(9);
    os << "step " << steps_ + 1 << ", t = " << time_ + dt
       << ": the projection with the consistent mass matrix "
       << "(implicit.mass = \"consistent\") did not converge in " << stats.iterations
       << " CG iterations: use the lumped mass";
    throw SimulationFailure(os.str());
  }
  for (std::size_t k = 0; k < active.size(); ++k)
    for (int c = 0; c < Dim; ++c) grid_.nodes[active[k]].v[c] = x[static_cast<Eigen::Index>(k * Dim + c)];
  constraints_.mirror(grid_, &GridNode<Dim>::v);
  periodic_halo_.copy_to_ghosts(grid_);
}

// The inertia term of the residual, M (v^L - v^k) on every node, into mass_dv_ (Sulsky & Kaul 2004,
// Eq. (2.4.12) with the consistent mass of Eq. (2.2.6)); v^L in GridNode::v_new.
template <int Dim, class Kernel>
void ImplicitSimulation<Dim, Kernel>::consistent_inertia() {
  mass_dv_.resize(grid_.size());
  parallel_for(static_cast<std::ptrdiff_t>(grid_.size()), [&](std::ptrdiff_t n) {
    const GridNode<Dim>& node = grid_.nodes[n];
    mass_dv_[n] = node.m > min_node_mass_ ? Vec<Dim>(node.v_new - node.v) : Vec<Dim>::Zero();
  });
  consistent_mass_times(mass_dv_);
}

}  // namespace mpm
