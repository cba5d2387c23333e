#include "mpm/shape/kernel_kind.hpp"

#include <array>
#include <string>
#include <string_view>

#include "mpm/core/errors.hpp"

namespace mpm {

namespace {
constexpr std::array<std::string_view, 11> kernel_names{
    "linear", "ugimp", "cpgimp", "bspline2", "bspline3", "bspline2-clamped", "bspline3-clamped", "cpdi", "ugimp-wide",
    "cpgimp-wide", "cpdi2"};
}  // namespace

KernelKind parse_kernel(std::string_view name, std::string_view key) {
  return parse_name<KernelKind>(kernel_names, name, key);
}

std::string_view to_string(KernelKind k) {
  return kernel_names[static_cast<std::size_t>(k)];
}

std::string half_length_bound(KernelKind k) {
  if (max_half_length(k) < 1)
    return "(0, h/2] (kernel = \"" + std::string(to_string(k)) + "-wide\" takes half-lengths up to h, kernel = \"cpdi\" "
           "follows any deformation)";
  return "(0, h] (kernel = \"cpdi\" follows any deformation)";
}

template <int Dim>
void validate_half_lengths(KernelKind k, const Vec<Dim>& l, Real h, const std::string& at) {
  if (!is_gimp(k)) return;
  for (int d = 0; d < Dim; ++d)
    require(l[d] > 0 && l[d] <= max_half_length(k) * h,
            at + ": GIMP half-length " + std::to_string(l[d]) + " must lie in " + half_length_bound(k));
}
template void validate_half_lengths<1>(KernelKind, const Vec<1>&, Real, const std::string&);
template void validate_half_lengths<2>(KernelKind, const Vec<2>&, Real, const std::string&);
template void validate_half_lengths<3>(KernelKind, const Vec<3>&, Real, const std::string&);

template <int Dim>
void validate_clamped_cells(KernelKind k, const BoundarySpec<Dim>& spec, const IVec<Dim>& cells, const std::string& at) {
  const std::array<bool, 2 * Dim> clamped = clamped_faces(k, spec);
  const int needed = clamped_cells_needed(k);
  for (int d = 0; d < Dim; ++d)
    require(!clamped[2 * d] || cells[d] >= needed,
            at + "grid.cells: kernel = \"" + std::string(to_string(k)) + "\" needs at least " + std::to_string(needed) +
                " cells along each axis it clamps (axis " + std::to_string(d) + " has " + std::to_string(cells[d]) + ")");
}

template void validate_clamped_cells<1>(KernelKind, const BoundarySpec<1>&, const IVec<1>&, const std::string&);
template void validate_clamped_cells<2>(KernelKind, const BoundarySpec<2>&, const IVec<2>&, const std::string&);
template void validate_clamped_cells<3>(KernelKind, const BoundarySpec<3>&, const IVec<3>&, const std::string&);

}  // namespace mpm
