#include "shapes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mpm/geometry/surface_normal.hpp"
#include "mpm/particles/generate.hpp"

namespace mpm {

namespace {
/// The corners of the part of the lattice a box from the grid's lo would have (ppc particles per cell per
/// axis) that covers [lo, hi] within the grid: shapes seeded on it meet boxes and each other without gaps or
/// overlaps, and a shape reaching past a symmetry face (read_shape) is cut at its plane.
template <int Dim>
std::pair<Vec<Dim>, Vec<Dim>> lattice_cover(const Scene& sc, const Vec<Dim>& lo, const Vec<Dim>& hi,
                                            Real spacing) {
  const Vec<Dim> grid_lo = to_vec<Dim>(sc.grid_lo), grid_hi = to_vec<Dim>(sc.grid_hi);
  return {grid_lo.array() + spacing * ((lo.cwiseMax(grid_lo) - grid_lo) / spacing).array().floor(),
          grid_lo.array() + spacing * ((hi.cwiseMin(grid_hi) - grid_lo) / spacing).array().ceil()};
}

/// The box whose lattice a box, disk or ring fills: [lo, hi] itself inside the grid, or the grid's lattice
/// covering its part inside (lattice_cover) when it reaches past a symmetry face.
template <int Dim>
std::pair<Vec<Dim>, Vec<Dim>> seeded_box(const Scene& sc, const Vec<Dim>& lo, const Vec<Dim>& hi,
                                         Real spacing) {
  if ((lo.array() >= to_vec<Dim>(sc.grid_lo).array()).all() &&
      (hi.array() <= to_vec<Dim>(sc.grid_hi).array()).all())
    return {lo, hi};
  return lattice_cover<Dim>(sc, lo, hi, spacing);
}

/// Whether x lies inside, given the sorted crossings of its line with a closed surface: an odd number below
/// it.
bool odd_below(const std::vector<Real>& crossings, Real x) {
  return (std::lower_bound(crossings.begin(), crossings.end(), x) - crossings.begin()) % 2 == 1;
}

/// The corners of a lattice shape's bounding box [m].
template <int Dim>
std::pair<Vec<Dim>, Vec<Dim>> bounds_of(const SceneShape& s) {
  switch (s.shape) {
    case SceneShape::Shape::disk:
    case SceneShape::Shape::ring: {
      const Vec<Dim> c = to_vec<Dim>(s.center);
      return {c.array() - s.radius, c.array() + s.radius};
    }
    case SceneShape::Shape::polygon:
      if constexpr (Dim == 2) return s.polygon.bounds();
      break;
    case SceneShape::Shape::surface:
      if constexpr (Dim == 3) return s.surface.bounds();
      break;
    case SceneShape::Shape::box:
    case SceneShape::Shape::file:
    case SceneShape::Shape::mesh:
      break;
  }
  return {to_vec<Dim>(s.lo), to_vec<Dim>(s.hi)};
}

/// Whether x lies in a lattice shape (a surface's test casts one line; fill_shape casts one a row).
template <int Dim>
bool shape_contains(const SceneShape& s, const Vec<Dim>& x) {
  switch (s.shape) {
    case SceneShape::Shape::box:
      return (x.array() >= to_vec<Dim>(s.lo).array()).all() && (x.array() <= to_vec<Dim>(s.hi).array()).all();
    case SceneShape::Shape::disk:
    case SceneShape::Shape::ring: {
      const Real r = (x - to_vec<Dim>(s.center)).norm();
      return r <= s.radius && r >= s.inner_radius;
    }
    case SceneShape::Shape::polygon:
      if constexpr (Dim == 2) return s.polygon.contains(x);
      break;
    case SceneShape::Shape::surface:
      if constexpr (Dim == 3) {
        return odd_below(s.surface.crossings(x[1], x[2]), x[0]);
      }
      break;
    case SceneShape::Shape::file:
    case SceneShape::Shape::mesh:
      break;
  }
  return false;
}
}  // namespace

template <int Dim>
void fill_shape(const Scene& sc, const SceneShape& b, Real density, std::uint16_t material,
                ParticleSet<Dim>& p) {
  const Real spacing = sc.h / b.ppc;
  switch (b.shape) {
    case SceneBody::Shape::box: {
      const auto [lo, hi] = seeded_box<Dim>(sc, to_vec<Dim>(b.lo), to_vec<Dim>(b.hi), spacing);
      fill_box<Dim>(p, lo, hi, spacing, density, material);
      break;
    }
    case SceneBody::Shape::disk:
    case SceneBody::Shape::ring: {
      const Vec<Dim> c = to_vec<Dim>(b.center);
      const Real r_in = b.inner_radius, r_out = b.radius;
      const auto [lo, hi] = seeded_box<Dim>(sc, c.array() - r_out, c.array() + r_out, spacing);
      fill_box<Dim>(p, lo, hi, spacing, density, material, {}, [&](const Vec<Dim>& x) {
        const Real r = (x - c).norm();
        return r <= r_out && r >= r_in;
      });
      break;
    }
    case SceneBody::Shape::polygon:
      if constexpr (Dim == 2) {
        const auto [lo, hi] = b.polygon.bounds();
        const auto [start, end] = lattice_cover<2>(sc, lo, hi, spacing);
        fill_box<2>(p, start, end, spacing, density, material, {},
                    [&](const Vec<2>& x) { return b.polygon.contains(x); });
      }
      break;
    case SceneBody::Shape::surface:
      if constexpr (Dim == 3) {
        const auto [lo, hi] = b.surface.bounds();
        const auto [start, end] = lattice_cover<3>(sc, lo, hi, spacing);
        // fill_box visits the lattice row by row along x: the crossings of a row's line with the surface
        // are found once, and a point is inside when an odd number of them lie below it.
        std::vector<Real> row;
        Vec<2> row_at(std::nan(""), std::nan(""));
        fill_box<3>(p, start, end, spacing, density, material, {}, [&](const Vec<3>& x) {
          if (x[1] != row_at[0] || x[2] != row_at[1]) {
            row = b.surface.crossings(x[1], x[2]);
            row_at = {x[1], x[2]};
          }
          return odd_below(row, x[0]);
        });
      }
      break;
    case SceneBody::Shape::file:  // a body's particles from a file or a mesh: seed_shape
    case SceneBody::Shape::mesh:
      break;
  }
}

template <int Dim>
void fill_combined(const Scene& sc, const SceneBody& b, Real density, std::uint16_t material,
                   ParticleSet<Dim>& p) {
  auto [lo, hi] = bounds_of<Dim>(b);
  for (const SceneShape& s : b.add) {
    const auto [a, z] = bounds_of<Dim>(s);
    lo = lo.cwiseMin(a), hi = hi.cwiseMax(z);
  }
  const Real spacing = sc.h / b.ppc;
  const auto [start, end] = lattice_cover<Dim>(sc, lo, hi, spacing);
  const auto in = [&](const SceneShape& s, const Vec<Dim>& x) { return shape_contains<Dim>(s, x); };
  fill_box<Dim>(p, start, end, spacing, density, material, {}, [&](const Vec<Dim>& x) {
    const auto at = [&](const SceneShape& s) { return in(s, x); };
    return (in(b, x) || std::any_of(b.add.begin(), b.add.end(), at)) &&
           std::all_of(b.intersect.begin(), b.intersect.end(), at) &&
           std::none_of(b.subtract.begin(), b.subtract.end(), at);
  });
}

template <int Dim>
OutwardNormalFn<Dim> outward_normal_of(const SceneShape& shape) {
  switch (shape.shape) {
    case SceneShape::Shape::box:
      return [lo = to_vec<Dim>(shape.lo), hi = to_vec<Dim>(shape.hi)](const Vec<Dim>& x) {
        // Outside: from the nearest point of the box; inside or on it: the nearest face's normal.
        const Vec<Dim> away = x - x.cwiseMax(lo).cwiseMin(hi);
        if (away.norm() > 1e-12 * (hi - lo).norm()) return Vec<Dim>(away.normalized());
        Vec<Dim> n = Vec<Dim>::Zero();
        Real nearest = std::numeric_limits<Real>::infinity();
        for (int d = 0; d < Dim; ++d)
          for (const Real side : {-1.0, 1.0}) {
            const Real to_face = side < 0 ? x[d] - lo[d] : hi[d] - x[d];
            if (to_face < nearest) {
              nearest = to_face;
              n = Vec<Dim>::Zero();
              n[d] = side;
            }
          }
        return n;
      };
    case SceneShape::Shape::disk:
    case SceneShape::Shape::ring:
      // Radial: out of the outer circle, or into the hole from the nearer inner one.
      return [c = to_vec<Dim>(shape.center), mid = 0.5 * (shape.radius + shape.inner_radius),
              solid = shape.inner_radius == 0](const Vec<Dim>& x) {
        const Real r = (x - c).norm();
        if (r == 0) return Vec<Dim>(Vec<Dim>::Unit(0));
        return Vec<Dim>((solid || r >= mid ? 1 : -1) * (x - c) / r);
      };
    case SceneShape::Shape::polygon:
      if constexpr (Dim == 2)
        return [polygon = shape.polygon](const Vec<2>& x) { return polygon.outward_normal(x); };
      break;
    case SceneShape::Shape::surface:
      if constexpr (Dim == 3)
        return [normal = SurfaceNormal(shape.surface)](const Vec<3>& x) mutable { return normal(x); };
      break;
    case SceneShape::Shape::file:
    case SceneShape::Shape::mesh:
      break;
  }
  return {};
}

template void fill_shape<1>(const Scene&, const SceneShape&, Real, std::uint16_t, ParticleSet<1>&);
template void fill_shape<2>(const Scene&, const SceneShape&, Real, std::uint16_t, ParticleSet<2>&);
template void fill_shape<3>(const Scene&, const SceneShape&, Real, std::uint16_t, ParticleSet<3>&);
template void fill_combined<1>(const Scene&, const SceneBody&, Real, std::uint16_t, ParticleSet<1>&);
template void fill_combined<2>(const Scene&, const SceneBody&, Real, std::uint16_t, ParticleSet<2>&);
template void fill_combined<3>(const Scene&, const SceneBody&, Real, std::uint16_t, ParticleSet<3>&);

template OutwardNormalFn<1> outward_normal_of<1>(const SceneShape&);
template OutwardNormalFn<2> outward_normal_of<2>(const SceneShape&);
template OutwardNormalFn<3> outward_normal_of<3>(const SceneShape&);

}  // namespace mpm
