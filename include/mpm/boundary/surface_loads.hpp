#pragma once
/// Loads on the surface of a body: a pressure that follows the deforming surface, or a dead traction per unit
/// reference area. Each is carried by the surface particles as a force; both engines add it to the body
/// force.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "mpm/core/model_geometry.hpp"
#include "mpm/core/parallel.hpp"
#include "mpm/core/types.hpp"
#include "mpm/particles/particles.hpp"

namespace mpm {

/// A particle's share of a loaded surface: its id and its outward reference area vector N dA
/// (lattice_surface).
template <int Dim>
struct SurfacePatch {
  std::int64_t id = 0;
  Vec<Dim> area = Vec<Dim>::Zero();
};

/// A pressure P(t) [Pa], positive pushing into the body along the current normal, or a traction t(t) [Pa] per
/// unit reference area whose direction stays fixed, on a set of patches.
template <int Dim>
struct SurfaceLoad {
  std::function<Real(Real t)> pressure;      ///< set for a pressure
  std::function<Vec<Dim>(Real t)> traction;  ///< set for a traction
  std::vector<SurfacePatch<Dim>> patches;
};

/// The force of a load on one patch of a particle with deformation gradient F:
/// - pressure: -P n da with the current area vector n da = J F^-T N dA (Nanson's relation); in axisymmetry F
/// is
///   the in-plane gradient, the areas are per radian, and the hoop stretch x_r / X_r multiplies J F^-T;
/// - traction: t |N dA|.
template <int Dim>
Vec<Dim> patch_force(const SurfaceLoad<Dim>& load, Real magnitude, const Vec<Dim>& traction,
                     const Vec<Dim>& area, const Mat<Dim>& F, const Vec<Dim>& x, const Vec<Dim>& X,
                     bool axisymmetric) {
  if (!load.pressure) return traction * area.norm();
  const Mat<Dim> cofactor = F.determinant() * F.inverse().transpose();
  return -magnitude * (axisymmetric ? x[0] / X[0] : 1.0) * (cofactor * area);
}

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
      for (const SurfacePatch<Dim>& s : loads_[l].patches)
        entries_[next[s.id]++] = {static_cast<int>(l), s.area};
  }

  bool empty() const { return loads_.empty(); }
  const std::vector<SurfaceLoad<Dim>>& loads() const { return loads_; }

  /// Add weight times each loaded particle's surface force at time t over its mass to accel (sized to the
  /// particles), the deformation of the particles as they stand.
  void accelerate(const ParticleSet<Dim>& p, Real t, Real weight, Geometry geometry,
                  std::vector<Vec<Dim>>& accel) const {
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
        const Vec<Dim> f = patch_force(loads_[en.load], magnitude[en.load], traction[en.load], en.area,
                                       p.F[i], p.x[i], p.X[i], axisymmetric);
        accel[i] += weight / p.m[i] * f;
      }
    });
  }

 private:
  struct Entry {
    int load;
    Vec<Dim> area;
  };
  std::vector<SurfaceLoad<Dim>> loads_;
  std::vector<std::int32_t> first_;
  std::vector<Entry> entries_;
};

}  // namespace mpm
