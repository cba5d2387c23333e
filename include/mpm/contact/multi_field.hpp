#pragma once
/// Multi-velocity-field contact (Bardenhagen, Brackbill & Sulsky 2000; Bardenhagen et al. 2001): bodies, or
/// groups of bodies, project to velocity fields of their own; where two fields share a node, their velocities
/// there are corrected by the Coulomb law of contact/coulomb.hpp when they approach, and by the
/// center-of-mass velocity (they stick, as one field) when the pair has no contact law. Every correction
/// exchanges momentum between the two fields only, so the total is conserved to round-off.
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "mpm/contact/coulomb.hpp"
#include "mpm/core/exact_sum.hpp"
#include "mpm/core/types.hpp"
#include "mpm/grid/grid.hpp"

namespace mpm {

/// Which normal a pair of fields uses at a node, from their volume gradients g_a, g_b (each points out of its
/// body): `average` the direction of g_a - g_b (the default, symmetric in the two bodies), `larger` that of
/// the body whose gradient is longer (g_a, or -g_b), `first` the first body's own g_a (the original choice of
/// Bardenhagen, Brackbill & Sulsky 2000). Nairn 2013 compares them. Measured (docs/contact.md): colliding
/// disks keep their energy best with the average; a block sliding on a flat plate needs `larger`, which keeps
/// the plate's normal under the block's corners, where the average tilts and the block ploughs.
enum class ContactNormal { average, larger, first };

/// One pair of fields that meet by the Coulomb law with friction coefficient `friction` (>= 0; infinity: no
/// slip while in contact), and the normal they use. Contact needs the fields to approach at a node and, with
/// a finite `gap` [cells], their mass centres there to lie less than gap cell widths apart along the normal
/// (Nairn 2013: 0.8 at 2 particles per cell per axis); the default, infinity, takes every approach as
/// contact. Fields that meet and are in no pair stick together.
struct ContactPair {
  int a = 0, b = 1;
  Real friction = 0;
  ContactNormal normal = ContactNormal::average;
  Real gap = std::numeric_limits<Real>::infinity();
};

/// The velocity fields of an explicit run: `fields` == 1 (the default) is single-field MPM, no contact.
struct ContactSpec {
  int fields = 1;
  std::vector<ContactPair> pairs;
};

/// Throw InputError naming the first invalid entry (fields < 1 or > 255, a pair naming a field out of range,
/// twice, or a field with itself, a negative or NaN friction, a gap not > 0).
void validate(const ContactSpec& contact);
/// Whether some pair detects contact by the gap of its mass centres (a finite ContactPair::gap).
bool measures_gaps(const ContactSpec& contact);

/// The unit normal from field a into field b at a node, from their volume gradients (ContactNormal); zero
/// where it is undefined (both gradients zero), and then no Coulomb correction applies.
template <int Dim>
Vec<Dim> contact_normal(const Vec<Dim>& g_a, const Vec<Dim>& g_b, ContactNormal choice) {
  Vec<Dim> n = g_a;
  if (choice == ContactNormal::average) n = g_a - g_b;
  if (choice == ContactNormal::larger && g_b.squaredNorm() > g_a.squaredNorm()) n = -g_b;
  const Real length = n.norm();
  if (!(length > 0) || !std::isfinite(length)) return Vec<Dim>::Zero();
  return n / length;
}

/// The momentum field a gains at a node from field b (b loses it): with a friction coefficient mu >= 0, the
/// reduced mass m_a m_b / (m_a + m_b) times the Coulomb change of a's velocity relative to b's
/// (coulomb_contact), which leaves no approach along n; with mu < 0 (no contact law) the change that brings
/// both to the center-of-mass velocity (Bardenhagen, Brackbill & Sulsky 2000).
template <int Dim>
Vec<Dim> pair_momentum_change(Real m_a, const Vec<Dim>& v_a, Real m_b, const Vec<Dim>& v_b, const Vec<Dim>& n,
                              Real mu) {
  const Real reduced = m_a * m_b / (m_a + m_b);
  if (mu < 0) return reduced * (v_b - v_a);
  return reduced * coulomb_contact<Dim>(v_a - v_b, n, mu);
}

/// What contact transmitted between the fields of one pair in a step: the force on the first field by the
/// second [N], its compressive normal and its tangential magnitudes summed over the nodes [N], and the power
/// friction dissipated [W].
template <int Dim>
struct PairForces {
  Vec<Dim> force = Vec<Dim>::Zero();
  Real normal = 0, tangential = 0, friction_power = 0;
};

/// The contact of an explicit step: the nodes where fields meet, found once a step from the fields' masses
/// and volume gradients, and the corrections at them.
template <int Dim>
class MultiFieldContact {
 public:
  MultiFieldContact() = default;
  explicit MultiFieldContact(const ContactSpec& spec);

