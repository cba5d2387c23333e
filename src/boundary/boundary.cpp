#include "mpm/boundary/boundary.hpp"

#include <cmath>

#include "mpm/contact/coulomb.hpp"
#include "mpm/core/errors.hpp"

namespace mpm {

namespace {
constexpr const char* face_name[] = {"x-min", "x-max", "y-min", "y-max", "z-min", "z-max"};

/// Visit every node (ghosts included) with its global grid coordinates (a box's nodes with its offset added).
template <int Dim, class Fn>
void for_all_nodes(const GridGeometry<Dim>& g, Fn&& fn) {
  const auto n = static_cast<std::ptrdiff_t>(g.node_count());
  for (std::ptrdiff_t f = 0; f < n; ++f) fn(static_cast<std::int32_t>(f), g.global(g.coords(f)));
}

template <int Dim>
Vec<Dim> reflect(Vec<Dim> v, int axis) {
  v[axis] = -v[axis];
  return v;
}
}  // namespace

template <int Dim>
void validate_faces(const BoundarySpec<Dim>& spec, const IVec<Dim>& cells, Geometry geometry, Real lo0,
                    const std::string& at) {
  for (int f = 0; f < 2 * Dim; ++f) {
    const FaceCondition<Dim>& fc = spec.faces[f];
    if (std::isnan(fc.friction) ||
        (fc.friction >= 0 && (!std::isfinite(fc.friction) || fc.type != FaceType::velocity)))
      throw InputError(at + "boundary " + face_name[f] + ": friction " + std::to_string(fc.friction) +
                       " (a Coulomb wall is a velocity face with a finite friction coefficient >= 0)");
  }
  for (int f = 0; f < 2 * Dim; ++f) {
    const FaceCondition<Dim>& fc = spec.faces[f];
    if (fc.type != FaceType::absorbing) continue;
    if (!(std::isfinite(fc.normal_impedance) && fc.normal_impedance > 0 &&
          std::isfinite(fc.shear_impedance) && fc.shear_impedance >= 0))
      throw InputError(at + "boundary " + face_name[f] +
                       ": an absorbing face needs impedances rho c_p > 0 and rho c_s >= 0");
    if (geometry == Geometry::axisymmetric)
      throw InputError(at + "boundary " + face_name[f] +
                       ": absorbing faces are for plane and 3-D grids, not axisymmetric ones");
  }
  for (int d = 0; d < Dim; ++d) {
    const bool lo = spec.faces[2 * d].type == FaceType::periodic,
               hi = spec.faces[2 * d + 1].type == FaceType::periodic;
    if (lo != hi)
      throw InputError(at + "boundary " + face_name[lo ? 2 * d + 1 : 2 * d] +
                       ": expected \"periodic\", as its opposite face " + face_name[lo ? 2 * d : 2 * d + 1] +
                       " is (periodic faces come in pairs)");
    if (lo && cells[d] < 2)
      throw InputError(at + "boundary " + face_name[2 * d] + ": a periodic axis needs at least 2 cells");
  }
  if (geometry != Geometry::axisymmetric) return;
  if (spec.faces[0].type == FaceType::periodic)
    throw InputError(at + "boundary x-min: the radial axis of an axisymmetric grid cannot be periodic");
  if (spec.faces[0].type == FaceType::outflow && lo0 == 0)
    throw InputError(at + "boundary x-min: the axis r = 0 of an axisymmetric grid cannot be an outflow face");
}

template <int Dim>
KinematicConstraints<Dim>::KinematicConstraints(const BoundarySpec<Dim>& spec, const GridGeometry<Dim>& g,
                                                const IVec<Dim>& owned)
    : acceleration_(spec.acceleration) {
  for (int face = 0; face < 2 * Dim; ++face) {
    const FaceCondition<Dim>& fc = spec.faces[face];
    const int axis = face / 2;
    const bool high = face % 2 == 1;
    const int plane = high ? g.cells[axis] : 0;
    const int outward = high ? 1 : -1;
    if (fc.type == FaceType::velocity) {
      Group grp{face_name[face], {}, -1, fc.velocity, {}};
      grp.friction = fc.friction;
      grp.normal[axis] = outward;
      for_all_nodes(g, [&](std::int32_t f, const IVec<Dim>& i) {
        if ((i[axis] - plane) * outward >= 0) grp.nodes.push_back(f);
      });
      groups_.push_back(std::move(grp));
    } else if (fc.type == FaceType::absorbing) {
      // The nodes on the face plane, each carrying h^(Dim-1) of the face, half of it per face edge it lies
      // on.
      Group grp{face_name[face], {}, -1, {}, {}};
      grp.normal[axis] = outward;
      grp.normal_impedance = fc.normal_impedance;
      grp.shear_impedance = fc.shear_impedance;
      for_all_nodes(g, [&](std::int32_t f, const IVec<Dim>& i) {
        if (i[axis] != plane) return;
        Real area = 1;
        for (int d = 0; d < Dim; ++d)
          if (d != axis) area *= (i[d] == 0 || i[d] == g.cells[d]) ? 0.5 * g.h : g.h;
        grp.nodes.push_back(f);
        grp.area.push_back(area);
      });
      groups_.push_back(std::move(grp));
    } else if (fc.type == FaceType::symmetry) {
      Group grp{face_name[face], {}, axis, {}, {}};
      Mirror mir{axis, {}, {}};
      for_all_nodes(g, [&](std::int32_t f, const IVec<Dim>& i) {
        const int k = (i[axis] - plane) * outward;  // layers beyond the plane
        if (k == 0) grp.nodes.push_back(f);
        if (k > 0) {
          // The mirror node, in this box's coordinates. A box of a divided grid holds both or neither of the
          // pairs any of its particles reach (cut_limit in mpm/distributed/box_halo.hpp); the rest are
          // skipped.
          IVec<Dim> j = i;
          j[axis] = plane - k * outward;
          for (int d = 0; d < Dim; ++d) j[d] -= g.offset[d];
          if (j[axis] + g.ghost < 0 || j[axis] + g.ghost >= g.nodes_along(axis)) return;
          mir.ghost.push_back(f);
          mir.real.push_back(static_cast<std::int32_t>(g.flat(j)));
        }
      });
      groups_.push_back(std::move(grp));
      mirrors_.push_back(std::move(mir));
    }
  }
  const Real tol = 1e-9 * g.h;
  for (const RegionConstraint<Dim>& rc : spec.regions) {
    Group grp{"region " + std::to_string(&rc - spec.regions.data()), {}, -1, rc.velocity, {}};
    for_all_nodes(g, [&](std::int32_t f, const IVec<Dim>& i) {
      const Vec<Dim> x = g.position(i);
      for (int d = 0; d < Dim; ++d)
        if (x[d] < rc.lo[d] - tol || x[d] > rc.hi[d] + tol) return;
      grp.nodes.push_back(f);
    });
    groups_.push_back(std::move(grp));
  }
  // A group's reaction counts the nodes this box owns, copies of other nodes excepted (repeats_another).
  const std::array<FaceType, 2 * Dim> types = face_types(spec);
  for (Group& grp : groups_)
    for (std::int32_t f : grp.nodes) {
      const IVec<Dim> i = g.coords(f);
      bool mine = !repeats_another<Dim>(types, g.cells, g.global(i));
      for (int d = 0; d < Dim; ++d) mine = mine && i[d] + g.ghost < owned[d];
      grp.owned.push_back(mine);
    }
  reactions_.assign(groups_.size(), Vec<Dim>::Zero());
  reaction_sums_.resize(groups_.size());
  moments_.resize(groups_.size());
}

template <int Dim>
KinematicConstraints<Dim>::KinematicConstraints(const BoundarySpec<Dim>& spec, const GridGeometry<Dim>& g)
    : KinematicConstraints(spec, g, [&] {
        IVec<Dim> all;
        for (int d = 0; d < Dim; ++d) all[d] = g.nodes_along(d);
        return all;
      }()) {}

template <int Dim>
void KinematicConstraints<Dim>::fold_and_mirror(Grid<Dim>& grid, NodeFields fields) const {
  if (fields == NodeFields::force) return fold_and_mirror(grid, &GridNode<Dim>::a);
  for (const Mirror& mir : mirrors_)
    for (std::size_t k = 0; k < mir.ghost.size(); ++k)
      grid.nodes[mir.real[k]].m += grid.nodes[mir.ghost[k]].m;
  for (auto it = mirrors_.rbegin(); it != mirrors_.rend(); ++it)
    for (std::size_t k = 0; k < it->ghost.size(); ++k) grid.nodes[it->ghost[k]].m = grid.nodes[it->real[k]].m;
  fold_and_mirror(grid, &GridNode<Dim>::v);
}

template <int Dim>
void KinematicConstraints<Dim>::fold_and_mirror(Grid<Dim>& grid, NodeVelocity<Dim> field) const {
  for (const Mirror& mir : mirrors_)
    for (std::size_t k = 0; k < mir.ghost.size(); ++k)
      grid.nodes[mir.real[k]].*field += reflect<Dim>(grid.nodes[mir.ghost[k]].*field, mir.axis);
  mirror(grid, field);
}

template <int Dim>
void KinematicConstraints<Dim>::mirror(Grid<Dim>& grid, NodeVelocity<Dim> field) const {
  // In reverse order, so a corner ghost takes its value from a node another plane has already mirrored.
  for (auto it = mirrors_.rbegin(); it != mirrors_.rend(); ++it)
    for (std::size_t k = 0; k < it->ghost.size(); ++k)
      grid.nodes[it->ghost[k]].*field = reflect<Dim>(grid.nodes[it->real[k]].*field, it->axis);
}

template <int Dim>
void KinematicConstraints<Dim>::mark_mirrored(std::vector<std::uint8_t>& mask) const {
  for (const Mirror& mir : mirrors_)
    for (std::int32_t g : mir.ghost) mask[g] = 1;
}

template <int Dim>
void KinematicConstraints<Dim>::count_mirror_copies(std::vector<std::uint8_t>& copies) const {
  for (const Group& grp : groups_)
    if (grp.component >= 0 && !grp.velocity)  // a symmetry plane: one component, no prescribed velocity
      for (std::int32_t n : grp.nodes) copies[n] = static_cast<std::uint8_t>(2 * copies[n]);
}

template <int Dim>
std::vector<typename KinematicConstraints<Dim>::Component> KinematicConstraints<Dim>::components() const {
  std::vector<Component> out;
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    const Group& grp = groups_[g];
    if (grp.absorbing()) continue;  // it holds no component
    for (std::int32_t n : grp.nodes)
      for (int c = 0; c < Dim; ++c)
        if (grp.component < 0 || grp.component == c) out.push_back({n, c, static_cast<int>(g)});
  }
  return out;
}

