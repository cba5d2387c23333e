#pragma once
/// Kinematic boundary conditions on grid faces and node regions. Steffen et al. 2008, Sec. 3.4.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "mpm/core/exact_sum.hpp"
#include "mpm/core/model_geometry.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/core/types.hpp"
#include "mpm/grid/grid.hpp"

namespace mpm {

/// periodic: the face and its opposite are one (both must say so); the grid's halo carries it
/// (grid/halo.hpp). outflow: a free face that particles may cross; the engines remove them once they have
/// (particles/outflow.hpp). absorbing: viscous dashpots that let waves out (Lysmer & Kuhlemeyer 1969).
enum class FaceType { free, velocity, symmetry, periodic, outflow, absorbing };

/// A prescribed velocity as a function of time; an empty function means zero (a fixed wall).
template <int Dim>
using VelocityFn = std::function<Vec<Dim>(Real t)>;

/// Body acceleration b(X, t) as a function of reference position and time [m/s^2].
template <int Dim>
using BodyForceFn = std::function<Vec<Dim>(const Vec<Dim>& X, Real t)>;

template <int Dim>
struct FaceCondition {
  FaceType type = FaceType::free;
  VelocityFn<Dim> velocity;  ///< used when type == velocity
  /// A velocity face with friction >= 0 is a Coulomb wall moving at `velocity` (coulomb_contact,
  /// contact/coulomb.hpp): the body may leave it and slides along it against friction. Negative: it holds
  /// every component (no slip).
  Real friction = -1;
  /// An absorbing face's dashpots (Lysmer & Kuhlemeyer 1969): the traction -rho c_p v_n n - rho c_s v_t on
  /// the material at the face, rho c_p and rho c_s the impedances of the material it absorbs waves from [Pa
  /// s/m].
  Real normal_impedance = 0, shear_impedance = 0;
};

/// Every node (ghosts included) whose position lies in the box [lo, hi] gets the prescribed velocity.
template <int Dim>
struct RegionConstraint {
  Vec<Dim> lo, hi;
  VelocityFn<Dim> velocity;
};

/// Acceleration on constrained nodes: zero, or the velocity change the constraint imposes
/// a_i = (v_i^{n+1} - v_i^n)/dt (Steffen et al. 2008, Eq. (30)).
enum class ConstrainedAcceleration { zero, velocity_difference };

template <int Dim>
struct BoundarySpec {
  /// Faces in the order x-lo, x-hi, y-lo, y-hi, z-lo, z-hi.
  std::array<FaceCondition<Dim>, 2 * Dim> faces{};
  std::vector<RegionConstraint<Dim>> regions;
  ConstrainedAcceleration acceleration = ConstrainedAcceleration::zero;
};

/// The axes whose faces are periodic (validated in pairs by the specs).
template <int Dim>
std::array<bool, Dim> periodic_axes(const BoundarySpec<Dim>& spec) {
  std::array<bool, Dim> axes{};
  for (int d = 0; d < Dim; ++d) axes[d] = spec.faces[2 * d].type == FaceType::periodic;
  return axes;
}

/// The faces particles may leave through, in the order of BoundarySpec::faces.
template <int Dim>
std::array<bool, 2 * Dim> outflow_faces(const BoundarySpec<Dim>& spec) {
  std::array<bool, 2 * Dim> faces{};
  for (int f = 0; f < 2 * Dim; ++f) faces[f] = spec.faces[f].type == FaceType::outflow;
  return faces;
}

/// The faces that hold the material (velocity faces, Coulomb walls among them, and symmetry planes), in the
/// order of BoundarySpec::faces.
template <int Dim>
std::array<bool, 2 * Dim> wall_faces(const BoundarySpec<Dim>& spec) {
  std::array<bool, 2 * Dim> faces{};
  for (int f = 0; f < 2 * Dim; ++f)
    faces[f] = spec.faces[f].type == FaceType::velocity || spec.faces[f].type == FaceType::symmetry;
  return faces;
}

/// The type of each face, in the order of BoundarySpec::faces.
template <int Dim>
std::array<FaceType, 2 * Dim> face_types(const BoundarySpec<Dim>& spec) {
  std::array<FaceType, 2 * Dim> types{};
  for (int f = 0; f < 2 * Dim; ++f) types[f] = spec.faces[f].type;
  return types;
}

/// Whether the node at global grid coordinates i repeats another node: beyond a symmetry plane, a mirror
/// ghost that fold_and_mirror overwrites with its partner's fields; along a periodic axis, outside [0, cells
/// - 1], an image that PeriodicHalo fills with its owner's sums. Such a node is held as its original is, but
/// no reaction, friction power or force moment counts it: its original does, as the implicit engine's
/// unknowns skip it (mirrored_). Ghosts beyond the other faces hold particles' mass of their own, and count.
/// `faces`: face_types.
template <int Dim>
bool repeats_another(const std::array<FaceType, 2 * Dim>& faces, const IVec<Dim>& cells, const IVec<Dim>& i) {
  for (int d = 0; d < Dim; ++d) {
    const FaceType lo = faces[2 * d], hi = faces[2 * d + 1];
    if (lo == FaceType::periodic && (i[d] < 0 || i[d] >= cells[d])) return true;
    if ((lo == FaceType::symmetry && i[d] < 0) || (hi == FaceType::symmetry && i[d] > cells[d])) return true;
  }
  return false;
}

/// Throws InputError (prefixed with `at`) unless every periodic face has a periodic opposite face and its
/// axis at least 2 cells, and an axisymmetric grid's radial axis is neither periodic nor, on the axis r = lo
/// = 0, an outflow face.
template <int Dim>
void validate_faces(const BoundarySpec<Dim>& spec, const IVec<Dim>& cells, Geometry geometry, Real lo0,
                    const std::string& at);

/// Boundary conditions compiled to node lists for one grid.
template <int Dim>
class KinematicConstraints {
 public:
  KinematicConstraints(const BoundarySpec<Dim>& spec, const GridGeometry<Dim>& g);
  /// On a box of a divided grid: the reactions count the nodes of the first owned[d] storage layers along
  /// each axis, the box's own tiles (the layers above them are other boxes').
  KinematicConstraints(const BoundarySpec<Dim>& spec, const GridGeometry<Dim>& g, const IVec<Dim>& owned);

