#pragma once
/// The ways a command can stop early: bad input (exit 2), numerical failure or an output that cannot be written
/// (exit 1), a missing or failing helper tool such as python3 for plots (exit 3), and a run interrupted by
/// SIGINT or SIGTERM (exit 128 + the signal: 130, 143).
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

/// An output file that cannot be written (disk full, file-size limit, output folder removed). Exit status 1.
struct OutputError : std::runtime_error {
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
inline constexpr int exit_output_failure = 1;
/// The exit status of a run stopped by signal `signal` (the shell's convention): 130 for SIGINT, 143 for SIGTERM.
inline constexpr int exit_interrupted(int signal) { return 128 + signal; }

}  // namespace mpm