template <int Dim>
std::vector<typename KinematicConstraints<Dim>::Dashpot> KinematicConstraints<Dim>::dashpots() const {
  std::vector<Dashpot> out;
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    const Group& grp = groups_[g];
    if (!grp.absorbing()) continue;
    for (std::size_t k = 0; k < grp.nodes.size(); ++k)
      for (int c = 0; c < Dim; ++c) {
        const Real Z = grp.normal[c] != 0 ? grp.normal_impedance : grp.shear_impedance;
        out.push_back({grp.nodes[k], c, static_cast<int>(g), Z * grp.area[k], grp.owned[k] != 0});
      }
  }
  return out;
}

template <int Dim>
Vec<Dim> KinematicConstraints<Dim>::value(const Group& grp, Real t) const {
  return grp.velocity ? grp.velocity(t) : Vec<Dim>::Zero();
}

template <int Dim>
void KinematicConstraints<Dim>::constrain_velocity(Grid<Dim>& grid, NodeVelocity<Dim> field, Real t) const {
  for (const Group& grp : groups_) {
    if (grp.absorbing()) continue;  // it holds no velocity
    const Vec<Dim> val = value(grp, t);
    for (std::int32_t n : grp.nodes) {
      Vec<Dim>& v = grid.nodes[n].*field;
      if (grp.friction >= 0)
        v += coulomb_contact<Dim>(v - val, grp.normal, grp.friction);
      else if (grp.component < 0)
        v = val;
      else
        v[grp.component] = val[grp.component];
    }
  }
}

