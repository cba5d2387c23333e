#pragma once
/// The rigid bodies of a run (RigidBody, boundary/rigid_body.hpp) at run time: where they are, the nodes they
/// touch, the velocities they impose there and their reactions, in both engines. Their locate, which needs a
/// kernel's stencil, is in boundary/rigid_bodies_locate.hpp, included where an engine is compiled.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/boundary/rigid_body.hpp"
#include "mpm/contact/coulomb.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/core/exact_sum.hpp"
#include "mpm/grid/grid.hpp"

namespace mpm {

/// The rigid bodies of a run, where they are, and the nodes they touch.
template <int Dim>
class RigidBodies {
 public:
  /// Throws InputError when a point lies outside the grid. `faces` (face_types): the reactions count no node
  /// that repeats another beyond a symmetry plane or a periodic face (repeats_another).
  RigidBodies(std::vector<RigidBody<Dim>> bodies, const GridGeometry<Dim>& g,
              const std::array<FaceType, 2 * Dim>& faces)
      : bodies_(std::move(bodies)),
        faces_(faces),
        nodes_(bodies_.size()),
        normals_(bodies_.size()),
        displacement_(bodies_.size(), Vec<Dim>::Zero()),
        reactions_(bodies_.size(), Vec<Dim>::Zero()),
        reaction_sums_(bodies_.size()) {
    for (const RigidBody<Dim>& body : bodies_)
      for (const Vec<Dim>& x : body.points)
        if (!g.contains(x)) throw InputError("rigid body '" + body.name + "': a point lies outside the grid");
  }

  const std::vector<RigidBody<Dim>>& bodies() const { return bodies_; }
  std::size_t size() const { return bodies_.size(); }
  bool empty() const { return bodies_.empty(); }
  /// Nodes body b touches (weight > 0 from one of its points), ascending, as of the last locate().
  const std::vector<std::int32_t>& nodes(std::size_t b) const { return nodes_[b]; }
  /// Displacement of each body since t = 0 [m].
  const std::vector<Vec<Dim>>& displacements() const { return displacement_; }
  void restore(const std::vector<Vec<Dim>>& displacement) { displacement_ = displacement; }
  /// Force [N per unit thickness or radian] each body applied to the material in the last constrain_update.
  const std::vector<Vec<Dim>>& reactions() const { return reactions_; }
  std::vector<Vec<Dim>>& reactions() { return reactions_; }
  std::vector<Vec<Dim>> velocities(Real t) const {
    std::vector<Vec<Dim>> v;
    for (const RigidBody<Dim>& b : bodies_) v.push_back(b.velocity(t));
    return v;
  }

  /// Find the nodes each body touches at its current position. Throws SimulationFailure, naming `when` (the
  /// step and time), when a body left the grid. On a box of a divided grid only the nodes the box holds
  /// count, and the reactions count those of the first owned[d] storage layers along each axis (the box's own
  /// tiles).
  template <class Kernel>
  void locate(const GridGeometry<Dim>& g, const std::string& when) {
    IVec<Dim> all;
    for (int d = 0; d < Dim; ++d) all[d] = g.nodes_along(d);
    locate<Kernel>(g, when, all);
  }
  template <class Kernel>
  void locate(const GridGeometry<Dim>& g, const std::string& when,
              const IVec<Dim>& owned);  // rigid_bodies_locate.hpp

  /// The nodes in the box [lo, hi] (to 1e-9 h), each with whether its reaction counts: the box of a divided
  /// grid owns it, and it repeats no other node (repeats_another).
  std::vector<std::pair<std::int32_t, bool>> nodes_inside(const GridGeometry<Dim>& g, const Vec<Dim>& lo,
                                                          const Vec<Dim>& hi, const IVec<Dim>& owned) const {
    IVec<Dim> first, last;  // storage layers
    for (int d = 0; d < Dim; ++d) {
      const Real tol = 1e-9;
      first[d] =
          std::max(0, static_cast<int>(std::ceil((lo[d] - g.lo[d]) / g.h - tol)) + g.ghost - g.offset[d]);
      last[d] = std::min(g.nodes_along(d) - 1,
                         static_cast<int>(std::floor((hi[d] - g.lo[d]) / g.h + tol)) + g.ghost - g.offset[d]);
    }
    std::vector<std::pair<std::int32_t, bool>> out;
    for (int d = 0; d < Dim; ++d)
      if (first[d] > last[d]) return out;
    IVec<Dim> k = first;
    while (true) {
      std::int32_t flat = 0;
      bool mine = true;
      for (int d = Dim - 1; d >= 0; --d) {
        flat = flat * g.nodes_along(d) + k[d];
        mine = mine && k[d] < owned[d];
      }
      out.emplace_back(flat, mine && !repeats_another<Dim>(faces_, g.cells, global_node(g, k)));
      int d = 0;
      while (d < Dim && k[d] >= last[d]) k[d] = first[d], ++d;
      if (d == Dim) break;
      ++k[d];
    }
    return out;
  }

