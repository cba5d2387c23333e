#pragma once
/// Grid-to-particle transfers: velocity, position and deformation updates through the precomputed stencils.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/shape/stencil.hpp"
#include "mpm/transfer/g2p_stress.hpp"
#include "mpm/transfer/lanes.hpp"
#include "mpm/transfer/particle_update.hpp"
#include "mpm/transfer/passes.hpp"

namespace mpm {

/// What a G2P pass gathers at each particle from the nodes of its stencil.
struct Sums {
  bool acceleration;    ///< sum_i S_ip a_i
  bool velocity;        ///< sum_i S_ip v_i, v a chosen node velocity field
  bool gradient;        ///< grad v_p = sum_i v_i (x) grad S_ip
  bool affine = false;  ///< APIC's B_p = sum_i S_ip v_i (x) (x_i - x_p) (Jiang et al. 2015)
};

/// A block's gathered sums in lanes (zero where not gathered); grad_v[a][c] = d v_a / d x_c, B[a][c] the (a,
/// c) entry of B_p.
template <int Dim>
struct GatheredLanes {
  RealLanes a[Dim] = {}, v[Dim] = {}, grad_v[Dim][Dim] = {}, B[Dim][Dim] = {};
};

/// G2P: for the particles of `range` in blocks of simd::lanes (in parallel), gather `what` from the nodes of
/// their stencils, v from the node field `v_grid`, and hand each block's sums to use(block, sums).
template <Sums what, int Dim, class Kernel, class Use>
void g2p_gather(const ParticleStencils<Dim, Kernel>& stencils, const Grid<Dim>& grid,
                NodeVelocity<Dim> v_grid, ParticleRange range, Use&& use) {
  const NodeLayout<Dim> layout(grid.geometry);
  const auto& nodes = grid.nodes;
  parallel_for(
      LaneBlock::count(range),
      [&](std::ptrdiff_t b) {
        const LaneBlock block(b, range);
        LaneStencil<Dim, Kernel> s(stencils, block, grid.geometry, layout.inv_h);
        if constexpr (what.affine) s.locate_nodes(grid.geometry.h);
        GatheredLanes<Dim> sum;
        for_each_node<what.affine ? NodeMoment::offset : NodeMoment::none>(
            s, layout,
            [&](std::int32_t offset, const RealLanes& S_ip, const RealLanes(&dS_ip)[Dim],
                const auto&... Sx_ip) {
              for (int c = 0; c < Dim; ++c) {
                if constexpr (what.acceleration)
                  sum.a[c] += S_ip * s.gather(nodes, offset, [&](const GridNode<Dim>& node) -> const Real& {
                    return node.a[c];
                  });
                if constexpr (what.velocity || what.gradient || what.affine) {
                  const RealLanes v_i =
                      s.gather(nodes, offset,
                               [&](const GridNode<Dim>& node) -> const Real& { return (node.*v_grid)[c]; });
                  if constexpr (what.velocity) sum.v[c] += S_ip * v_i;
                  if constexpr (what.gradient)
                    for (int e = 0; e < Dim; ++e) sum.grad_v[c][e] += dS_ip[e] * v_i;
                  if constexpr (what.affine) {
                    const auto& Sx = [](const auto& moment) -> const auto& {
                      return moment;
                    }
                    (Sx_ip...);
                    for (int e = 0; e < Dim; ++e) sum.B[c][e] += v_i * Sx[e];
                  }
                }
              }
            });
        use(block, sum);
      },
      1024 / LaneBlock::width);  // a chunk of about 1024 particles
}

/// G2P of one node vector field: out_p = sum_i S_ip (node_i.*field), for the particles of `range` (all by
/// default).
template <int Dim, class Kernel>
void g2p_interpolate(const ParticleStencils<Dim, Kernel>& stencils, const Grid<Dim>& grid,
                     NodeVelocity<Dim> field, std::vector<Vec<Dim>>& out,
                     std::optional<ParticleRange> range = {}) {
  out.resize(stencils.size());
  g2p_gather<Sums{.acceleration = false, .velocity = true, .gradient = false}>(
      stencils, grid, field, range.value_or(ParticleRange{0, static_cast<std::ptrdiff_t>(stencils.size())}),
      [&](const LaneBlock& block, const GatheredLanes<Dim>& sum) {
        RecordLanes<Vec<Dim>> v;
        for (int d = 0; d < Dim; ++d) v[d] = sum.v[d];
        block.store(out, v);
      });
}

/// APIC's G2P of one node velocity field (Jiang et al. 2015): v_p = sum_i S_ip v_i into `v` and
/// B_p = sum_i S_ip v_i (x) (x_i - x_p) into `B`, for the particles of `range` (all by default).
template <int Dim, class Kernel>
void g2p_affine(const ParticleStencils<Dim, Kernel>& stencils, const Grid<Dim>& grid, NodeVelocity<Dim> field,
                std::vector<Vec<Dim>>& v, std::vector<Mat<Dim>>& B, std::optional<ParticleRange> range = {}) {
  v.resize(stencils.size());
  B.resize(stencils.size());
  g2p_gather<Sums{.acceleration = false, .velocity = true, .gradient = false, .affine = true}>(
      stencils, grid, field, range.value_or(ParticleRange{0, static_cast<std::ptrdiff_t>(stencils.size())}),
      [&](const LaneBlock& block, const GatheredLanes<Dim>& sum) {
        RecordLanes<Vec<Dim>> v_p;
        RecordLanes<Mat<Dim>> B_p;
        for (int c = 0; c < Dim; ++c) {
          v_p[c] = sum.v[c];
          for (int e = 0; e < Dim; ++e) B_p[c + e * Dim] = sum.B[c][e];
        }
        block.store(v, v_p);
        block.store(B, B_p);
      });
}

/// CPDI2's corner update (Sadeghirad et al. 2013): to_c = from_c + dt sum_i N_i(x_c) v_i for every corner x_c
/// of the particles of `range` (all by default), v_i the node field `v_grid`, through the stencils of the
/// step's start, whose corner hats N_i(x_c) CornerWeights holds. `from` and `to` may be one array.
template <int Dim, class Kernel>
requires moves_corners<Kernel>
void g2p_corners(const ParticleStencils<Dim, Kernel>& stencils, const Grid<Dim>& grid,
                 NodeVelocity<Dim> v_grid, Real dt, const std::vector<Corners<Dim>>& from,
                 std::vector<Corners<Dim>>& to, std::optional<ParticleRange> range = {}) {
  constexpr int C = Kernel::corners;
  const NodeLayout<Dim> layout(grid.geometry);
  const auto& nodes = grid.nodes;
  to.resize(from.size());
  const ParticleRange r = range.value_or(ParticleRange{0, static_cast<std::ptrdiff_t>(stencils.size())});
  parallel_for(
      LaneBlock::count(r),
      [&](std::ptrdiff_t b) {
        const LaneBlock block(b, r);
        const LaneStencil<Dim, Kernel> s(stencils, block, grid.geometry, layout.inv_h);
        RealLanes v_c[C][Dim] = {};
        s.corners.visit_hats([&](const int(&k)[Dim], const RealLanes(&N)[C]) __attribute__((always_inline)) {
          std::int32_t offset = k[0];
          for (int d = 1; d < Dim; ++d) offset += k[d] * layout.stride[d];
          for (int d = 0; d < Dim; ++d) {
            const RealLanes v_i = s.gather(
                nodes, offset, [&](const GridNode<Dim>& node) -> const Real& { return (node.*v_grid)[d]; });
            for (int c = 0; c < C; ++c) v_c[c][d] += N[c] * v_i;
          }
        });
        RecordLanes<Corners<Dim>> x = block.load(from);
        for (int c = 0; c < C; ++c)
          for (int d = 0; d < Dim; ++d) x[d + c * Dim] += dt * v_c[c][d];
        block.store(to, x);
      },
      1024 / LaneBlock::width);
}

/// The FLIP-PIC blend of a velocity update: v_p = flip (v_p + dt sum_i S_ip a_i) + (1 - flip) pic_p, pic_p
/// the grid velocity interpolated to the particle (sum_i S_ip v_i). Without pic the update is FLIP's.
template <int Dim>
struct VelocityBlend {
  Real flip = 1;
  const std::vector<Vec<Dim>>* pic = nullptr;
};

/// The explicit step's G2P: update the particles from the sums g2p_gather hands over. `v_grid` is the node
/// velocity field used for positions and velocity gradients (&GridNode::v_new, or &GridNode::v after a
/// re-projection).
/// A CPDI2 pass puts each particle at the centroid of its corners, which g2p_corners moved first, and moves
/// the corners with it through a periodic wrap or onto a wall (Sadeghirad et al. 2013). A pass that moves the
/// particles can also compute their stencils at the new positions for the next step, into `next` when given:
/// the positions are then at hand, and no separate pass over the particles is needed. A deforming pass hands
/// each block's F, J, velocity gradient, interpolated radial velocity and radius at the start of the step to
/// `stress` (a LaneStress of transfer/g2p_stress.hpp), which may fail lanes. Returns the lowest-index
/// particle whose new state is non-finite, has J <= 0 or left the grid. Only the particles of `range` gather
/// (those of the velocity field `grid` holds); all of them by default. A velocity update is blended with
/// PIC's by `blend`.
template <Gather what, int Dim, class Kernel, class Stress>
ParticleFault g2p(ParticleSet<Dim>& p, const ParticleStencils<Dim, Kernel>& stencils, const Grid<Dim>& grid,
                  NodeVelocity<Dim> v_grid, Real dt, const Stress& stress,
                  StencilTargets<Dim, Kernel>* next = nullptr, std::optional<ParticleRange> range = {},
                  const VelocityBlend<Dim>& blend = {}) {
  constexpr bool interpolate_velocity = what.position || (what.deformation && Stress::reads_velocity);
  const GridGeometry<Dim>& geo = grid.geometry;
  const NodeLayout<Dim> layout(geo);
  std::atomic<std::int64_t> first_fault{ParticleFault::none};
  const PositionBounds<Dim> bounds(geo);
  // Whether the stencils of the next step are located at positions clamped to the grid: a particle beyond an
  // outflow face is removed after the step.
  bool clamps = false;
  for (int c = 0; c < Dim; ++c) clamps = clamps || geo.outflow[2 * c] || geo.outflow[2 * c + 1];
  constexpr Sums sums{
      .acceleration = what.velocity, .velocity = interpolate_velocity, .gradient = what.deformation};
  g2p_gather<sums>(
      stencils, grid, v_grid, range.value_or(ParticleRange{0, static_cast<std::ptrdiff_t>(p.size())}),
      [&](const LaneBlock& block, const GatheredLanes<Dim>& sum) __attribute__((always_inline)) {
        const auto& a_p = sum.a;
        const auto& v_p = sum.v;
        const auto& grad_v = sum.grad_v;
        simd::MaskLanes ok = simd::MaskLanes{} == 0;  // all lanes true
        RecordLanes<Vec<Dim>> x;
        RealLanes r_start{};
        if constexpr (what.deformation && Stress::reads_velocity) r_start = block.load(p.x)[0];
        if constexpr (what.velocity || what.position) {
          RecordLanes<Vec<Dim>> v = block.load(p.v);
          if constexpr (what.velocity) {
            for (int c = 0; c < Dim; ++c) v[c] += dt * a_p[c];
            if (blend.pic) {
              const RecordLanes<Vec<Dim>> pic = block.load(*blend.pic);
              for (int c = 0; c < Dim; ++c) v[c] = blend.flip * v[c] + (1 - blend.flip) * pic[c];
            }
            block.store(p.v, v);
          }
          if constexpr (what.position) {
            x = block.load(p.x);
            [[maybe_unused]] RecordLanes<Corners<Dim>> corners;
            if constexpr (moves_corners<Kernel>) corners = block.load(p.corners);  // g2p_corners moved them
            ok &= move_positions<Dim, Kernel>(bounds, x, v_p, dt, corners);
            for (int c = 0; c < Dim; ++c) ok &= v[c] - v[c] == 0;
            block.store(p.x, x);
            if constexpr (moves_corners<Kernel>) block.store(p.corners, corners);
          }
        }
        if constexpr (what.deformation) {
          // Wallstedt & Guilkey 2008, Eq. (11), Eq. (12), Eq. (13): F^{n+1} = (I + grad v dt) F^n, V = V^0
          // det F, sigma = sigma(F).
          RecordLanes<Mat<Dim>> F_new;
          RealLanes F[Dim][Dim];
          const RealLanes J = deform<Dim>([&](int a, int c) -> const RealLanes& { return grad_v[a][c]; }, dt,
                                          block.load(p.F), F, F_new);
          block.store(p.F, F_new);
          block.store(p.V, {block.load(p.V0)[0] * J});
          const simd::MaskLanes valid = (J > 0) & (J - J == 0);
          ok &= valid;
          // A lane with an invalid J keeps its stress (the run stops).
          ok &= stress(block, p, F, J, valid, grad_v, v_p[0], r_start);
        }
        if constexpr (what.position)
          if (next) {
            if (clamps)
              for (int c = 0; c < Dim; ++c) {
                const RealLanes lo = simd::broadcast(geo.lo[c]),
                                hi = simd::broadcast(geo.lo[c] + geo.h * geo.cells[c]);
                x[c] = x[c] < lo ? lo : x[c];
                x[c] = x[c] > hi ? hi : x[c];
              }
            next->store(block, locate_block<Dim, Kernel>(geo, layout, x, load_domain<Dim, Kernel>(block, p)));
          }
        note_first_fault(first_fault, block, ok);
      });
  return ParticleFault{first_fault.load()};
}

}  // namespace mpm