  bool active() const { return spec_.fields > 1; }
  int fields() const { return spec_.fields; }
  const ContactSpec& spec() const { return spec_; }

  /// Find the nodes where two or more fields carry mass (more than min_mass), and the normal of each pair of
  /// fields there from the volume gradients the mass pass left in v_new (VolumeGradient). `fields[k]` is
  /// field k's grid; a node counts in the forces when `owned` (its box owns it, and it is no periodic image
  /// or mirror). When measures_gaps(spec()), `positions[k]` holds field k's sums m_p x_p S_ip in the v slot
  /// of each node.
  void locate(const std::vector<Grid<Dim>*>& fields, Real min_mass, const IVec<Dim>& owned,
              const std::vector<Grid<Dim>>* positions = nullptr);
  /// Correct the node velocities `v` (the projected v^n, or the re-projected one) at the contact nodes.
  void correct_velocity(const std::vector<Grid<Dim>*>& fields, NodeVelocity<Dim> v) const;
  /// Correct the advanced velocities v_new, and the accelerations a by the change over dt, at the contact
  /// nodes, and record what each pair transmitted (pair_forces over this rank's nodes). A gap measured at the
  /// step's start is closed by the relative velocity over dt first (Nairn 2013).
  void correct_update(const std::vector<Grid<Dim>*>& fields, Real dt);
  /// What each pair of spec().pairs transmitted in the last correct_update, summed exactly over this rank's
  /// owned nodes: force (Dim), normal, tangential, friction power.
  const std::vector<std::array<ExactSum, Dim + 3>>& pair_sums() const { return sums_; }
  /// The nodes where fields met in the last locate().
  std::size_t contact_nodes() const { return node_begin_.empty() ? 0 : node_begin_.size() - 1; }

 private:
  /// One pair of fields meeting at one node.
  struct Meeting {
    std::int32_t node;
    std::uint16_t a, b;
    std::int32_t pair;  ///< index into spec_.pairs, or -1: they stick
    bool owned;
    Vec<Dim> normal;
    /// The gap of the mass centres along the normal less the pair's gap [m]: in contact when <= 0 (-infinity
    /// without a gap)
    Real separation;
  };
  /// The friction of fields a < b: their pair's, or -1 (stick).
  Real friction(std::int32_t pair) const { return pair < 0 ? Real(-1) : spec_.pairs[pair].friction; }
  /// The change of a meeting's momentum: none while its fields' separation, closed by their relative velocity
  /// over dt, stays positive.
  Vec<Dim> momentum_change(const Meeting& m, const GridNode<Dim>& a, const Vec<Dim>& v_a,
                           const GridNode<Dim>& b, const Vec<Dim>& v_b, Real dt) const;

  ContactSpec spec_;
  std::vector<std::int32_t> pair_of_;  ///< fields * fields: the pair index of (a, b), or -1
  std::vector<Meeting> meetings_;      ///< by node, then (a, b)
  std::vector<std::size_t>
      node_begin_;  ///< meetings_ of contact node k: [node_begin_[k], node_begin_[k + 1])
  std::vector<std::array<Real, Dim + 3>> recorded_;  ///< per meeting: what correct_update transmitted
  std::vector<std::array<ExactSum, Dim + 3>> sums_;
};

}  // namespace mpm
