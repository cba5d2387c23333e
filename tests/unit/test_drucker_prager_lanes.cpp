// The explicit engine's Drucker-Prager step in G2P's SIMD lanes (DruckerPragerLanes) against the one-particle
// step both engines share (rate_form_step): random stresses, plastic strains and velocity gradients large
// enough to reach every branch of the return (elastic, cone, cut-off, corner, apex), in plane strain,
// axisymmetry and 3-D, with one material (broadcast), several (gathered by index), a softening one (its lanes
// take rate_form_step) and a last block of fewer particles than lanes. The lanes evaluate the same operations
// in the same order, so every stress, plastic strain, energy, stretch and volume is asserted bit for bit.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "frictional_paths.hpp"
#include "mpm/materials/material_step.hpp"
#include "mpm/transfer/g2p_stress.hpp"

namespace {

using namespace frictional_paths;
using mpm::DruckerPrager;
using mpm::LaneBlock;
using mpm::Material;
using mpm::RealLanes;

constexpr Real dt = 1e-3;

/// How often each branch of the return was taken.
struct Branches {
  int elastic = 0, cone = 0, at_largest_mean_stress = 0, softening = 0;
};

template <int Dim, bool Axisymmetric>
Branches expect_lanes_equal_one_particle_steps(const std::vector<Material>& materials, unsigned seed) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<Real> u(-1, 1);
  const int n = 3 * LaneBlock::width + 3;  // a last block with 3 particles
  mpm::ParticleSet<Dim> p;
  for (int i = 0; i < n; ++i)
    p.add(mpm::Vec<Dim>::Zero(), mpm::Vec<Dim>::Zero(), 1, 0.5 + 0.25 * u(gen), mpm::Vec<Dim>::Constant(0.1),
          static_cast<std::uint16_t>(i % materials.size()));
  p.state.resize(n);
  std::vector<mpm::Mat<Dim>> L(n);
  std::vector<Real> J(n), v_r(n), r(n);
  for (int i = 0; i < n; ++i) {
    // Stresses of the size of the strength (c = 10 kPa) and a tensile side, strain increments of 1e-3 (20
    // kPa).
    for (int c = 0; c < 3; ++c) p.state.sigma[i].c[c] = 40e3 * u(gen) - 20e3;
    for (int c = 3; c < 6; ++c) p.state.sigma[i].c[c] = 15e3 * u(gen);
    if (Dim == 2 && !Axisymmetric) p.state.sigma[i](0, 2) = p.state.sigma[i](1, 2) = 0;
    p.state.eps_bar[i] = i % 3 == 0 ? 0 : 0.02 * (1 + u(gen));
    p.state.energy[i] = u(gen);
    p.state.stretch3[i] = Axisymmetric ? 1 + 0.1 * u(gen) : 1;
    L[i] = mpm::Mat<Dim>::NullaryExpr([&] { return 2 * u(gen); });
    mpm::Mat<Dim> F = mpm::Mat<Dim>::Identity() + 0.2 * mpm::Mat<Dim>::NullaryExpr([&] { return u(gen); });
    p.F[i] = F;
    Real Fa[Dim][Dim];
    for (int a = 0; a < Dim; ++a)
      for (int c = 0; c < Dim; ++c) Fa[a][c] = F(a, c);
    J[i] = mpm::simd::determinant(Fa);
    p.V[i] = p.V0[i] * J[i];  // as G2P leaves it
    r[i] = 0.5 + 0.4 * u(gen);
    v_r[i] = r[i] * u(gen);
  }

  // The one-particle steps, from the same start.
  const mpm::ParticleSet<Dim> start = p;
  const mpm::Geometry geometry = Axisymmetric ? mpm::Geometry::axisymmetric : mpm::Geometry::plane_strain;
  std::vector<mpm::MaterialStep> expected(n);
  Branches seen;
  for (int i = 0; i < n; ++i) {
    const DruckerPrager& law = std::get<DruckerPrager>(materials[p.material[i]]);
    const mpm::Mat<Dim> dL = dt * L[i];
    Real step[Dim][Dim];
    for (int a = 0; a < Dim; ++a)
      for (int c = 0; c < Dim; ++c) step[a][c] = (a == c ? 1 : 0) + dL(a, c);
    Real V_start = p.V[i] / mpm::simd::determinant(step);
    if (Axisymmetric) V_start = V_start * p.state.stretch3[i];
    const Real hoop = Axisymmetric ? dt * (v_r[i] / r[i]) : 0;
    expected[i] = mpm::rate_form_step<Dim>(law, p.state.sigma[i], p.state.eps_bar[i], p.state.stretch3[i],
                                           V_start, dL, hoop, geometry);
    EXPECT_TRUE(expected[i].ok);
    if (!law.strength.constant()) {
      ++seen.softening;
      continue;
    }
    const mpm::ConeStrength<Real> cone = mpm::cone_strength(law, 0);
    const Real p_new = (expected[i].sigma.c[0] + expected[i].sigma.c[1] + expected[i].sigma.c[2]) / 3;
    // A return to the cone raises eps_bar; one to the cut-off, corner or apex sets p = t.
    if (p_new == cone.t)
      ++seen.at_largest_mean_stress;
    else if (expected[i].eps_bar > p.state.eps_bar[i])
      ++seen.cone;
    else
      ++seen.elastic;
  }

