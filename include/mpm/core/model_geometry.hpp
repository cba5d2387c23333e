#pragma once
/// How a 2-D model stands for a 3-D body.
#include <string_view>

namespace mpm {

/// Plane strain (eps_zz = 0), plane stress (sigma_zz = 0), or a body of revolution about x = 0 with
/// (x, y) = (r, z) (hoop strain rate v_r / r; masses and volumes per radian). 1-D and 3-D runs are plane
/// strain.
enum class Geometry { plane_strain, plane_stress, axisymmetric };

Geometry parse_geometry(std::string_view name, std::string_view key);
std::string_view to_string(Geometry g);

}  // namespace mpm
