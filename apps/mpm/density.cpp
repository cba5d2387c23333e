// `mpm density-1d`: the projected density field of Steffen et al. 2008, Fig. 7, for one kernel.
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "mpm/shape/kernel_kind.hpp"
#include "mpm/verification/projected_density.hpp"

namespace mpm::app {

Action add_density(CLI::App& app) {
  struct Options {
    std::string kernel = "linear";
    DensityCase c;
    double gimp_length = 0;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "density-1d",
      "project a constant-density bar on [0, 1] to a grid on [-0.2, 1.2] (Steffen et al. 2008, Fig. 7)");
  cmd->add_option("--kernel", o->kernel, kernel_name_list());
  cmd->add_option("--cells", o->c.cells, "cells per unit length (a multiple of 5)");
  cmd->add_option("--ppc", o->c.ppc, "particles per cell");
  cmd->add_option("--samples", o->c.samples, "points at which the field is evaluated");
  cmd->add_flag("--aligned", o->c.boundary_aligned, "the grid is [0, 1], the body's own extent (Sec. 4.3)");
  CLI::Option* length =
      cmd->add_option("--gimp-length", o->gimp_length, "uGIMP smoothing length l in (0, h]");
  cmd->add_flag("--json", o->json, "print JSON with the nodal and sampled fields");
  return [o, length]() {
    o->c.kernel = parse_kernel(o->kernel, "--kernel");
    if (length->count() > 0) o->c.gimp_length = o->gimp_length;
    const DensityProjection d = project_density_1d(o->c);
    if (o->json) {
      std::cout << nlohmann::json{{"kernel", o->kernel},
                                  {"h", d.h},
                                  {"support_lo", d.support_lo},
                                  {"support_hi", d.support_hi},
                                  {"l1_error", d.l1_error},
                                  {"outside_mass", d.outside_mass},
                                  {"particle_x", d.particle_x},
                                  {"node_x", d.node_x},
                                  {"node_density", d.node_density},
                                  {"sample_x", d.sample_x},
                                  {"sample_density", d.sample_density}}
                       .dump()
                << '\n';
    } else {
      std::cout << "projected density, " << o->kernel << ", h = " << d.h << ": nonzero on [" << d.support_lo
                << ", " << d.support_hi << "] (body [0, 1]), L1 error " << d.l1_error
                << ", mass outside the body " << d.outside_mass << '\n';
    }
    return 0;
  };
}

}  // namespace mpm::app
