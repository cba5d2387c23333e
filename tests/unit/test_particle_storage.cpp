// What the engines keep per particle: the reference half-lengths l0 only for the kernels that read them (GIMP
// and CPDI; the current ones follow from l0 and F), in both engines, and counted that way; and the reorder
// into scatter order through a buffer of one 8-byte column per particle, which permutes every array and
// leaves the ones of another size alone.
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include "mpm/explicit/simulation.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/particles/reorder.hpp"
#include "mpm/transfer/lanes.hpp"

namespace {

using mpm::ParticleSet;
using mpm::Real;
using mpm::Vec;

/// 4 x 4 particles of half-length 0.125 in the middle cells of a 4 x 4 grid of 1 m cells.
ParticleSet<2> block() {
  ParticleSet<2> p;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      p.add(Vec<2>(1.125 + 0.5 * i, 1.125 + 0.5 * j), Vec<2>::Zero(), 1.0, 0.25, Vec<2>::Constant(0.125), 0);
  return p;
}

/// A spec (either engine's) of a 4 x 4 grid of 1 m cells from the origin, with kernel `kind`.
template <class Spec>
Spec on_four_cells(mpm::KernelKind kind) {
  Spec spec;
  spec.grid_lo = Vec<2>::Zero();
  spec.h = 1;
  spec.cells = {4, 4};
  spec.kernel = kind;
  return spec;
}

/// How a kernel kind's particles keep their half-lengths: none unless the kernel reads them, l_p = l_p^0
/// diag(F_p) for cpGIMP, l_p = l_p^0 otherwise.
template <class Kernel>
mpm::HalfLengths expected_half_lengths(mpm::KernelKind kind) {
  if (!mpm::reads_half_lengths<Kernel>) return mpm::HalfLengths::none;
  return kind == mpm::KernelKind::cpgimp ? mpm::HalfLengths::deformed : mpm::HalfLengths::fixed;
}

template <class Kernel>
std::size_t explicit_half_lengths(mpm::KernelKind kind) {
  auto spec = on_four_cells<mpm::SimulationSpec<2>>(kind);
  spec.materials = {mpm::NeoHookean::from_young_poisson(1e6, 0.3, 1000)};
  spec.dt = 1e-4;
  mpm::Simulation<2, Kernel> sim(spec, block());
  sim.step();
  EXPECT_EQ(sim.particles().half_lengths, expected_half_lengths<Kernel>(kind));
  return sim.particles().l0.size();
}

template <class Kernel>
std::size_t implicit_half_lengths(mpm::KernelKind kind) {
  auto spec = on_four_cells<mpm::ImplicitSpec<2>>(kind);
  mpm::ElastoPlastic steel;
  steel.E = 1e6;
  steel.nu = 0.3;
  steel.rho0 = 1000;
  spec.materials = {steel};
  const mpm::ImplicitSimulation<2, Kernel> sim(spec, block());
  EXPECT_EQ(sim.particles().half_lengths, expected_half_lengths<Kernel>(kind));
  return sim.particles().l0.size();
}

TEST(ParticleStorage, HalfLengthsOnlyForTheKernelsThatReadThem) {
  static_assert(!mpm::reads_half_lengths<mpm::LinearKernel> &&
                !mpm::reads_half_lengths<mpm::QuadraticBSplineKernel> &&
                !mpm::reads_half_lengths<mpm::CubicBSplineKernel>);
  static_assert(mpm::reads_half_lengths<mpm::GimpKernel> && mpm::reads_half_lengths<mpm::WideGimpKernel> &&
                mpm::reads_half_lengths<mpm::CpdiKernel<2>> && mpm::reads_half_lengths<mpm::Cpdi2Kernel<2>>);
  EXPECT_EQ(explicit_half_lengths<mpm::LinearKernel>(mpm::KernelKind::linear), 0u);
  EXPECT_EQ(explicit_half_lengths<mpm::QuadraticBSplineKernel>(mpm::KernelKind::bspline2), 0u);
  EXPECT_EQ(explicit_half_lengths<mpm::GimpKernel>(mpm::KernelKind::cpgimp), 16u);
  EXPECT_EQ(explicit_half_lengths<mpm::CpdiKernel<2>>(mpm::KernelKind::cpdi), 16u);
  EXPECT_EQ(implicit_half_lengths<mpm::LinearKernel>(mpm::KernelKind::linear), 0u);
  EXPECT_EQ(implicit_half_lengths<mpm::GimpKernel>(mpm::KernelKind::ugimp), 16u);
  // The counts follow: one Vec<2> (16 B) less per particle without l0.
  EXPECT_EQ(ParticleSet<2>::bytes_per_particle(true) - ParticleSet<2>::bytes_per_particle(false),
            sizeof(Vec<2>));
  // The budget's model: a tensor-product kernel's particle keeps its stencil's base node and tile (8 B), a
  // CPDI particle its axis data; GIMP's particle differs from linear's by l0, and under USF with cpGIMP by
  // the half-lengths of the locate too. The reorder's buffer is one 8-byte column for all.
  static_assert(sizeof(mpm::StoredStencil<2, mpm::LinearKernel>) == 8 &&
                sizeof(mpm::StoredStencil<2, mpm::CubicBSplineKernel>) == 8 &&
                sizeof(mpm::StoredStencil<2, mpm::GimpKernel>) == 8);
  static_assert(sizeof(mpm::StoredStencil<2, mpm::CpdiKernel<2>>) ==
                sizeof(mpm::Stencil<2, mpm::CpdiKernel<2>>));
  const double gimp = mpm::Simulation<2, mpm::GimpKernel>::memory_model(false, false, false).per_particle;
  const double gimp_usf = mpm::Simulation<2, mpm::GimpKernel>::memory_model(false, false, true).per_particle;
  const double linear = mpm::Simulation<2, mpm::LinearKernel>::memory_model(false, false, false).per_particle;
  EXPECT_EQ(gimp - linear, 16);
  EXPECT_EQ(gimp_usf - gimp, 16);
}

/// The weights `stencils` gives their particles, lane by lane, in particle order.
template <class Kernel>
std::vector<Real> weights_in_lanes(const mpm::ParticleStencils<2, Kernel>& stencils,
                                   const mpm::GridGeometry<2>& g) {
  const mpm::NodeLayout<2> nl(g);
  const std::size_t n = stencils.size();
  std::vector<Real> w(n * 2 * Kernel::width);
  for (std::ptrdiff_t b = 0; b < mpm::LaneBlock::count(n); ++b) {
    const mpm::LaneBlock block(b, static_cast<std::ptrdiff_t>(n));
    const mpm::LaneStencil<2, Kernel> s(stencils, block, g, nl.inv_h);
    for (int k = 0; k < block.active; ++k)
      for (int d = 0; d < 2; ++d)
        for (int j = 0; j < Kernel::width; ++j)
          w[(static_cast<std::size_t>(block.first + k) * 2 + d) * Kernel::width + j] = s.w[d][j][k];
  }
  return w;
}

TEST(ParticleStorage, GimpStencilsWeighWithTheHalfLengthsOfTheirLocate) {
  // A GIMP particle keeps its stencil's base node and tile (8 B) and the transfers locate the rest again from
  // its position and half-lengths. The weights must be those of make_stencil at the locate's half-lengths,
  // bit for bit. When F, and with it cpGIMP's l_p = l_p^0 diag(F), changes before the stencil's last use (a
  // USF step's deformation pass comes before its force pass), the half-lengths of the locate, handed over,
  // keep them so.
  using K = mpm::GimpKernel;
  const mpm::GridGeometry<2> g{Vec<2>(0, 0), 1.0, {4, 4}, K::ghost};
  const mpm::NodeLayout<2> nl(g);
  ParticleSet<2> p = block();
  p.half_lengths = mpm::HalfLengths::deformed;
  for (std::size_t i = 0; i < p.size(); ++i)
    p.F[i].diagonal() = Vec<2>(1.5 + 0.125 * static_cast<Real>(i % 3), 0.75);
  std::vector<mpm::StoredStencil<2, K>> stored;
  mpm::build_stencils<2, K>(p, g, stored);
  const std::vector<Real> located = weights_in_lanes<K>(mpm::ParticleStencils<2, K>{stored, p}, g);
  std::vector<Vec<2>> half_lengths(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    half_lengths[i] = p.half_length(i);
    const mpm::Stencil<2, K> one = mpm::make_stencil<2, K>(g, nl, p.x[i], p.half_length(i));
    const mpm::Stencil<2, K> at = mpm::ParticleStencils<2, K>{stored, p}.at(i, g, nl);
    for (int d = 0; d < 2; ++d) {
      Real w[K::width], dw[K::width], w_at[K::width];
      K::weights_at(one.axis[d], w, dw);
      K::weights_at(at.axis[d], w_at, dw);
      for (int j = 0; j < K::width; ++j) {
        EXPECT_EQ(located[(i * 2 + d) * K::width + j], w[j]) << i;
        EXPECT_EQ(w_at[j], w[j]) << i;
      }
    }
  }
  // F changes: the stencils weigh as located with the half-lengths handed over, and differently without them.
  for (mpm::Mat<2>& F : p.F) F.diagonal() = Vec<2>(1, 1);
  EXPECT_EQ(weights_in_lanes<K>(mpm::ParticleStencils<2, K>{stored, p, &half_lengths}, g), located);
  EXPECT_NE(weights_in_lanes<K>(mpm::ParticleStencils<2, K>{stored, p}, g), located);
}

/// Reorder a row of 64 particles by `order`, with two arrays more (one of records shorter than a column, one
/// of another size), and check every record moved; returns the bytes the buffer holds after.
std::size_t expect_reordered(const std::vector<std::int32_t>& order) {
  ParticleSet<2> p;
  for (int i = 0; i < 64; ++i)
    p.add(Vec<2>(0.5 + i, 0.5), Vec<2>::Zero(), 1.0, 1.0, Vec<2>::Constant(0.5), 0);
  p.B.assign(p.size(), mpm::Mat<2>::Zero());
  std::vector<std::int32_t> tile(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.B[i](1, 0) = static_cast<Real>(i);
    p.material[i] = static_cast<std::uint16_t>(i);  // a record shorter than the column
    p.F[i](0, 1) = 0.5 * static_cast<Real>(i);
    tile[i] = static_cast<std::int32_t>(100 + i);
  }
  const ParticleSet<2> before = p;
  std::vector<std::int64_t> spare(3, 7);  // another size: left as it is
  mpm::ReorderBuffer buffer;
  mpm::reorder_particles(p, order, buffer, tile, spare);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto i = static_cast<std::size_t>(order[k]);
    EXPECT_EQ(p.x[k], before.x[i]);
    EXPECT_EQ(p.id[k], before.id[i]);
    EXPECT_EQ(p.l0[k], before.l0[i]);
    EXPECT_EQ(p.B[k](1, 0), static_cast<Real>(i));
    EXPECT_EQ(p.material[k], i);
    EXPECT_EQ(p.F[k], before.F[i]);
    EXPECT_EQ(tile[k], static_cast<std::int32_t>(100 + i));
  }
  EXPECT_EQ(spare, std::vector<std::int64_t>(3, 7));
  return buffer.bytes();
}

TEST(ParticleStorage, ReordersMoveEveryRecordThroughOneColumn) {
  // Particle 1 moved to place 40 and particle 60 to place 50, the records between shifted by one place (as
  // when particles change tiles); and the reverse order.
  std::vector<std::int32_t> shifted(64), reverse(64);
  std::iota(shifted.begin(), shifted.end(), 0);
  shifted.erase(shifted.begin() + 1), shifted.insert(shifted.begin() + 40, 1);
  shifted.erase(shifted.begin() + 60), shifted.insert(shifted.begin() + 50, 60);
  for (std::size_t k = 0; k < reverse.size(); ++k) reverse[k] = static_cast<std::int32_t>(63 - k);
  // One 8-byte column for each of the 64 particles, whatever the records: 512 B, eight 64-byte lines.
  EXPECT_EQ(expect_reordered(shifted), 64 * mpm::ReorderBuffer::column);
  EXPECT_EQ(expect_reordered(reverse), 64 * mpm::ReorderBuffer::column);
}

}  // namespace