  /// The global grid coordinates of the node in storage layers k.
  static IVec<Dim> global_node(const GridGeometry<Dim>& g, const IVec<Dim>& k) {
    IVec<Dim> i;
    for (int d = 0; d < Dim; ++d) i[d] = k[d] - g.ghost;
    return g.global(i);
  }

  /// Impose the bodies' velocities at time t on a node velocity field.
  void constrain_velocity(Grid<Dim>& grid, NodeVelocity<Dim> field, Real t) const {
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const Vec<Dim> v = bodies_[b].velocity(t);
      const Real mu = bodies_[b].friction;
      for (std::size_t k = 0; k < nodes_[b].size(); ++k) {
        Vec<Dim>& u = grid.nodes[nodes_[b][k]].*field;
        if (mu >= 0)
          u += coulomb_contact<Dim>(u - v, normals_[b][k], mu);
        else
          for (int c = 0; c < Dim; ++c)
            if (bodies_[b].imposes[c]) u[c] = v[c];
      }
    }
  }

  /// Impose the bodies' velocities at t_new on v_new, with the acceleration that brings the projected
  /// velocity to them, a_i = (v_body - v_i) / dt (the particles take the body's velocity change, as in Sulsky
  /// & Kaul 2004, Eq. (3.2.6)); record each body's reaction sum_i m_i (a_i - a_i^free). The reaction is
  /// summed exactly over the nodes the box owns (reaction_sums, to add over the boxes). With several velocity
  /// fields (contact), each field's call after the first adds to the last (`add_to_last`).
  void constrain_update(Grid<Dim>& grid, Real t_new, Real dt, bool add_to_last = false) {
    if (!add_to_last) friction_power_ = {};
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const Vec<Dim> v = bodies_[b].velocity(t_new);
      std::array<ExactSum, Dim>& reaction = reaction_sums_[b];
      if (!add_to_last) reaction = {};
      for (std::size_t k = 0; k < nodes_[b].size(); ++k) {
        GridNode<Dim>& node = grid.nodes[nodes_[b][k]];
        if (bodies_[b].friction >= 0) {  // a Coulomb body
          coulomb_partner<Dim>(node, v, normals_[b][k], bodies_[b].friction, dt, owned_[b][k], reaction,
                               friction_power_);
          continue;
        }
        for (int c = 0; c < Dim; ++c) {
          if (!bodies_[b].imposes[c]) continue;
          const Real a = (v[c] - node.v[c]) / dt;
          if (owned_[b][k]) reaction[c].add(node.m * (a - node.a[c]));
          node.a[c] = a;
          node.v_new[c] = v[c];
        }
      }
      for (int c = 0; c < Dim; ++c) reactions_[b][c] = reaction[c].value();
    }
  }
  /// The last constrain_update's reactions as exact sums over the owned nodes.
  const std::vector<std::array<ExactSum, Dim>>& reaction_sums() const { return reaction_sums_; }
  /// The power friction dissipated on the Coulomb bodies in the last constrain_update [W], as an exact sum
  /// over the owned nodes (KinematicConstraints::friction_power).
  const ExactSum& friction_power() const { return friction_power_; }

  /// Move the bodies over a step from t: displacement += dt v(t + dt/2).
  void advance(Real t, Real dt) {
    for (std::size_t b = 0; b < bodies_.size(); ++b)
      displacement_[b] += dt * bodies_[b].velocity(t + 0.5 * dt);
  }

 private:
  std::vector<RigidBody<Dim>> bodies_;
  std::array<FaceType, 2 * Dim> faces_;
  std::vector<std::vector<std::int32_t>> nodes_;
  std::vector<std::vector<Vec<Dim>>>
      normals_;  ///< a Coulomb body's: per touched node, from the material into it
  std::vector<std::vector<std::uint8_t>>
      owned_;  ///< per touched node: its reaction counts (nodes_inside's bool)
  std::vector<Vec<Dim>> displacement_, reactions_;
  std::vector<std::array<ExactSum, Dim>> reaction_sums_;
  ExactSum friction_power_;
};

}  // namespace mpm
