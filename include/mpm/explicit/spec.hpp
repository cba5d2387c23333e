#pragma once
/// Plain parameter structs describing an explicit simulation, validated in full before anything is built.
#include <array>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/boundary/rigid_body.hpp"
#include "mpm/boundary/surface_loads.hpp"
#include "mpm/contact/multi_field.hpp"
#include "mpm/core/model_geometry.hpp"
#include "mpm/core/types.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/materials/material.hpp"

namespace mpm {

/// Explicit time integrators of Wallstedt & Guilkey 2008: update stress first (USF) or last (USL), centered
/// difference (CD) and the update-velocity-first / modified USL variant (UVF-MPM, "musl").
enum class Integrator { usf, usl, cd, musl };

/// Shape functions: linear MPM, GIMP with fixed (uGIMP) or deformed (cpGIMP) particle sizes, B-splines, B-splines
/// whose knots are clamped at the grid's faces (Steffen et al. 2008, Sec. 4.3), CPDI (Sadeghirad et al. 2011),
/// the GIMP kinds on a stencil one node wider, for half-lengths up to a cell, and CPDI2 (Sadeghirad et al. 2013).
enum class KernelKind {
  linear,
  ugimp,
  cpgimp,
  bspline2,
  bspline3,
  bspline2_clamped,
  bspline3_clamped,
  cpdi,
  ugimp_wide,
  cpgimp_wide,
  cpdi2
};

/// Whether a kernel kind is GIMP's, whose particles' half-lengths shape the weights.
inline bool is_gimp(KernelKind k) {
  return k == KernelKind::ugimp || k == KernelKind::cpgimp || k == KernelKind::ugimp_wide ||
         k == KernelKind::cpgimp_wide;
}

/// Whether a kernel kind's half-lengths follow the diagonal of F, l_p = l_p0 diag(F) (cpGIMP, Wallstedt & Guilkey
/// 2008, Eq. (63)).
inline bool deforms_half_lengths(KernelKind k) { return k == KernelKind::cpgimp || k == KernelKind::cpgimp_wide; }

/// How a kernel kind's particles' current half-lengths follow from l_p^0 (ParticleSet::half_lengths), set by both
/// engines before they validate them; an engine whose kernel reads none then drops them.
inline HalfLengths half_lengths_of(KernelKind k) {
  return deforms_half_lengths(k) ? HalfLengths::deformed : HalfLengths::fixed;
}

/// The largest half-length a GIMP kind's stencil holds, in cells: 1/2, or 1 for the wide kinds.
inline Real max_half_length(KernelKind k) {
  return k == KernelKind::ugimp_wide || k == KernelKind::cpgimp_wide ? 1 : 0.5;
}

/// What a GIMP kind's particles may not outgrow, "(0, h/2]" or "(0, h]", and the kernel that takes larger ones.
std::string half_length_bound(KernelKind k);

/// Throws InputError (prefixed with `at`) when a GIMP kind's particle has a half-length outside (0, max_half_length h].
template <int Dim>
void validate_half_lengths(KernelKind k, const Vec<Dim>& l, Real h, const std::string& at);

/// Whether a kernel kind clamps the B-splines' knots at the grid's faces.
inline bool clamps_knots(KernelKind k) {
  return k == KernelKind::bspline2_clamped || k == KernelKind::bspline3_clamped;
}

/// The faces a kernel kind clamps its knots at (GridGeometry::clamped): every face but the periodic ones for the
/// clamped B-splines, none for the other kernels.
template <int Dim>
std::array<bool, 2 * Dim> clamped_faces(KernelKind k, const BoundarySpec<Dim>& spec) {
  std::array<bool, 2 * Dim> faces{};
  for (int f = 0; f < 2 * Dim; ++f) faces[f] = clamps_knots(k) && spec.faces[f].type != FaceType::periodic;
  return faces;
}

/// The cells a clamped B-spline needs along each axis it clamps, so that the stencils of its two faces do not
/// overlap: its width less one (2 quadratic, 3 cubic); 0 for the other kernels.
inline int clamped_cells_needed(KernelKind k) {
  return k == KernelKind::bspline3_clamped ? 3 : k == KernelKind::bspline2_clamped ? 2 : 0;
}

/// Throws InputError (prefixed with `at`) unless each axis a clamped B-spline clamps has clamped_cells_needed cells.
template <int Dim>
void validate_clamped_cells(KernelKind k, const BoundarySpec<Dim>& spec, const IVec<Dim>& cells, const std::string& at);

/// How particle velocities come from the grid: FLIP (blended with PIC by flip_fraction), or APIC (Jiang et al.
/// 2015), which keeps an affine matrix B_p per particle and carries the particle's angular momentum both ways.
enum class Transfer { flip, apic };

/// Body acceleration b(X, t) as a function of reference position and time [m/s^2].
template <int Dim>
using BodyForceFn = std::function<Vec<Dim>(const Vec<Dim>& X, Real t)>;

template <int Dim>
struct SimulationSpec {
  Vec<Dim> grid_lo = Vec<Dim>::Zero();  ///< position of the first node [m]
  Real h = 0;                           ///< cell width [m]
  IVec<Dim> cells{};                    ///< cells per axis
  Integrator integrator = Integrator::usl;
  KernelKind kernel = KernelKind::linear;
  /// Neo-Hookean (hyperelastic) and rate-form (hypoelastic, von Mises) materials, in any mix.
  std::vector<Material> materials;
  /// 2-D only: plane strain, or with rate-form materials plane stress and axisymmetry (masses and volumes of
  /// the particles given per unit thickness become per radian, times r).
  Geometry geometry = Geometry::plane_strain;
  BoundarySpec<Dim> boundary;
  std::vector<RigidBody<Dim>> rigid_bodies;
  /// Velocity fields and their contact (one field by default): each particle projects to field
  /// ParticleSet::field.
  ContactSpec contact;
  Vec<Dim> gravity = Vec<Dim>::Zero();  ///< [m/s^2]
  /// Local non-viscous damping alpha in [0, 1) of the grid update (node_update; Cundall 1987): 0 is none. It brings
  /// a body quasi-statically to equilibrium (a gravity ramp, a slope), and it is not energy-conserving.
  Real local_damping = 0;
  /// alpha of the FLIP-PIC blend of the particle velocity update, in [0, 1]:
  /// v_p = alpha (v_p + dt sum_i S_ip a_i) + (1 - alpha) sum_i S_ip v_i. 1 is FLIP (Wallstedt & Guilkey 2008,
  /// Eq. (18)), 0 is PIC, which filters each velocity mode by the kernel's P2G-G2P round trip every step (it
  /// dissipates; docs/transfers.md).
  Real flip_fraction = 1;
  /// APIC: v_p = sum_i S_ip v_i and B_p = sum_i S_ip v_i (x) (x_i - x_p) after the velocity update, P2G with
  /// m_p (v_p + B_p D_p^-1 (x_i - x_p)) (transfer/g2p.hpp, p2g.hpp; docs/transfers.md). flip_fraction stays 1.
  Transfer transfer = Transfer::flip;
  BodyForceFn<Dim> body_force;          ///< optional b(X, t), evaluated at the start of each step
  /// Pressures and tractions on the surfaces of bodies, carried by their surface particles as body forces.
  SurfaceLoads<Dim> surface_loads;
  Real dt = 0;                          ///< fixed time step [s], or 0 to use the CFL number
  Real cfl = 0;                         ///< dt = cfl h / max_p (c_p + |v_p|) when dt == 0
  /// CD and UVF-MPM: the particle velocities given are v^{-1/2}, so the first grid acceleration is not halved
  /// (Wallstedt & Guilkey 2008, Sec. 4: the start from exact half-step data); false starts from v^0.
  bool half_step_velocity_given = false;
  /// USL and CD with the linear kernel: move and deform particles with the re-projected velocity on nodes that
  /// carry less than a quarter of the lightest particle's mass (Sulsky & Kaul 2004, Eq. (3.2.7)); false runs
  /// the papers' algorithms unchanged (Wallstedt & Guilkey 2008, Eq. (37), Eq. (38), Eq. (39)). Scenes default to true.
  bool reproject_light_nodes = false;
  /// Account the power of gravity and the body force in each step (Simulation::load_power), for an energy
  /// balance; scenes do, the benchmark does not.
  bool account_load_power = false;
  /// Divided between ranks: the grid is divided again when the rank holding the most particles holds more than
  /// this many times the mean (checked after every step, at most once every rebalance_interval steps).
  Real rebalance_above = 1.2;
  int rebalance_interval = 10;
};

/// Parse a name; throws InputError naming `key` and the expected values.
Integrator parse_integrator(std::string_view name, std::string_view key = "integrator");
KernelKind parse_kernel(std::string_view name, std::string_view key = "kernel");
std::string_view to_string(Integrator i);
std::string_view to_string(KernelKind k);

/// Throw InputError with a clear message for the first invalid field.
template <int Dim>
void validate(const SimulationSpec<Dim>& spec);

}  // namespace mpm
