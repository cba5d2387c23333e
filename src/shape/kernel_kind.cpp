#include "mpm/shape/kernel_kind.hpp"

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "mpm/core/errors.hpp"

namespace mpm {

KernelKind parse_kernel(std::string_view name, std::string_view key) {
  std::array<std::string_view, kernel_registry.size()> names;
  for (std::size_t i = 0; i < names.size(); ++i) names[i] = kernel_registry[i].name;
  return parse_name<KernelKind>(names, name, key);
}

std::vector<std::string> kernel_names() {
  std::vector<std::string> names;
  for (const KernelEntry& e : kernel_registry) names.emplace_back(e.name);
  return names;
}

std::string kernel_name_list() {
  std::string list;
  for (std::size_t i = 0; i < kernel_registry.size(); ++i)
    list += (i == 0                            ? ""
             : i + 1 == kernel_registry.size() ? " or "
                                               : ", ") +
            std::string(kernel_registry[i].name);
  return list;
}

std::string half_length_bound(KernelKind k) {
  if (max_half_length(k) < 1)
    return "(0, h/2] (kernel = \"" + std::string(to_string(k)) +
           "-wide\" takes half-lengths up to h, kernel = \"cpdi\" "
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
void validate_clamped_cells(KernelKind k, const BoundarySpec<Dim>& spec, const IVec<Dim>& cells,
                            const std::string& at) {
  const std::array<bool, 2 * Dim> clamped = clamped_faces(k, spec);
  const int needed = clamped_cells_needed(k);
  for (int d = 0; d < Dim; ++d)
    require(!clamped[2 * d] || cells[d] >= needed,
            at + "grid.cells: kernel = \"" + std::string(to_string(k)) + "\" needs at least " +
                std::to_string(needed) + " cells along each axis it clamps (axis " + std::to_string(d) +
                " has " + std::to_string(cells[d]) + ")");
}

template void validate_clamped_cells<1>(KernelKind, const BoundarySpec<1>&, const IVec<1>&,
                                        const std::string&);
template void validate_clamped_cells<2>(KernelKind, const BoundarySpec<2>&, const IVec<2>&,
                                        const std::string&);
template void validate_clamped_cells<3>(KernelKind, const BoundarySpec<3>&, const IVec<3>&,
                                        const std::string&);

}  // namespace mpm
