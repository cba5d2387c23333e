#pragma once
/// The ways a command can stop early: bad input (exit 2), numerical failure or an output that cannot be
/// written (exit 1), a missing or failing helper tool such as python3 for plots (exit 3), and a run
/// interrupted by SIGINT or SIGTERM (exit 128 + the signal: 130, 143).
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

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

/// Throws InputError(message) unless `ok`: the validators' one-line checks.
inline void require(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}

/// A text the user gave, for messages: cut to 80 characters (a 10,000-character value would otherwise fill
/// the message).
inline std::string shortened(std::string_view text) {
  return text.size() > 80 ? std::string(text.substr(0, 77)) + "..." : std::string(text);
}

/// shortened(text) in quotes.
inline std::string in_quotes(std::string_view text) {
  std::string out = "'";
  out += shortened(text);
  out += '\'';
  return out;
}

/// The Enum whose index in `names` is that of `name`; otherwise InputError naming `key` and the expected
/// names.
template <class Enum, class Names>
Enum parse_name(const Names& names, std::string_view name, std::string_view key) {
  std::string list;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (name == names[k]) return static_cast<Enum>(k);
    list += (k ? ", " : "") + std::string(names[k]);
  }
  throw InputError(std::string(key) + ": unknown name " + in_quotes(name) + " (expected one of " + list +
                   ")");
}

inline constexpr int exit_input_error = 2;
inline constexpr int exit_tool_error = 3;
inline constexpr int exit_simulation_failure = 1;
inline constexpr int exit_output_failure = 1;
/// The exit status of a run stopped by signal `signal` (the shell's convention): 130 for SIGINT, 143 for
/// SIGTERM.
inline constexpr int exit_interrupted(int signal) {
  return 128 + signal;
}

}  // namespace mpm