  // The lanes, block by block.
  const std::vector<mpm::DruckerPragerRow> rows = mpm::drucker_prager_rows(materials);
  EXPECT_EQ(rows.size(), materials.size());
  const mpm::DruckerPragerLanes<Dim, Axisymmetric> lanes{materials, rows, dt};
  for (std::ptrdiff_t b = 0; b < LaneBlock::count(static_cast<std::size_t>(n)); ++b) {
    const LaneBlock block(b, n);
    mpm::DeformedBlock<Dim> d;
    for (int k = 0; k < LaneBlock::width; ++k) {
      const auto i = block.index[k];
      for (int a = 0; a < Dim; ++a)
        for (int c = 0; c < Dim; ++c) d.F[a][c][k] = p.F[i](a, c), d.L[a][c][k] = L[i](a, c);
      d.J[k] = J[i], d.v_r[k] = v_r[i], d.r_start[k] = r[i];
    }
    d.valid = d.J > 0;
    d.ok = d.valid;
    lanes.apply(block, p, d);
    const mpm::simd::MaskLanes ok = d.ok;
    for (int k = 0; k < block.active; ++k) EXPECT_EQ(ok[k], -1) << "particle " << block.index[k];
  }

  for (int i = 0; i < n; ++i) {
    SCOPED_TRACE("particle " + std::to_string(i));
    for (int c = 0; c < 6; ++c) EXPECT_EQ(p.state.sigma[i].c[c], expected[i].sigma.c[c]) << "component " << c;
    EXPECT_EQ(p.state.eps_bar[i], expected[i].eps_bar);
    EXPECT_EQ(p.state.energy[i], start.state.energy[i] + expected[i].energy);
    EXPECT_EQ(p.state.stretch3[i], expected[i].stretch3);
    EXPECT_EQ(p.V[i], start.V[i] * expected[i].stretch3);
  }
  return seen;
}

DruckerPrager with_cut_off(Real tension) {
  DruckerPrager m = soil<DruckerPrager>();
  m.tension = tension;
  return m;
}

TEST(DruckerPragerLanes, PlaneStrainWithOneMaterialTakesEveryBranch) {
  const Branches seen = expect_lanes_equal_one_particle_steps<2, false>({with_cut_off(5e3)}, 1);
  EXPECT_GT(seen.elastic, 0);
  EXPECT_GT(seen.cone, 0);
  EXPECT_GT(seen.at_largest_mean_stress, 0);
}

TEST(DruckerPragerLanes, AxisymmetryWithSeveralMaterialsAndASofteningOne) {
  DruckerPrager inner = soil<DruckerPrager>();
  inner.match = mpm::ConeMatch::inner;
  DruckerPrager softening = soil<DruckerPrager>(true);
  softening.match = mpm::ConeMatch::plane_strain;
  const Branches seen =
      expect_lanes_equal_one_particle_steps<2, true>({inner, softening, with_cut_off(2e3)}, 2);
  EXPECT_GT(seen.elastic, 0);
  EXPECT_GT(seen.cone, 0);
  EXPECT_GT(seen.at_largest_mean_stress, 0);
  EXPECT_GT(seen.softening, 0);
}

TEST(DruckerPragerLanes, ThreeDimensionsAndOne) {
  const std::vector<Material> materials = {with_cut_off(5e3), soil<DruckerPrager>(true)};
  const Branches three = expect_lanes_equal_one_particle_steps<3, false>(materials, 3);
  EXPECT_GT(three.cone, 0);
  EXPECT_GT(three.softening, 0);
  const Branches one = expect_lanes_equal_one_particle_steps<1, false>(materials, 4);
  EXPECT_GT(one.cone + one.at_largest_mean_stress, 0);
}

TEST(DruckerPragerLanes, OnlyAnAllDruckerPragerTableHasRows) {
  EXPECT_EQ(mpm::drucker_prager_rows({soil<DruckerPrager>(), soil<mpm::MohrCoulomb>()}).size(), 0u);
  const std::vector<mpm::DruckerPragerRow> rows =
      mpm::drucker_prager_rows({soil<DruckerPrager>(), soil<DruckerPrager>(true)});
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].softens, 0);
  EXPECT_EQ(rows[1].softens, 1);
}

}  // namespace
