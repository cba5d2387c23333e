#pragma once
/// Rigid bodies: material points moving at a prescribed velocity that impose it on every node they touch
/// (no-slip contact through the single velocity field, Sulsky & Kaul 2004 Secs 3.1.1 and 3.2.7), in both engines.
#include <algorithm>
#include <array>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "mpm/boundary/boundary.hpp"
#include "mpm/core/errors.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/shape/stencil.hpp"

namespace mpm {

template <int Dim>
constexpr std::array<bool, Dim> filled(bool value) {
  std::array<bool, Dim> a{};
  a.fill(value);
  return a;
}

template <int Dim>
struct RigidBody {
  std::string name;
  std::vector<Vec<Dim>> points;             ///< material point positions at t = 0 [m]
  Vec<Dim> half_length = Vec<Dim>::Zero();  ///< GIMP half-lengths of its points [m]
  VelocityFn<Dim> velocity;                 ///< v(t) [m/s]
  /// Components the body imposes: all (no-slip contact, the default), or some (free slip along the others).
  std::array<bool, Dim> imposes = filled<Dim>(true);
};

/// The rigid bodies of a run, where they are, and the nodes they touch.
template <int Dim>
class RigidBodies {
 public:
  /// Throws InputError when a point lies outside the grid.
  RigidBodies(std::vector<RigidBody<Dim>> bodies, const GridGeometry<Dim>& g)
      : bodies_(std::move(bodies)),
        nodes_(bodies_.size()),
        displacement_(bodies_.size(), Vec<Dim>::Zero()),
        reactions_(bodies_.size(), Vec<Dim>::Zero()) {
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
  /// step and time), when a body left the grid.
  template <class Kernel>
  void locate(const GridGeometry<Dim>& g, const std::string& when) {
    const NodeLayout<Dim> layout(g);
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const RigidBody<Dim>& body = bodies_[b];
      std::vector<std::int32_t>& touched = nodes_[b];
      touched.clear();
      for (const Vec<Dim>& x0 : body.points) {
        const Vec<Dim> x = x0 + displacement_[b];
        if (!g.contains(x)) throw SimulationFailure(when + ": rigid body '" + body.name + "' left the grid");
        for_each_node(make_stencil<Dim, Kernel>(g, layout, x, body.half_length), layout,
                      [&](std::int32_t n, Real S, const Vec<Dim>&) {
                        if (S > 0) touched.push_back(n);
                      });
      }
      std::sort(touched.begin(), touched.end());
      touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    }
  }

  /// Impose the bodies' velocities at time t on a node velocity field.
  void constrain_velocity(Grid<Dim>& grid, NodeVelocity<Dim> field, Real t) const {
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const Vec<Dim> v = bodies_[b].velocity(t);
      for (std::int32_t n : nodes_[b])
        for (int c = 0; c < Dim; ++c)
          if (bodies_[b].imposes[c]) (grid.nodes[n].*field)[c] = v[c];
    }
  }

  /// Impose the bodies' velocities at t_new on v_new, with the acceleration that brings the projected velocity
  /// to them, a_i = (v_body - v_i) / dt (the particles take the body's velocity change, as in Sulsky & Kaul 2004,
  /// Eq. (3.2.6)); record each body's reaction sum_i m_i (a_i - a_i^free).
  void constrain_update(Grid<Dim>& grid, Real t_new, Real dt) {
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const Vec<Dim> v = bodies_[b].velocity(t_new);
      Vec<Dim> reaction = Vec<Dim>::Zero();
      for (std::int32_t n : nodes_[b]) {
        GridNode<Dim>& node = grid.nodes[n];
        for (int c = 0; c < Dim; ++c) {
          if (!bodies_[b].imposes[c]) continue;
          const Real a = (v[c] - node.v[c]) / dt;
          reaction[c] += node.m * (a - node.a[c]);
          node.a[c] = a;
          node.v_new[c] = v[c];
        }
      }
      reactions_[b] = reaction;
    }
  }

  /// Move the bodies over a step from t: displacement += dt v(t + dt/2).
  void advance(Real t, Real dt) {
    for (std::size_t b = 0; b < bodies_.size(); ++b) displacement_[b] += dt * bodies_[b].velocity(t + 0.5 * dt);
  }

 private:
  std::vector<RigidBody<Dim>> bodies_;
  std::vector<std::vector<std::int32_t>> nodes_;
  std::vector<Vec<Dim>> displacement_, reactions_;
};

}  // namespace mpm
