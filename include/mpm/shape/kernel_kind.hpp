#pragma once
/// The kernels a scene names (KernelKind), what each asks of the particles and the grid, and their names. The
/// policies that compute them are listed in shape/kernel_policies.hpp.
#include <array>
#include <string>
#include <string_view>

#include "mpm/boundary/boundary.hpp"
#include "mpm/core/types.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

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

/// Parse a kernel name; throws InputError naming `key` and the expected values.
KernelKind parse_kernel(std::string_view name, std::string_view key = "kernel");
std::string_view to_string(KernelKind k);

}  // namespace mpm
