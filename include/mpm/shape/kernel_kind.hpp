#pragma once
/// The kernels a scene names (KernelKind) and their registry (kernel_registry): names, labels, policies and
/// what each asks of the particles and the grid. The policies that compute them are listed in
/// shape/kernel_policies.hpp.
#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/core/types.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// Shape functions: linear MPM, GIMP with fixed (uGIMP) or deformed (cpGIMP) particle sizes, B-splines,
/// B-splines whose knots are clamped at the grid's faces (Steffen et al. 2008, Sec. 4.3), CPDI (Sadeghirad et
/// al. 2011), the GIMP kinds on a stencil one node wider, for half-lengths up to a cell, and CPDI2
/// (Sadeghirad et al. 2013).
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

/// One kernel a scene names and what it asks of the particles and the grid. The registry below is the one
/// list of kernels: their names in scenes, on the command line, in Python and summaries, the help texts and
/// plot labels, the dispatch to a policy (with_kernel) and the predicates below derive from it.
struct KernelEntry {
  KernelKind kind;
  std::string_view name;      ///< in scenes, on the command line, in Python and summaries
  std::string_view label;     ///< in convergence plots (Wallstedt & Guilkey 2008's names where they have one)
  std::size_t policy;         ///< its entry of KernelPolicies (shape/kernel_policies.hpp)
  bool gimp;                  ///< its particles' half-lengths shape the weights (GIMP)
  bool deforms_half_lengths;  ///< l_p = l_p0 diag(F) (cpGIMP, Wallstedt & Guilkey 2008, Eq. (63))
  Real max_half_length;       ///< GIMP: the largest half-length its stencil holds, in cells
  int clamped_cells;  ///< > 0: it clamps the B-splines' knots at the faces and needs this many cells an axis
};

// clang-format off
inline constexpr std::array<KernelEntry, 11> kernel_registry{{
    // kind                          name                label      policy gimp   deforms max_l clamped
    {KernelKind::linear,           "linear",           "MPM",     0,     false, false,  0,    0},
    {KernelKind::ugimp,            "ugimp",            "uGIMP",   1,     true,  false,  0.5,  0},
    {KernelKind::cpgimp,           "cpgimp",           "cpGIMP",  1,     true,  true,   0.5,  0},
    {KernelKind::bspline2,         "bspline2",         "B2",      3,     false, false,  0,    0},
    {KernelKind::bspline3,         "bspline3",         "B3",      4,     false, false,  0,    0},
    {KernelKind::bspline2_clamped, "bspline2-clamped", "B2c",     3,     false, false,  0,    2},
    {KernelKind::bspline3_clamped, "bspline3-clamped", "B3c",     4,     false, false,  0,    3},
    {KernelKind::cpdi,             "cpdi",             "CPDI",    5,     false, false,  0,    0},
    {KernelKind::ugimp_wide,       "ugimp-wide",       "uGIMPw",  2,     true,  false,  1,    0},
    {KernelKind::cpgimp_wide,      "cpgimp-wide",      "cpGIMPw", 2,     true,  true,   1,    0},
    {KernelKind::cpdi2,            "cpdi2",            "CPDI2",   6,     false, false,  0,    0},
}};
// clang-format on

/// The registry's entry of a kernel kind.
constexpr const KernelEntry& kernel_entry(KernelKind k) {
  return kernel_registry[static_cast<std::size_t>(k)];
}
static_assert(
    [] {
      for (std::size_t i = 0; i < kernel_registry.size(); ++i)
        if (static_cast<std::size_t>(kernel_registry[i].kind) != i) return false;
      return true;
    }(),
    "kernel_registry lists the kernel kinds in the order of KernelKind");

/// Whether a kernel kind is GIMP's, whose particles' half-lengths shape the weights.
inline bool is_gimp(KernelKind k) {
  return kernel_entry(k).gimp;
}

/// Whether a kernel kind's half-lengths follow the diagonal of F, l_p = l_p0 diag(F) (cpGIMP, Wallstedt &
/// Guilkey 2008, Eq. (63)).
inline bool deforms_half_lengths(KernelKind k) {
  return kernel_entry(k).deforms_half_lengths;
}

/// How a kernel kind's particles' current half-lengths follow from l_p^0 (ParticleSet::half_lengths), set by
/// both engines before they validate them; an engine whose kernel reads none then drops them.
inline HalfLengths half_lengths_of(KernelKind k) {
  return deforms_half_lengths(k) ? HalfLengths::deformed : HalfLengths::fixed;
}

/// The largest half-length a GIMP kind's stencil holds, in cells: 1/2, or 1 for the wide kinds.
inline Real max_half_length(KernelKind k) {
  return kernel_entry(k).max_half_length;
}

/// What a GIMP kind's particles may not outgrow, "(0, h/2]" or "(0, h]", and the kernel that takes larger
/// ones.
std::string half_length_bound(KernelKind k);

/// Throws InputError (prefixed with `at`) when a GIMP kind's particle has a half-length outside (0,
/// max_half_length h].
template <int Dim>
void validate_half_lengths(KernelKind k, const Vec<Dim>& l, Real h, const std::string& at);

/// Whether a kernel kind clamps the B-splines' knots at the grid's faces.
inline bool clamps_knots(KernelKind k) {
  return kernel_entry(k).clamped_cells > 0;
}

/// The faces a kernel kind clamps its knots at (GridGeometry::clamped): every face but the periodic ones for
/// the clamped B-splines, none for the other kernels.
template <int Dim>
std::array<bool, 2 * Dim> clamped_faces(KernelKind k, const BoundarySpec<Dim>& spec) {
  std::array<bool, 2 * Dim> faces{};
  for (int f = 0; f < 2 * Dim; ++f) faces[f] = clamps_knots(k) && spec.faces[f].type != FaceType::periodic;
  return faces;
}

/// The cells a clamped B-spline needs along each axis it clamps, so that the stencils of its two faces do not
/// overlap: its width less one (2 quadratic, 3 cubic); 0 for the other kernels.
inline int clamped_cells_needed(KernelKind k) {
  return kernel_entry(k).clamped_cells;
}

/// Throws InputError (prefixed with `at`) unless each axis a clamped B-spline clamps has clamped_cells_needed
/// cells.
template <int Dim>
void validate_clamped_cells(KernelKind k, const BoundarySpec<Dim>& spec, const IVec<Dim>& cells,
                            const std::string& at);

/// Parse a kernel name; throws InputError naming `key` and the expected values.
KernelKind parse_kernel(std::string_view name, std::string_view key = "kernel");
inline std::string_view to_string(KernelKind k) {
  return kernel_entry(k).name;
}
/// Every kernel's name, in the registry's order.
std::vector<std::string> kernel_names();
/// The names as a help text: "linear, ugimp, ... or cpdi2".
std::string kernel_name_list();

}  // namespace mpm
