// Runs the embedded Python helpers (scripts compiled into the program by CMake, see embed_python.cmake).
#include "python_tool.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "embedded_python.hpp"
#include "mpm/core/errors.hpp"

namespace mpm::app {

namespace {
std::string interpreter() {
  if (const char* env = std::getenv("MPM_PYTHON"); env && *env) return env;
  if (std::filesystem::exists("/usr/bin/python3")) return "/usr/bin/python3";
  return "python3";
}

std::string_view script_text(std::string_view name) {
  for (const EmbeddedScript& s : embedded_scripts)
    if (s.name == name) return s.text;
  throw ToolError("no embedded script named " + std::string(name));
}

/// A private temporary file holding the script, removed when the run ends.
struct TemporaryScript {
  std::filesystem::path path;
  explicit TemporaryScript(std::string_view text) {
    std::string pattern = (std::filesystem::temp_directory_path() / "mpm-XXXXXX.py").string();
    const int fd = mkstemps(pattern.data(), 3);
    if (fd < 0)
      throw ToolError("cannot create a temporary file in " + std::filesystem::temp_directory_path().string());
    close(fd);
    path = pattern;
    std::ofstream(path) << text;
  }
  ~TemporaryScript() {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
  }
};
}  // namespace

void run_python(std::string_view name, const std::vector<std::string>& args, const std::string& what) {
  const TemporaryScript script(script_text(name));
  const std::string python = interpreter();
  std::vector<std::string> argv_text{python, script.path.string()};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) throw ToolError(what + ": cannot start " + python);
  if (pid == 0) {
    execvp(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code == 127) throw ToolError(what + ": needs python3 (" + python + " was not found); set MPM_PYTHON");
  if (code == 3)
    throw ToolError(what + ": needs Debian's python3-matplotlib (apt-get install python3-matplotlib)");
  if (code == 4) throw InputError(what + ": invalid request (see the line above)");
  if (code != 0)
    throw ToolError(what + ": the " + std::string(name) + " helper failed (exit " + std::to_string(code) +
                    ")");
}

}  // namespace mpm::app
