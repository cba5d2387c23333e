#pragma once
/// What a model is, whichever engine runs it: the grid, the kernel and the transfer, the geometry, the
/// materials, the boundary and the rigid bodies, and the loads. The explicit engine's SimulationSpec and the
/// implicit engine's ImplicitSpec extend it with their integrators' settings.
#include <string>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/boundary/rigid_body.hpp"
#include "mpm/boundary/surface_loads.hpp"
#include "mpm/core/model_geometry.hpp"
#include "mpm/core/types.hpp"
#include "mpm/materials/material.hpp"
#include "mpm/shape/kernel_kind.hpp"
#include "mpm/transfer/passes.hpp"

namespace mpm {

template <int Dim>
struct ModelSpec {
  Vec<Dim> grid_lo = Vec<Dim>::Zero();  ///< position of the first node [m]
  Real h = 0;                           ///< cell width [m]
  IVec<Dim> cells{};                    ///< cells per axis
  KernelKind kernel = KernelKind::linear;
  /// 2-D only: plane strain, or with rate-form materials plane stress and axisymmetry (masses and volumes of
  /// the particles given per unit thickness become per radian, times r).
  Geometry geometry = Geometry::plane_strain;
  /// Neo-Hookean (hyperelastic) and rate-form materials, in any mix.
  std::vector<Material> materials;
  BoundarySpec<Dim> boundary;
  std::vector<RigidBody<Dim>> rigid_bodies;
  Vec<Dim> gravity = Vec<Dim>::Zero();  ///< [m/s^2]
  /// Optional b(X, t) [m/s^2]: the explicit step evaluates it at its start, the implicit step takes (1 -
  /// theta) b(X, t^k) + theta b(X, t^{k+1}).
  BodyForceFn<Dim> body_force;
  /// Pressures and tractions on the surfaces of bodies, carried by their surface particles as body forces.
  SurfaceLoads<Dim> surface_loads;
  /// alpha of the FLIP-PIC blend of the particle velocity update, in [0, 1]:
  /// v_p = alpha (v_p + dt sum_i S_ip a_i) + (1 - alpha) sum_i S_ip v_i. 1 is FLIP (Wallstedt & Guilkey 2008,
  /// Eq. (18)), 0 is PIC, which filters each velocity mode by the kernel's P2G-G2P round trip every step (it
  /// dissipates; docs/transfers.md). The implicit step blends its formulation's update (Sulsky & Kaul 2004,
  /// Eq. (2.3.3) or Eq. (3.2.6)) so.
  Real flip_fraction = 1;
  /// APIC: v_p = sum_i S_ip v_i and B_p = sum_i S_ip v_i (x) (x_i - x_p) after the velocity update, P2G with
  /// m_p (v_p + B_p D_p^-1 (x_i - x_p)) (transfer/g2p.hpp, p2g.hpp; docs/transfers.md). flip_fraction
  /// stays 1.
  Transfer transfer = Transfer::flip;
};

/// Throw InputError for the first invalid field of what both engines share; `at` prefixes every message.
template <int Dim>
void validate_model(const ModelSpec<Dim>& spec, const std::string& at);

}  // namespace mpm
