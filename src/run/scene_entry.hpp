#pragma once
// The run loop's entry points for one engine: run_scene_on (SceneRun, scene_run.hpp) and open_session_on
// (SceneSession, scene_session.hpp). Declared here and instantiated once per engine, dimension and kernel, in
// one generated unit per dimension (CMakeLists.txt, cmake/instantiate.cmake), so that run.cpp and session.cpp
// choose among them without compiling the loop.
#include <memory>

#include "mpm/run/run.hpp"
#include "mpm/run/session.hpp"
#include "mpm/scene/scene.hpp"

namespace mpm {

namespace scene_engines {
template <int Dim, class Kernel>
class Explicit;
template <int Dim, class Kernel>
class Implicit;
}  // namespace scene_engines

/// Run a scene on `Engine` from its start or o.restart to its end; run_scene's exit status.
template <int Dim, class Engine>
int run_scene_on(const Scene& sc, const RunOptions& o);

/// Open a Session of a scene on `Engine`.
template <int Dim, class Engine>
std::unique_ptr<Session> open_session_on(const Scene& sc, const RunOptions& o);

}  // namespace mpm
