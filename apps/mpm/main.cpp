// The `mpm` command-line program.
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <new>
#include <string>
#include <utility>

#include "commands.hpp"
#include "mpm/core/build_info.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/distributed/communicator.hpp"

namespace {

/// Error messages come from rank 0 alone when a launcher started several processes (they all meet the same
/// input); in one process, from it.
std::ostream& say() {
  static std::ostream null(nullptr);
  return mpm::launched_rank() == 0 ? std::cerr : null;
}

/// Started among several processes (mpirun, srun): only `mpm run` and `mpm bench` of an MPI build divide
/// their work between them. Otherwise say so once, from rank 0, so that the copies do not all write the same
/// output; true when the command must not go on.
bool refused_among_several(const std::string& command) {
  const int size = mpm::launched_size();
  if (size <= 1 || ((command == "run" || command == "bench") && mpm::built_with_mpi())) return false;
  say() << "mpm: started as one of " << size << " processes, but "
        << (mpm::built_with_mpi()
                ? "mpm " + command +
                      " runs in one process (mpm run and mpm bench divide their work between ranks)"
                : std::string("this mpm was built without MPI and runs in one process"))
        << "; start it without mpirun or srun (docs/scaling.md)\n";
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  // A write past the file-size limit (ulimit -f) fails with EFBIG and is reported, instead of killing the
  // program.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"mpm: material point method for large-deformation solids"};
  app.set_version_flag("--version", mpm::build_info_text());
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
  } catch (const CLI::CallForVersion& e) {
    std::cout << mpm::build_info_text();
    return 0;
  } catch (const CLI::ParseError& e) {
    if (argc == 1) {  // no subcommand at all: what there is to run
      say() << app.help();
      return mpm::exit_input_error;
    }
    say() << "mpm: " << e.what() << '\n';
    return mpm::exit_input_error;
  }
  if (refused_among_several(app.get_subcommands().front()->get_name())) return mpm::exit_input_error;
  // MPI starts only for a command that uses it, and only under a launcher (MpiSession).
  const mpm::MpiSession mpi(argc, argv);
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
    say() << "mpm: " << e.what() << '\n';
    return mpm::exit_input_error;
  } catch (const mpm::SimulationFailure& e) {
    say() << "mpm: simulation failed: " << e.what() << '\n';
    return mpm::exit_simulation_failure;
  } catch (const mpm::ToolError& e) {
    say() << "mpm: " << e.what() << '\n';
    return mpm::exit_tool_error;
  } catch (const mpm::OutputError& e) {
    say() << "mpm: " << e.what() << '\n';
    return mpm::exit_output_failure;
  } catch (const std::bad_alloc&) {
    say() << "mpm: out of memory (see the budget line; --dry-run estimates a run's memory)\n";
    return mpm::exit_simulation_failure;
  } catch (const std::filesystem::filesystem_error& e) {
    say() << "mpm: " << e.what() << '\n';
    return mpm::exit_output_failure;
  } catch (const std::exception& e) {
    say() << "mpm: internal error: " << e.what() << '\n';
    return mpm::exit_simulation_failure;
  }
  return 0;
}
