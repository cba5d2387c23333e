#pragma once
/// Grid-to-particle transfers: velocity, position and deformation updates through the precomputed stencils.
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/materials/neo_hookean.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/stencil.hpp"

namespace mpm {

/// What a G2P pass updates.
struct Gather {
  bool velocity;     ///< v_p += dt sum_i S_ip a_i                       (Wallstedt & Guilkey 2008, Eq. 18)
  bool position;     ///< x_p += dt sum_i S_ip v_i                       (Eq. 17)
  bool deformation;  ///< grad v_p = sum_i v_i grad S_ip, F, V, sigma     (Eqs 10-13 / 19)
};

/// How GIMP half-lengths evolve: fixed (uGIMP) or l_p = l_p^0 diag(F_p) (cpGIMP, Wallstedt & Guilkey 2008,
/// Eq. 63).
enum class SizeUpdate { fixed, deformed };

/// The first particle (lowest index) that failed in a pass, if any.
struct ParticleFault {
  static constexpr std::int64_t none = std::numeric_limits<std::int64_t>::max();
  std::int64_t index = none;
  explicit operator bool() const { return index != none; }
};

/// Gather grid fields to particles. `v_grid` is the node velocity field used for positions and velocity
/// gradients (&GridNode::v_new, or &GridNode::v after a re-projection).
/// Returns the lowest-index particle whose new state is non-finite, has J <= 0 or left the grid.
template <Gather what, int Dim, class Kernel>
ParticleFault g2p(ParticleSet<Dim>& p, const std::vector<Stencil<Dim, Kernel>>& stencils,
                  const Grid<Dim>& grid, NodeVelocity<Dim> v_grid, Real dt,
                  const std::vector<NeoHookean>& materials, SizeUpdate sizes) {
  const NodeLayout<Dim> layout(grid.geometry);
  const GridGeometry<Dim>& geo = grid.geometry;
  std::atomic<std::int64_t> first_fault{ParticleFault::none};
  parallel_for(static_cast<std::ptrdiff_t>(p.size()), [&](std::ptrdiff_t i) {
    Vec<Dim> a_p = Vec<Dim>::Zero(), v_p = Vec<Dim>::Zero();
    Mat<Dim> grad_v = Mat<Dim>::Zero();
    for_each_node(stencils[i], layout, [&](std::int32_t n, Real S_ip, const Vec<Dim>& dS_ip) {
      const GridNode<Dim>& node = grid.nodes[n];
      if constexpr (what.velocity) a_p += S_ip * node.a;
      if constexpr (what.position) v_p += S_ip * (node.*v_grid);
      if constexpr (what.deformation)  // column by column: no Dim x Dim temporary (store-forwarding stalls)
        for (int b = 0; b < Dim; ++b) grad_v.col(b) += dS_ip[b] * (node.*v_grid);
    });
    bool ok = true;
    if constexpr (what.velocity) p.v[i] += dt * a_p;
    if constexpr (what.position) {
      p.x[i] += dt * v_p;
      ok = geo.contains(p.x[i]) && p.v[i].allFinite();
    }
    if constexpr (what.deformation) {
      // Wallstedt & Guilkey 2008, Eqs (11)-(13): F^{n+1} = (I + grad v dt) F^n, V = V^0 det F, sigma =
      // sigma(F).
      const Mat<Dim> F = (Mat<Dim>::Identity() + dt * grad_v) * p.F[i];
      const Real J = F.determinant();
      p.F[i] = F;
      p.V[i] = p.V0[i] * J;
      if (J > 0 && std::isfinite(J)) {
        p.sigma[i] = materials[p.material[i]].template stress<Dim>(F, J);
        if (sizes == SizeUpdate::deformed)
          for (int d = 0; d < Dim; ++d) {
            p.l[i][d] = p.l0[i][d] * F(d, d);
            ok = ok && p.l[i][d] > 0 && p.l[i][d] <= 0.5 * geo.h;  // the GIMP stencil holds l_p <= h/2
          }
      } else {
        ok = false;
      }
    }
    if (!ok) {
      std::int64_t cur = first_fault.load(std::memory_order_relaxed);
      while (i < cur && !first_fault.compare_exchange_weak(cur, i)) {
      }
    }
  });
  return ParticleFault{first_fault.load()};
}

}  // namespace mpm
