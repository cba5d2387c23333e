#pragma once
// The run loop's entry points: run_scene_on (SceneRun, scene_run.hpp) and open_session_on (SceneSession,
// scene_session.hpp), instantiated once per dimension, on an engine that make_engine builds, instantiated
// once per engine, dimension and kernel. Each goes into generated units (CMakeLists.txt,
// cmake/instantiate.cmake), so that run.cpp and session.cpp choose among them without compiling the loop.
#include <memory>

#include "mpm/run/run.hpp"
#include "mpm/run/session.hpp"
#include "mpm/scene/scene.hpp"
#include "mpm/shape/kernel_policies.hpp"

namespace mpm {

template <int Dim>
class SceneEngine;

namespace scene_engines {
template <int Dim, class Kernel>
class Explicit;
template <int Dim, class Kernel>
class Implicit;
}  // namespace scene_engines

/// An engine of a scene: scene_engines::Explicit or Implicit behind SceneEngine.
template <int Dim>
using EngineFactory = std::unique_ptr<SceneEngine<Dim>> (*)(const Scene&);
template <int Dim, class Engine>
std::unique_ptr<SceneEngine<Dim>> make_engine(const Scene& sc);

/// Run a scene on the engine `make` builds from its start or o.restart to its end; run_scene's exit status.
template <int Dim>
int run_scene_on(const Scene& sc, const RunOptions& o, EngineFactory<Dim> make);

/// Open a Session of a scene on the engine `make` builds.
template <int Dim>
std::unique_ptr<Session> open_session_on(const Scene& sc, const RunOptions& o, EngineFactory<Dim> make);

/// The factory of the scene's engine: its integrator's, with its kernel.
template <int Dim>
EngineFactory<Dim> engine_of(const Scene& sc) {
  return with_kernel<Dim>(sc.kernel, [&]<class Kernel>() -> EngineFactory<Dim> {
    if (sc.implicit) return &make_engine<Dim, scene_engines::Implicit<Dim, Kernel>>;
    return &make_engine<Dim, scene_engines::Explicit<Dim, Kernel>>;
  });
}

}  // namespace mpm
