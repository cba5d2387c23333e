#pragma once
/// The ways a command can stop early: bad input (exit 2), numerical failure (exit 1), and a missing or failing
/// helper tool such as python3 for plots (exit 3).
#include <stdexcept>
#include <string>

namespace mpm {

/// Invalid user input: an argument, key or value that is not what was expected. Exit status 2.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A numerical failure during a run (non-finite value, J <= 0, particle off the grid). Exit status 1.
struct SimulationFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A helper program a command needs (python3 with matplotlib for plots and pictures) is missing or failed.
/// Exit status 3.
struct ToolError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

inline constexpr int exit_input_error = 2;
inline constexpr int exit_tool_error = 3;
inline constexpr int exit_simulation_failure = 1;

}  // namespace mpm
