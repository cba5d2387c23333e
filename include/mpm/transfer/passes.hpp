#pragma once
/// How particle velocities come from the grid (Transfer), and what the transfer passes are told to do and
/// report, as the engines name them (Scatter, Gather, ParticleFault, LightMass). The passes are in
/// transfer/p2g.hpp and transfer/g2p.hpp, which only the units that compile an engine include.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "mpm/core/types.hpp"

namespace mpm {

/// What a P2G pass of the explicit step scatters.
struct Scatter {
  bool mass_momentum;
  bool force;
  bool volume_gradient = false;  ///< with mass_momentum: VolumeGradient into v_new (contact normals)
};

/// What a G2P pass updates.
struct Gather {
  bool velocity;     ///< v_p += dt sum_i S_ip a_i                       (Wallstedt & Guilkey 2008, Eq. (18))
  bool position;     ///< x_p += dt sum_i S_ip v_i                       (Wallstedt & Guilkey 2008, Eq. (17))
  bool deformation;  ///< grad v_p = sum_i v_i grad S_ip, F, V, sigma     (Wallstedt & Guilkey 2008, Eq. (10),
                     ///< Eq. (11), Eq. (12), Eq. (13), or Eq. (19))
};

/// The first particle (lowest index) that failed in a pass, if any.
struct ParticleFault {
  static constexpr std::int64_t none = std::numeric_limits<std::int64_t>::max();
  std::int64_t index = none;
  explicit operator bool() const { return index != none; }
};

/// The mass below which a node is light: a fixed mass, or in axisymmetry, where masses are per radian and
/// grow with the radius, a mass per unit radius times the node's radius |r_i|.
template <int Dim>
struct LightMass {
  Real mass = 0;        ///< [kg]; 0: no node is light
  Real per_radius = 0;  ///< [kg/m per radian]; > 0 in axisymmetry, which then ignores `mass`
  Real lo = 0, h = 1;   ///< the grid's radial origin and cell width [m]
  int nodes_along = 1, ghost = 0;

  bool any() const { return mass > 0 || per_radius > 0; }
  Real operator()(std::ptrdiff_t n) const {
    if (per_radius == 0) return mass;
    return per_radius * std::abs(lo + h * static_cast<Real>(n % nodes_along - ghost));
  }
};

/// How particle velocities come from the grid: FLIP (blended with PIC by flip_fraction), or APIC (Jiang et
/// al. 2015), which keeps an affine matrix B_p per particle and carries the particle's angular momentum both
/// ways.
enum class Transfer { flip, apic };

}  // namespace mpm