template <int Dim>
void KinematicConstraints<Dim>::constrain_update(Grid<Dim>& grid, Real t_new, Real dt, bool add_to_last) {
  const bool difference = acceleration_ == ConstrainedAcceleration::velocity_difference;
  if (!add_to_last) friction_power_ = {};
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    const Group& grp = groups_[g];
    const Vec<Dim> val = value(grp, t_new);
    const int first = grp.component < 0 ? 0 : grp.component;
    const int last = grp.component < 0 ? Dim : grp.component + 1;
    std::array<ExactSum, Dim>& reaction = reaction_sums_[g];
    if (!add_to_last) {
      reaction = {};
      moments_[g] = {};
    }
    for (std::size_t k = 0; k < grp.nodes.size(); ++k) {
      GridNode<Dim>& node = grid.nodes[grp.nodes[k]];
      if (grp.absorbing()) {
        // The dashpots of Lysmer & Kuhlemeyer 1969, implicit in the advanced velocity so that they are stable
        // at any step: m (v_c - v) = dt (f - Z A v_c), i.e. v_c = m v_new / (m + dt Z A) with Z = rho c_p
        // along the normal and rho c_s across it; the particles receive a + (v_c - v_new) / dt.
        if (!(node.m > 0)) continue;
        const Real vn = node.v_new.dot(grp.normal);
        const Vec<Dim> v_normal = vn * grp.normal, v_shear = node.v_new - v_normal;
        const Vec<Dim> v_c = node.m / (node.m + dt * grp.normal_impedance * grp.area[k]) * v_normal +
                             node.m / (node.m + dt * grp.shear_impedance * grp.area[k]) * v_shear;
        const Vec<Dim> da = (v_c - node.v_new) / dt;
        if (grp.owned[k])
          for (int c = 0; c < Dim; ++c) reaction[c].add(node.m * da[c]);
        node.a += da;
        node.v_new = v_c;
        continue;
      }
      if (grp.friction >= 0) {  // a Coulomb wall
        const Vec<Dim> free = node.a;
        coulomb_partner<Dim>(node, val, grp.normal, grp.friction, dt, grp.owned[k], reaction,
                             friction_power_);
        if (!grp.owned[k]) continue;
        // The moments of the normal force along the face plane's axes.
        const Real f_n = -node.m * (node.a - free).dot(grp.normal);
        const Vec<Dim> x = grid.geometry.position(grid.geometry.coords(grp.nodes[k]));
        moments_[g][0].add(f_n);
        for (int d = 0; d < Dim; ++d)
          if (grp.normal[d] == 0) {
            moments_[g][1 + d].add(f_n * x[d]);
            moments_[g][1 + Dim + d].add(f_n * x[d] * x[d]);
          }
        continue;
      }
      for (int c = first; c < last; ++c) {
        node.v_new[c] = val[c];
        // Steffen et al. 2008, Eq. (30): the acceleration that brings the projected velocity to the
        // prescribed one.
        const Real a = difference ? (val[c] - node.v[c]) / dt : 0;
        // The force that turns the free acceleration into a, summed exactly over the nodes this box owns.
        if (grp.owned[k]) reaction[c].add(node.m * (a - node.a[c]));
        node.a[c] = a;
      }
    }
    for (int c = 0; c < Dim; ++c) reactions_[g][c] = reaction[c].value();
  }
}

template <int Dim>
std::vector<std::string> KinematicConstraints<Dim>::names() const {
  std::vector<std::string> out;
  for (const Group& grp : groups_) out.push_back(grp.name);
  return out;
}

template <int Dim>
std::vector<Vec<Dim>> KinematicConstraints<Dim>::velocities(Real t) const {
  std::vector<Vec<Dim>> out;
  for (const Group& grp : groups_)
    out.push_back(grp.component < 0 && !grp.absorbing() ? value(grp, t) : Vec<Dim>::Zero());
  return out;
}

template void validate_faces<1>(const BoundarySpec<1>&, const IVec<1>&, Geometry, Real, const std::string&);
template void validate_faces<2>(const BoundarySpec<2>&, const IVec<2>&, Geometry, Real, const std::string&);
template void validate_faces<3>(const BoundarySpec<3>&, const IVec<3>&, Geometry, Real, const std::string&);
template class KinematicConstraints<1>;
template class KinematicConstraints<2>;
template class KinematicConstraints<3>;

}  // namespace mpm