  /// Add each symmetry-face ghost node's contributions to its mirror node (reflected), then overwrite the
  /// ghost with the reflected mirror node: the grid then holds the fields of the body and its mirror image,
  /// so ghosts carry the negated normal velocity of their mirror node (Steffen et al. 2008, Sec. 3.4.2).
  void fold_and_mirror(Grid<Dim>& grid, NodeFields fields) const;
  /// The same for one vector field of the nodes (momentum, force, a re-projected momentum).
  void fold_and_mirror(Grid<Dim>& grid, NodeVelocity<Dim> field) const;
  /// Overwrite symmetry-plane ghost nodes with the reflected field of their mirror node (no fold).
  void mirror(Grid<Dim>& grid, NodeVelocity<Dim> field) const;
  /// Set mask[n] = 1 for every ghost node that copies a mirror node (mask sized to the grid).
  void mark_mirrored(std::vector<std::uint8_t>& mask) const;
  /// Double copies[n] for every node on a symmetry plane, once per plane: such a node holds the mass of the
  /// body alone, while the body with its mirror images would give it copies[n] times as much (2 on a plane, 4
  /// where two planes meet, 8 at a corner of three).
  void count_mirror_copies(std::vector<std::uint8_t>& copies) const;

  /// One constrained velocity component of one node; `group` indexes names() and velocities().
  struct Component {
    std::int32_t node;
    int component;
    int group;
  };
  /// Every constrained (node, component), group by group.
  std::vector<Component> components() const;

  /// One dashpot of an absorbing face on one velocity component of one node: the force -resistance v_c, with
  /// resistance = Z A (Z = rho c_p along the face's normal, rho c_s across it; A the node's share of the
  /// face).
  struct Dashpot {
    std::int32_t node;
    int component;
    int group;
    Real resistance;  ///< [N s/m]
    bool owned;       ///< its force counts in the group's reaction (owned, no copy of another node)
  };
  /// Every dashpot of the absorbing faces, group by group.
  std::vector<Dashpot> dashpots() const;

  /// Impose prescribed components on a node velocity field (&GridNode::v or &GridNode::v_new) at time t.
  void constrain_velocity(Grid<Dim>& grid, NodeVelocity<Dim> field, Real t) const;

