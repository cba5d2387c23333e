// Distributed explicit runs give the same bits as one process. Run by ctest under mpirun with 1, 2, 3 and 4
// ranks (tests/CMakeLists.txt): every rank runs its box of the problem (Simulation with world()), rank 0 also
// runs the whole problem in one process, gathers the ranks' particles and compares every field of every
// particle, by id, byte for byte, after every step count checked, with 1 and 2 threads per rank. Cases: the
// colliding-disks example with every kernel (particles cross boxes all the way), the 2-D axis-aligned scene
// (cpGIMP, centered difference, four symmetry planes, a body force) and the 3-D axis-aligned verification
// problem (cpGIMP, USL, six symmetry planes), the 3-D block example (MUSL, a wall, free faces) and the
// upsetting example made explicit, plane strain and axisymmetric (a rigid platen, von Mises plasticity, the
// hoop force).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "mpm/core/parallel.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/explicit/simulation.hpp"
#include "mpm/particles/pack.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"
#include "mpm/verification/axis_aligned.hpp"

namespace {

using namespace mpm;

/// Every field of every particle, by id: the particles packed (pack_particle) in id order.
template <int Dim>
std::vector<std::byte> by_id(ParticleSet<Dim>& p, PackedArrays with) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  std::vector<std::byte> bytes;
  for (std::size_t i : order) pack_particle(p, i, with, bytes);
  return bytes;
}

/// The particles of every rank, on rank 0 (empty elsewhere).
template <int Dim>
ParticleSet<Dim> gathered(ParticleSet<Dim> mine, PackedArrays with, const Communicator& comm) {
  std::vector<std::vector<std::byte>> to(static_cast<std::size_t>(comm.size()));
  for (std::size_t i = 0; i < mine.size(); ++i) pack_particle(mine, i, with, to[0]);
  const std::vector<std::vector<std::byte>> from = comm.exchange(to);
  ParticleSet<Dim> all;
  for (const std::vector<std::byte>& bytes : from) unpack_particles(bytes, with, all);
  return all;
}

/// Run `steps` steps distributed and, on rank 0, in one process; compare after each of `checks` (step
/// counts). Returns how many times the divided run divided its grid again (Simulation::rebalances).
template <int Dim, class Kernel>
int expect_same_bits(const SimulationSpec<Dim>& spec, const ParticleSet<Dim>& particles,
                     const std::vector<int>& checks, const std::string& name) {
  const Communicator& comm = world();
  int rebalances = 0;
  for (int threads : {1, 2}) {
    set_num_threads(threads);
    Simulation<Dim, Kernel> divided(spec, particles, comm);
    std::optional<Simulation<Dim, Kernel>> whole;
    if (comm.rank() == 0) {
      set_num_threads(1);
      whole.emplace(spec, particles, one_process());
      set_num_threads(threads);
    }
    const bool with_state = whole && !whole->particles().state.empty();
    const PackedArrays state{.state = comm.max(with_state ? 1.0 : 0.0) > 0,
                             .affine = spec.transfer == Transfer::apic,
                             .corners = false,
                             .half_lengths = reads_half_lengths<Kernel>};
    // The division is real: with several ranks each holds a box of the grid and only its particles.
    EXPECT_EQ(divided.boxes().divided(), comm.size() > 1);
    std::vector<std::int64_t> counts(static_cast<std::size_t>(comm.size()), 0);
    counts[static_cast<std::size_t>(comm.rank())] = static_cast<std::int64_t>(divided.particles().size());
    comm.sum(counts);
    if (comm.size() > 1) {
      for (std::int64_t n : counts) EXPECT_LT(n, static_cast<std::int64_t>(particles.size())) << name;
    }
    std::vector<std::int64_t> first_ids = divided.particles().id;
    std::sort(first_ids.begin(), first_ids.end());
    for (int check : checks) {
      while (divided.steps() < check) divided.step();
      // Particles that have moved to another rank since the start, over all ranks.
      std::vector<std::int64_t> moved{0};
      for (std::int64_t id : divided.particles().id)
        moved[0] += !std::binary_search(first_ids.begin(), first_ids.end(), id);
      comm.sum(moved);
      if (comm.rank() == 0 && check == checks.back() && comm.size() > 1)
        std::printf("%s, %d ranks: %lld particles changed rank\n", name.c_str(), comm.size(),
                    static_cast<long long>(moved[0]));
      ParticleSet<Dim> all = gathered(divided.particles(), state, comm);
      if (comm.rank() != 0) continue;
      set_num_threads(1);
      while (whole->steps() < check) whole->step();
      set_num_threads(threads);
      ParticleSet<Dim> reference = whole->particles();
      const std::string at = name + ", " + std::to_string(comm.size()) + " ranks x " +
                             std::to_string(threads) + " threads, step " + std::to_string(check);
      EXPECT_EQ(all.size(), reference.size()) << at;
      if (all.size() != reference.size()) continue;  // no return: the other ranks wait in the next collective
      EXPECT_EQ(divided.time(), whole->time()) << at;
      const std::vector<std::byte> a = by_id(all, state), b = by_id(reference, state);
      const auto differ = std::mismatch(a.begin(), a.end(), b.begin());
      EXPECT_TRUE(differ.first == a.end())
          << at << ": particle "
          << (differ.first - a.begin()) / static_cast<std::ptrdiff_t>(a.size() / all.size())
          << " (in id order) differs at byte "
          << (differ.first - a.begin()) % static_cast<std::ptrdiff_t>(a.size() / all.size());
    }
    rebalances = divided.rebalances();
  }
  return rebalances;
}

