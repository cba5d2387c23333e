#pragma once
/// The Coulomb contact law of multi-velocity-field MPM (Bardenhagen, Brackbill & Sulsky 2000; Bardenhagen et
/// al. 2001), applied at a node to a body's velocity relative to its partner's: when they approach, the
/// normal part of the relative velocity is removed, and the tangential part is reduced by at most mu times
/// that normal change (sliding), or removed (sticking). A grid face or a rigid body is a partner of infinite
/// mass, whose velocity the correction leaves as it is.
#include <algorithm>
#include <array>
#include <cmath>

#include "mpm/core/types.hpp"

namespace mpm {

/// The change of a body's nodal velocity that contact with a partner makes, from the relative velocity
/// v_rel = v_body - v_partner and the unit normal n pointing from the body into the partner; zero when they
/// do not approach (v_rel . n <= 0). mu >= 0 is the friction coefficient.
template <int Dim>
Vec<Dim> coulomb_contact(const Vec<Dim>& v_rel, const Vec<Dim>& n, Real mu) {
  const Real approach = v_rel.dot(n);
  if (!(approach > 0)) return Vec<Dim>::Zero();
  const Vec<Dim> tangential = v_rel - approach * n;
  const Real slip = tangential.norm();
  Vec<Dim> change = -approach * n;
  if (slip > 0) change -= (std::min(mu * approach, slip) / slip) * tangential;
  return change;
}

/// A partner of infinite mass moving at v_partner, met by the material at a grid node after the grid update:
/// the node's advanced velocity v_new gets the contact change, its acceleration a (what the particles
/// receive) the change over dt. When the node's force counts here (`owned`), the force the partner applied, m
/// dv / dt, is added to `force` and the power friction dissipated, minus that force times the velocity
/// relative to the partner after it, to `power`.
template <int Dim, class Node, class Sum>
void coulomb_partner(Node& node, const Vec<Dim>& v_partner, const Vec<Dim>& n, Real mu, Real dt, bool owned,
                     std::array<Sum, Dim>& force, Sum& power) {
  const Vec<Dim> change = coulomb_contact<Dim>(node.v_new - v_partner, n, mu);
  node.v_new += change;
  node.a += change / dt;
  if (!owned) return;
  const Vec<Dim> f = node.m * change / dt;
  for (int c = 0; c < Dim; ++c) force[c].add(f[c]);
  power.add(-f.dot(node.v_new - v_partner));
}

}  // namespace mpm
