#pragma once
/// Loads on the surface of a body: a pressure that follows the deforming surface, or a dead traction per unit
/// reference area. Each is carried by the surface particles as a force and its moment about the particle's
/// centre; both engines add them to the body force.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "mpm/core/model_geometry.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/core/types.hpp"
#include "mpm/grid/grid.hpp"
#include "mpm/particles/lattice_faces.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// A particle's share of a loaded surface: its id, the areas of the lattice faces that carry the load
/// (LatticeFaces) and half the lattice spacing, the distance from the particle's centre to those faces.
template <int Dim>
struct SurfacePatch {
  std::int64_t id = 0;
  LatticeFaces<Dim> faces{};
  Real half_spacing = 0;
};

/// A pressure P(t) [Pa], positive pushing into the body along the current normal, or a traction t(t) [Pa] per
/// unit reference area whose direction stays fixed, on a set of patches.
template <int Dim>
struct SurfaceLoad {
  std::function<Real(Real t)> pressure;      ///< set for a pressure
  std::function<Vec<Dim>(Real t)> traction;  ///< set for a traction
  std::vector<SurfacePatch<Dim>> patches;
};

/// The load of one patch on its particle: the force, and the first moment of its faces' forces about the
/// particle's centre in reference offsets, A = sum_f f_f (x) dX_f with dX_f = half_spacing N_f the offset of
/// face f. A face's force acts at the face, x_p + F dX_f, not at the particle's centre: to first order its
/// share at node i is S_i(x_p + F dX_f) = S_ip + grad S_ip . F dX_f, and the second term sums to grad S_ip .
/// (A F^T) (BodyForce). Exact where S_i is linear over the particle's domain (linear, GIMP and CPDI weights
/// of a domain inside one cell), so that a uniform stress balances the load at every node.
template <int Dim>
struct PatchLoad {
  Vec<Dim> force;
  Mat<Dim> moment;
};

/// The load of a patch of a particle with deformation gradient F:
/// - pressure: -P n da on each face, with the current area vector n da = J F^-T N dA (Nanson's relation); in
///   axisymmetry F is the in-plane gradient, the areas are per radian, and the hoop stretch x_r / X_r
///   multiplies J F^-T;
/// - traction: t |N dA| with N dA the patch's area vector (area_vector), its moment that of t on each face.
template <int Dim>
PatchLoad<Dim> patch_load(const SurfaceLoad<Dim>& load, Real magnitude, const Vec<Dim>& traction,
                          const SurfacePatch<Dim>& patch, const Mat<Dim>& F, const Vec<Dim>& x,
                          const Vec<Dim>& X, bool axisymmetric) {
  const Vec<Dim> area = area_vector<Dim>(patch.faces);
  if (!load.pressure) return {traction * area.norm(), traction * (patch.half_spacing * area).transpose()};
  Vec<Dim> both;  // the faces along each axis, N_f (x) N_f = e_d (x) e_d for both
  for (int d = 0; d < Dim; ++d) both[d] = patch.faces[2 * d] + patch.faces[2 * d + 1];
  const Mat<Dim> cofactor = F.determinant() * F.inverse().transpose();
  const Real scale = -magnitude * (axisymmetric ? x[0] / X[0] : 1.0);
  return {scale * (cofactor * area), (scale * patch.half_spacing) * (cofactor * both.asDiagonal())};
}

/// The surface loads the particles carry in one step, in storage order (empty without surface loads): each
/// particle's force f_p and moment A_p (patch_load's, weighted and summed), and where it stood at the step's
/// start. Over the step the faces' forces work f_p . (x_p^{n+1} - x_p^n) + (F_p^{n+1} - F_p^n) : A_p, each
/// face's force times the displacement of its face x_p + F_p dX_f: the work of the nodal forces they give
/// (BodyForce) on the grid velocities that move the particles.
template <int Dim>
struct SurfaceLoading {
  std::vector<Vec<Dim>> force;
  std::vector<Mat<Dim>> moment;
  std::vector<Vec<Dim>> x_start;
  std::vector<Real> FA_start;  ///< F_p^n : A_p