  /// Impose prescribed components on v_new at time t_new and set the constrained acceleration components.
  /// Records the reaction of each constraint, the force it applied: sum_i m_i (a_i - a_i^free) over its
  /// nodes, with a_i the constrained acceleration the particles receive (zero, or Steffen et al. 2008,
  /// Eq. (30)). With several velocity fields (contact), each field's call after the first adds to the
  /// reactions and the friction power (`add_to_last`).
  void constrain_update(Grid<Dim>& grid, Real t_new, Real dt, bool add_to_last = false);

  /// One name per constraint ("x-min", ..., "region 0", ...), the order of reactions() and velocities().
  std::vector<std::string> names() const;
  /// Reaction force [N] of each constraint in the last constrain_update (normal component only on symmetry
  /// planes).
  const std::vector<Vec<Dim>>& reactions() const { return reactions_; }
  /// The same as exact sums over the owned nodes, to be added over the boxes of a divided grid.
  const std::vector<std::array<ExactSum, Dim>>& reaction_sums() const { return reaction_sums_; }
  /// The power friction dissipated on the Coulomb walls in the last constrain_update [W]: minus the force
  /// each wall applied at a node times the node's velocity relative to the wall after it, summed; as exact
  /// sums over the owned nodes, to be added over the boxes of a divided grid.
  const ExactSum& friction_power() const { return friction_power_; }
  /// The moments of each Coulomb wall's normal force over its nodes in the last constrain_update, exact sums
  /// over the owned nodes (to be added over the boxes): f_n, then f_n x_d and f_n x_d^2 along each axis d of
  /// the face plane (zero along the normal, and for the other constraints). contact_spread() makes a length
  /// of them.
  using Moments = std::array<ExactSum, 1 + 2 * Dim>;
  const std::vector<Moments>& normal_force_moments() const { return moments_; }
  /// Whether constraint g (names() order) is a Coulomb wall.
  bool coulomb(std::size_t g) const { return groups_[g].friction >= 0; }
  /// Take the last step's reactions of `other`, the same constraints compiled for another box (a rebalance
  /// between the step and its report).
  void keep_reactions(const KinematicConstraints& other) {
    reactions_ = other.reactions_;
    reaction_sums_ = other.reaction_sums_;
    friction_power_ = other.friction_power_;
    moments_ = other.moments_;
  }
  /// Prescribed velocity of each constraint at time t (zero on symmetry and absorbing faces).
  std::vector<Vec<Dim>> velocities(Real t) const;

 private:
  struct Group {
    std::string name;
    std::vector<std::int32_t> nodes;
    int component;                    ///< constrained component, or -1 for all
    VelocityFn<Dim> velocity;         ///< empty: zero
    std::vector<std::uint8_t> owned;  ///< per node: its reaction counts (owned here, not a copy)
    Real friction = -1;  ///< >= 0: a Coulomb wall (component -1), whose outward normal is `normal`
    Vec<Dim> normal = Vec<Dim>::Zero();
    /// An absorbing face (impedances > 0): the area of the face each node carries [m^(Dim-1)].
    Real normal_impedance = 0, shear_impedance = 0;
    std::vector<Real> area = {};
    bool absorbing() const { return normal_impedance > 0; }
  };
  struct Mirror {
    int axis;
    std::vector<std::int32_t> ghost, real;  ///< pairs reflected across the plane
  };
  Vec<Dim> value(const Group& grp, Real t) const;

  std::vector<Group> groups_;
  std::vector<Vec<Dim>> reactions_;
  std::vector<std::array<ExactSum, Dim>> reaction_sums_;
  ExactSum friction_power_;
  std::vector<Moments> moments_;
  std::vector<Mirror> mirrors_;
  ConstrainedAcceleration acceleration_;
};

/// The spread of a Coulomb wall's normal force: the force-weighted root-mean-square distance of its nodes
/// from the centre of the force, in the face plane, sqrt(sum f_n |x - x_c|^2 / sum f_n) [m], from the summed
/// moments (KinematicConstraints::normal_force_moments: f_n, f_n x_d, f_n x_d^2); 0 without a normal force. A
/// Hertzian line contact, whose pressure is a semi-ellipse of half-width a, has spread a / 2.
template <int Dim>
Real contact_spread(const std::array<Real, 1 + 2 * Dim>& moments) {
  if (!(moments[0] > 0)) return 0;
  Real variance = 0;
  for (int d = 0; d < Dim; ++d) {
    const Real centre = moments[1 + d] / moments[0];
    variance += moments[1 + Dim + d] / moments[0] - centre * centre;
  }
  return std::sqrt(std::max(variance, Real(0)));
}

}  // namespace mpm
