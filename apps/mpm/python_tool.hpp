#pragma once
// Runs the Python helpers embedded in the program (plots, pictures) with Debian's python3.
#include <string>
#include <string_view>
#include <vector>

namespace mpm::app {

/// Run the embedded script `name` (see python/*.py) with the given arguments through python3 ($MPM_PYTHON, or
/// /usr/bin/python3 when it exists, or python3 on the PATH). Throws ToolError naming `what` (the option that
/// asked for it) when python3 is missing or the script fails.
void run_python(std::string_view name, const std::vector<std::string>& args, const std::string& what);

}  // namespace mpm::app