  bool empty() const { return force.empty(); }
  /// Cleared and sized to p's particles.
  void reset(const ParticleSet<Dim>& p) {
    force.assign(p.size(), Vec<Dim>::Zero());
    moment.assign(p.size(), Mat<Dim>::Zero());
  }
  /// Where the particles stand, once the loads are complete.
  void start(const ParticleSet<Dim>& p) {
    x_start = p.x;
    FA_start.resize(p.size());
    parallel_for(static_cast<std::ptrdiff_t>(p.size()),
                 [&](std::ptrdiff_t i) { FA_start[i] = p.F[i].cwiseProduct(moment[i]).sum(); });
  }
  /// The work of particle i's loads since start [J]; a particle that crossed a periodic face of `g` moved
  /// by less than half its period.
  Real work(const ParticleSet<Dim>& p, std::size_t i, const GridGeometry<Dim>& g) const {
    if (empty()) return 0;
    Vec<Dim> dx = p.x[i] - x_start[i];
    for (int d = 0; d < Dim; ++d)
      if (g.periodic[d]) {
        const Real period = g.h * g.cells[d];
        dx[d] -= period * std::round(dx[d] / period);
      }
    return force[i].dot(dx) + (p.F[i].cwiseProduct(moment[i]).sum() - FA_start[i]);
  }
  std::size_t bytes() const {
    return force.capacity() * sizeof(Vec<Dim>) + moment.capacity() * sizeof(Mat<Dim>) +
           x_start.capacity() * sizeof(Vec<Dim>) + FA_start.capacity() * sizeof(Real);
  }
  static constexpr std::size_t bytes_per_particle = 2 * sizeof(Vec<Dim>) + sizeof(Mat<Dim>) + sizeof(Real);
};

/// The surface loads of a run, indexed by particle id.
template <int Dim>
class SurfaceLoads {
 public:
  SurfaceLoads() = default;
  explicit SurfaceLoads(std::vector<SurfaceLoad<Dim>> loads) : loads_(std::move(loads)) {
    std::int64_t ids = 0;
    for (const SurfaceLoad<Dim>& l : loads_)
      for (const SurfacePatch<Dim>& s : l.patches) ids = std::max(ids, s.id + 1);
    // Entries of id k lie in [first_[k], first_[k + 1]), in load order.
    first_.assign(static_cast<std::size_t>(ids) + 1, 0);
    for (const SurfaceLoad<Dim>& l : loads_)
      for (const SurfacePatch<Dim>& s : l.patches) ++first_[s.id + 1];
    for (std::size_t k = 1; k < first_.size(); ++k) first_[k] += first_[k - 1];
    entries_.resize(first_.back());
    std::vector<std::int32_t> next(first_.begin(), first_.end() - 1);
    for (std::size_t l = 0; l < loads_.size(); ++l)
      for (const SurfacePatch<Dim>& s : loads_[l].patches) entries_[next[s.id]++] = {static_cast<int>(l), s};
  }

  bool empty() const { return loads_.empty(); }
  const std::vector<SurfaceLoad<Dim>>& loads() const { return loads_; }

  /// Add weight times each loaded particle's surface force and moment at time t to loading (sized to the
  /// particles: SurfaceLoading::reset), the deformation of the particles as they stand.
  void add_to_particles(const ParticleSet<Dim>& p, Real t, Real weight, Geometry geometry,
                        SurfaceLoading<Dim>& loading) const {
    if (loads_.empty()) return;
    std::vector<Real> magnitude(loads_.size(), 0);
    std::vector<Vec<Dim>> traction(loads_.size(), Vec<Dim>::Zero());
    for (std::size_t l = 0; l < loads_.size(); ++l) {
      if (loads_[l].pressure) magnitude[l] = loads_[l].pressure(t);
      if (loads_[l].traction) traction[l] = loads_[l].traction(t);
    }
    const bool axisymmetric = Dim == 2 && geometry == Geometry::axisymmetric;
    parallel_for(static_cast<std::ptrdiff_t>(p.size()), [&](std::ptrdiff_t i) {
      const std::int64_t id = p.id[i];
      if (id + 1 >= static_cast<std::int64_t>(first_.size())) return;
      for (std::int32_t e = first_[id]; e < first_[id + 1]; ++e) {
        const Entry& en = entries_[e];
        const PatchLoad<Dim> f = patch_load(loads_[en.load], magnitude[en.load], traction[en.load], en.patch,
                                            p.F[i], p.x[i], p.X[i], axisymmetric);
        loading.force[i] += weight * f.force;
        loading.moment[i] += weight * f.moment;
      }
    });
  }

 private:
  struct Entry {
    int load;
    SurfacePatch<Dim> patch;
  };
  std::vector<SurfaceLoad<Dim>> loads_;
  std::vector<std::int32_t> first_;
  std::vector<Entry> entries_;
};

}  // namespace mpm