template <int Dim>
void scene_case(const std::string& file, const std::vector<std::string>& overrides,
                const std::vector<int>& checks) {
  const Scene sc = read_scene(std::string(MPM_SOURCE_DIR) + "/" + file, overrides);
  const SimulationSpec<Dim> spec = make_spec<Dim>(sc);
  with_kernel<Dim>(sc.kernel, [&]<class K>() {
    expect_same_bits<Dim, K>(spec, seed_bodies<Dim>(sc), checks,
                             file + " " + std::string(to_string(sc.kernel)));
  });
}

TEST(SameBits, CollidingDisksEveryKernel) {
  // 150 steps to t = 3 s: the disks meet near step 60 and part; particles cross between boxes throughout.
  for (const char* kernel : {"linear", "ugimp", "cpgimp", "bspline2", "bspline3", "bspline2-clamped",
                             "bspline3-clamped", "cpdi", "cpgimp-wide", "cpdi2"})
    scene_case<2>("examples/colliding-disks/scene.toml", {std::string("simulation.kernel=") + kernel},
                  {1, 40, 150});
}

TEST(SameBits, CollidingDisksWithApic) {
  // APIC's matrices B_p move between ranks with their particles (PackedArrays::affine).
  scene_case<2>("examples/colliding-disks/scene.toml",
                {"simulation.kernel=bspline2", "simulation.transfer=apic"}, {1, 40, 150});
}

TEST(SameBits, CollidingDisksDividedAgainAsTheyMove) {
  // Rebalanced whenever the particles per rank are uneven at all, at most every 5 steps: the boxes change
  // many times, the bits do not.
  const Scene sc = read_scene(std::string(MPM_SOURCE_DIR) + "/examples/colliding-disks/scene.toml", {});
  SimulationSpec<2> spec = make_spec<2>(sc);
  spec.rebalance_above = 1.0;
  spec.rebalance_interval = 5;
  const int rebalances =
      expect_same_bits<2, LinearKernel>(spec, seed_bodies<2>(sc), {1, 40, 150}, "rebalanced disks");
  // Measured: 2 divisions on 3 and 4 ranks. On 2 the one cut can lie at two tile layers only (x = 0.35 or
  // 0.75 m on this 20-cell grid) and the disks, symmetric about the centre, keep the same one the better: the
  // bisection never moves it.
  if (world().size() > 2) {
    EXPECT_GT(rebalances, 0);
  } else {
    EXPECT_EQ(rebalances, 0);
  }
  if (world().rank() == 0 && world().size() > 1)
    std::printf("rebalanced disks, %d ranks: divided again %d times\n", world().size(), rebalances);
}

TEST(SameBits, PlaneStrainUpsettingUnderARigidPlaten) {
  // The upsetting example made explicit (MUSL) and plane strain: a rigid platen pressing a von Mises billet;
  // the boxes cut through both (rate-form state moves with the particles; the platen's nodes are found per
  // box).
  scene_case<2>("examples/implicit/upsetting.toml",
                {"simulation.integrator=musl", "simulation.geometry=plane-strain"}, {1, 100, 300});
}

TEST(SameBits, AxisymmetricUpsettingUnderARigidPlaten) {
  // The upsetting example made explicit (MUSL), axisymmetric as the paper's: the hoop force's own pass adds
  // onto the forces the halo sum agreed, and its halo sum starts the shared nodes from them.
  scene_case<2>("examples/implicit/upsetting.toml", {"simulation.integrator=musl"}, {1, 100, 300});
}

TEST(SameBits, AxisAligned2D) {
  scene_case<2>("examples/axis-aligned/scene.toml", {}, {1, 80, 160});
}

TEST(SameBits, Block3D) {
  scene_case<3>("examples/3d-block/scene.toml", {}, {1, 100, 250});
}

TEST(SameBits, AxisAligned3D) {
  // The verification problem of `mpm verify axis-aligned --dim 3 --cells 12` (USL here), on 12^3 cells.
  const AxisAligned<3> exact{0.05, NeoHookean::from_young_poisson(1e7, 0.3, 1000)};
  SimulationSpec<3> spec;
  exact.configure(spec, 12);
  spec.kernel = KernelKind::cpgimp;
  spec.integrator = Integrator::usl;
  spec.materials = {exact.mat};
  spec.cfl = 0.4;
  spec.body_force = [exact](const Vec<3>& X, Real t) { return exact.body_force(X, t); };
  ParticleSet<3> p;
  exact.seed(p, spec.h / 2);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.x[i] = p.X[i] + exact.displacement(p.X[i], 0);
    p.v[i] = exact.velocity(p.X[i], 0);
    p.F[i] = exact.deformation_gradient(p.X[i], 0);
  }
  expect_same_bits<3, GimpKernel>(spec, p, {1, 20, 40}, "3-D axis-aligned");
}

}  // namespace

int main(int argc, char** argv) {
  mpm::MpiSession mpi(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  // Only rank 0 reports (the others' results are the same collectives, compared there).
  if (mpm::world().rank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
}
