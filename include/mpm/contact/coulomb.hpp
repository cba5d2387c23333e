#pragma once
/// The Coulomb contact law of multi-velocity-field MPM (Bardenhagen, Brackbill & Sulsky 2000; Bardenhagen et al.
/// 2001), applied at a node to a body's velocity relative to its partner's: when they approach, the normal part of
/// the relative velocity is removed, and the tangential part is reduced by at most mu times that normal change
/// (sliding), or removed (sticking). A grid face or a rigid body is a partner of infinite mass, whose velocity the
/// correction leaves as it is.
#include <algorithm>
#include <cmath>

#include "mpm/core/types.hpp"

namespace mpm {

/// The change of a body's nodal velocity that contact with a partner makes, from the relative velocity
/// v_rel = v_body - v_partner and the unit normal n pointing from the body into the partner; zero when they do not
/// approach (v_rel . n <= 0). mu >= 0 is the friction coefficient.
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

}  // namespace mpm
