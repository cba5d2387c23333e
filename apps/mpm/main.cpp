// The `mpm` command-line program.
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <new>
#include <string>
#include <utility>

#include "commands.hpp"
#include "mpm/core/errors.hpp"

namespace {

/// The value of a whole-number environment variable, or `otherwise` when it is unset or not a number.
long env_number(const char* name, long otherwise) {
  const char* text = std::getenv(name);
  if (!text || !*text) return otherwise;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  return *end ? otherwise : value;
}

/// When an MPI launcher started this process among several (OpenMPI's mpirun sets OMPI_COMM_WORLD_SIZE; MPICH's
/// mpiexec and Slurm's srun with PMI set PMI_SIZE): say once, from rank 0, that this build runs in one process,
/// so that the copies do not all write the same output; true when the run must not go on.
bool started_among_several() {
  for (const auto& [size_name, rank_name] : {std::pair{"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"},
                                             std::pair{"PMI_SIZE", "PMI_RANK"}}) {
    const long size = env_number(size_name, 1);
    if (size <= 1) continue;
    if (env_number(rank_name, 0) == 0)
      std::cerr << "mpm: started as one of " << size << " processes (" << size_name << "=" << size
                << "), but mpm runs in one process (threads: --threads); start it without mpirun or srun "
                   "(docs/scaling.md)\n";
    return true;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  // A write past the file-size limit (ulimit -f) fails with EFBIG and is reported, instead of killing the program.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"mpm: material point method for large-deformation solids"};
  app.require_subcommand(1);
  const mpm::app::Action bench = mpm::app::add_bench(app);
  const mpm::app::Action verify = mpm::app::add_verify(app);
  const mpm::app::Action converge = mpm::app::add_converge(app);
  const mpm::app::Action density = mpm::app::add_density(app);
  const mpm::app::Action run = mpm::app::add_run(app);
  const mpm::app::Action render = mpm::app::add_render(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "mpm: " << e.what() << '\n';
    return mpm::exit_input_error;
  }
  if (started_among_several()) return mpm::exit_input_error;
  try {
    for (CLI::App* sub : app.get_subcommands()) {
      if (sub->get_name() == "bench") return bench();
      if (sub->get_name() == "verify") return verify();
      if (sub->get_name() == "converge") return converge();
      if (sub->get_name() == "density-1d") return density();
      if (sub->get_name() == "run") return run();
      if (sub->get_name() == "render") return render();
    }
  } catch (const mpm::InputError& e) {
    std::cerr << "mpm: " << e.what() << '\n';
    return mpm::exit_input_error;
  } catch (const mpm::SimulationFailure& e) {
    std::cerr << "mpm: simulation failed: " << e.what() << '\n';
    return mpm::exit_simulation_failure;
  } catch (const mpm::ToolError& e) {
    std::cerr << "mpm: " << e.what() << '\n';
    return mpm::exit_tool_error;
  } catch (const mpm::OutputError& e) {
    std::cerr << "mpm: " << e.what() << '\n';
    return mpm::exit_output_failure;
  } catch (const std::bad_alloc&) {
    std::cerr << "mpm: out of memory (see the budget line; --dry-run estimates a run's memory)\n";
    return mpm::exit_simulation_failure;
  } catch (const std::filesystem::filesystem_error& e) {
    std::cerr << "mpm: " << e.what() << '\n';
    return mpm::exit_output_failure;
  } catch (const std::exception& e) {
    std::cerr << "mpm: internal error: " << e.what() << '\n';
    return mpm::exit_simulation_failure;
  }
  return 0;
}
