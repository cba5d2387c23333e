// Checking and starting the particles an engine is given (particles/validate.hpp).
#include "mpm/particles/validate.hpp"

#include <algorithm>
#include <limits>
#include <sstream>

#include "mpm/core/errors.hpp"

namespace mpm {

std::string format_number(Real x) {
  std::ostringstream os;
  os.precision(9);
  os << x;
  return os.str();
}

template <int Dim>
std::string format_point(const Vec<Dim>& x) {
  std::ostringstream os;
  os.precision(9);
  os << '(';
  for (int d = 0; d < Dim; ++d) os << (d ? ", " : "") << x[d];
  os << ')';
  return os.str();
}

template <int Dim>
Real start_particles(ParticleSet<Dim>& p, const std::vector<Material>& materials, KernelKind kernel,
                     const GridGeometry<Dim>& g, bool axisymmetric, int fields) {
  if (p.field.size() != p.size())
    throw InputError("particles: one velocity field index per particle expected");
  Real min_mass = std::numeric_limits<Real>::max();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto at = [i] { return "particle " + std::to_string(i); };
    if (!g.contains(p.x[i]))
      throw InputError(at() + " at " + format_point<Dim>(p.x[i]) + " lies outside the grid " +
                       format_point<Dim>(g.lo) + " - " + format_point<Dim>(g.hi()));
    if (!(p.m[i] > 0) || !(p.V0[i] > 0)) throw InputError(at() + ": mass and volume must be positive");
    if (p.material[i] >= materials.size())
      throw InputError(at() + ": material index " + std::to_string(p.material[i]) + " has no material");
    if (p.field[i] >= fields)
      throw InputError(at() + ": velocity field " + std::to_string(p.field[i]) + " of " +
                       std::to_string(fields));
    if (!p.v[i].allFinite()) throw InputError(at() + ": velocity must be finite");
    if (is_rate_form(materials[p.material[i]]) && !(p.F[i] - Mat<Dim>::Identity()).isZero(0))
      throw InputError(at() + ": the rate-form materials start undeformed (F = I)");
    if (axisymmetric) {
      if (!(p.X[i][0] > 0)) throw InputError(at() + ": axisymmetric particles need radius x > 0");
      p.m[i] *= p.X[i][0];  // per radian: m_p = rho r_p A_p
      p.V0[i] *= p.X[i][0];
    }
    // A run bounds the half-lengths F convects (deformed_half_length); it starts within the bound.
    validate_half_lengths<Dim>(
        kernel, p.half_lengths == HalfLengths::deformed ? p.convected_half_length(i) : p.half_length(i), g.h,
        at());
    const Real J = p.F[i].determinant();
    if (!(J > 0)) throw InputError(at() + ": deformation gradient must have det F > 0");
    p.V[i] = p.V0[i] * J;
    min_mass = std::min(min_mass, p.m[i]);
  }
  return min_mass;
}

template std::string format_point<1>(const Vec<1>&);
template std::string format_point<2>(const Vec<2>&);
template std::string format_point<3>(const Vec<3>&);
template Real start_particles<1>(ParticleSet<1>&, const std::vector<Material>&, KernelKind,
                                 const GridGeometry<1>&, bool, int);
template Real start_particles<2>(ParticleSet<2>&, const std::vector<Material>&, KernelKind,
                                 const GridGeometry<2>&, bool, int);
template Real start_particles<3>(ParticleSet<3>&, const std::vector<Material>&, KernelKind,
                                 const GridGeometry<3>&, bool, int);

}  // namespace mpm
