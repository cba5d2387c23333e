#pragma once
// Sub-commands of the `mpm` program; each registers its options and returns the action to run.
#include <CLI/CLI.hpp>
#include <functional>

namespace mpm::app {

using Action = std::function<int()>;

Action add_bench(CLI::App& app);
Action add_verify(CLI::App& app);
Action add_converge(CLI::App& app);
Action add_density(CLI::App& app);
Action add_run(CLI::App& app);
Action add_render(CLI::App& app);

}  // namespace mpm::app
