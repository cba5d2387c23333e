#pragma once
// The engine a scene runs, for the verification tests that compare the explicit and implicit steps on one
// scene.
#include "mpm/explicit/simulation.hpp"
#include "mpm/implicit/simulation.hpp"
#include "mpm/scene/build.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm::testing {

/// Build the scene's simulation (ImplicitSimulation when its integrator is "implicit", Simulation otherwise,
/// with its kernel) from its seeded bodies, and call fn(simulation).
template <int Dim, class Fn>
void with_scene_simulation(const Scene& sc, Fn&& fn) {
  with_kernel<Dim>(sc.kernel, [&]<class K>() {
    if (sc.implicit) {
      ImplicitSimulation<Dim, K> sim(make_implicit_spec<Dim>(sc), seed_bodies<Dim>(sc));
      fn(sim);
    } else {
      Simulation<Dim, K> sim(make_spec<Dim>(sc), seed_bodies<Dim>(sc));
      fn(sim);
    }
  });
}

}  // namespace mpm::testing
