#include "mpm/scene/build.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "mpm/core/errors.hpp"
#include "mpm/particles/geostatic.hpp"
#include "mpm/particles/surface.hpp"
#include "mpm/particles/validate.hpp"
#include "mpm/scene/budget.hpp"
#include "particle_file.hpp"
#include "shapes.hpp"

namespace mpm {

namespace {

template <int Dim>
VelocityFn<Dim> velocity_of(const std::vector<ExpressionPtr>& components) {
  return [components](Real t) {
    const double vars[] = {t};
    return vector_value<Vec<Dim>>(components, vars);
  };
}

/// F = I + grad u by fourth-order central differences of the displacement expressions (when the scene gives u
/// but not F): error O(eps^4) ~ 1e-13 relative for smooth u.
template <int Dim>
Mat<Dim> gradient_of_displacement(const std::vector<ExpressionPtr>& u, const Vec<Dim>& X, Real length) {
  const Real eps = 1e-3 * length;
  Mat<Dim> F = Mat<Dim>::Identity();
  for (int b = 0; b < Dim; ++b) {
    auto at = [&](Real shift) {
      Vec<Dim> Y = X;
      Y[b] += shift;
      return vector_value<Vec<Dim>>(u, std::span<const double>(Y.data(), Dim));
    };
    F.col(b) += (8 * (at(eps) - at(-eps)) - (at(2 * eps) - at(-2 * eps))) / (12 * eps);
  }
  return F;
}

/// The grid faces' conditions.
template <int Dim>
BoundarySpec<Dim> boundary_of(const Scene& sc) {
  BoundarySpec<Dim> boundary;
  boundary.acceleration = sc.constrained_acceleration;
  for (int f = 0; f < 2 * Dim; ++f) {
    const SceneFace& face = sc.faces[f];
    FaceCondition<Dim>& fc = boundary.faces[f];
    fc.friction = face.friction;
    switch (face.kind) {
      case SceneFace::Kind::free:
        fc.type = FaceType::free;
        break;
      case SceneFace::Kind::fixed:
        fc.type = FaceType::velocity;  // an empty velocity function is zero
        break;
      case SceneFace::Kind::symmetry:
        fc.type = FaceType::symmetry;
        break;
      case SceneFace::Kind::periodic:
        fc.type = FaceType::periodic;
        break;
      case SceneFace::Kind::outflow:
        fc.type = FaceType::outflow;
        break;
      case SceneFace::Kind::velocity:
        fc.type = FaceType::velocity;
        fc.velocity = velocity_of<Dim>(face.velocity);
        break;
      case SceneFace::Kind::absorbing:
        fc.type = FaceType::absorbing;
        fc.normal_impedance = face.normal_impedance;
        fc.shear_impedance = face.shear_impedance;
        break;
    }
  }
  return boundary;
}

/// The scene's body force b(X, t); empty when it has none.
template <int Dim>
BodyForceFn<Dim> body_force_of(const Scene& sc) {
  if (sc.body_force.empty()) return {};
  return [body = sc.body_force](const Vec<Dim>& X, Real t) {
    double vars[Dim + 1];
    for (int d = 0; d < Dim; ++d) vars[d] = X[d];
    vars[Dim] = t;
    return vector_value<Vec<Dim>>(body, vars);
  };
}

/// Body k's particles: its shape's lattice, the rows of its particle file, or its mesh's Gauss points.
template <int Dim>
void seed_shape(const Scene& sc, std::size_t k, ParticleSet<Dim>& p) {
  const SceneBody& b = sc.bodies[k];
  const Real density = sc.materials[b.material].density;
  const auto material = static_cast<std::uint16_t>(b.material);
  if (b.shape == SceneBody::Shape::file) {
    read_particle_rows<Dim>(sc, b, "bodies[" + std::to_string(k) + "].file in " + sc.file.string(), p);
  } else if (b.shape == SceneBody::Shape::mesh) {
    for (const MeshPoint& m : b.mesh_points)
      p.add(Eigen::Map<const Vec<3>>(m.x.data()).template head<Dim>(), Vec<Dim>::Zero(),
            sc.materials[m.material].density * m.volume, m.volume, cube_half_lengths<Dim>(m.volume, sc.h),
            static_cast<std::uint16_t>(m.material));
  } else if (b.add.empty() && b.subtract.empty() && b.intersect.empty()) {
    fill_shape<Dim>(sc, b, density, material, p);
  } else {
    fill_combined<Dim>(sc, b, density, material, p);
  }
}

/// The lattice spacing s of a particle file's body that carries a surface load: its particles (reference
/// positions X, volumes V) must be cubes of one volume s^Dim whose centres lie s apart along each axis.
template <int Dim>
Real file_lattice_spacing(const Scene& sc, std::size_t k, const std::vector<Vec<Dim>>& X,
                          const std::vector<Real>& V) {
  const Real s = std::pow(V.front(), 1.0 / Dim);
  for (std::size_t i = 0; i < X.size(); ++i) {
    bool on = std::abs(V[i] - V.front()) <= 1e-9 * V.front();
    for (int d = 0; on && d < Dim; ++d) {
      const Real steps = (X[i][d] - X.front()[d]) / s;
      on = std::abs(steps - std::round(steps)) <= 1e-6;
    }
    if (!on)
      throw InputError(
          sc.file.string() + ": bodies[" + std::to_string(k) +
          "].file: a surface load needs the file's "
          "particles on a lattice, cubes of one volume whose centres lie its side apart (the first: " +
          "volume " + format_number(V.front()) + ", side " + format_number(s) + "); its particle " +
          std::to_string(i + 1) + " at " + format_point<Dim>(X[i]) + " with volume " + format_number(V[i]) +
          " is not");
  }
  return s;
}

/// The scene's pressures and tractions on the surfaces of bodies (lattice_surface of each loaded body, ids as
/// seed_bodies gives them, less the faces on symmetry planes), each kept to the faces looking along `face`
/// and the particles in its region.
template <int Dim>
SurfaceLoads<Dim> surface_loads_of(const Scene& sc) {
  if (sc.surface_loads.empty()) return {};
  std::vector<std::size_t> first(sc.bodies.size() + 1, 0);
  std::vector<std::vector<LatticeFaces<Dim>>> faces(sc.bodies.size());
  std::vector<Real> spacing(sc.bodies.size());
  ParticleSet<Dim> p;
  for (std::size_t k = 0; k < sc.bodies.size(); ++k) {
    seed_shape<Dim>(sc, k, p);
    first[k + 1] = p.size();
    const bool loaded = std::any_of(sc.surface_loads.begin(), sc.surface_loads.end(),
                                    [&](const SceneSurfaceLoad& l) { return l.body == k; });
    if (!loaded || first[k + 1] == first[k]) continue;
    const std::vector<Vec<Dim>> X(p.X.begin() + static_cast<std::ptrdiff_t>(first[k]), p.X.end());
    spacing[k] = sc.bodies[k].shape == SceneBody::Shape::file
                     ? file_lattice_spacing<Dim>(
                           sc, k, X, {p.V0.begin() + static_cast<std::ptrdiff_t>(first[k]), p.V0.end()})
                     : sc.h / sc.bodies[k].ppc;
    faces[k] = lattice_surface<Dim>(X, X.front(), spacing[k], sc.geometry == Geometry::axisymmetric);
    for (std::size_t j = 0; j < X.size(); ++j)
      for (int f = 0; f < 2 * Dim; ++f) {  // a face on a symmetry plane is the cut of a mirrored body
        const int axis = f / 2;
        const Real plane = X[j][axis] + (f % 2 ? 0.5 : -0.5) * spacing[k];
        const Real grid_face = f % 2 ? sc.grid_hi[axis] : sc.grid_lo[axis];
        if (sc.faces[f].kind == SceneFace::Kind::symmetry && std::abs(plane - grid_face) < 1e-9 * sc.h)
          faces[k][j][f] = 0;
      }
  }
  std::vector<SurfaceLoad<Dim>> loads;
  for (const SceneSurfaceLoad& l : sc.surface_loads) {
    SurfaceLoad<Dim> load;
    if (l.pressure)
      load.pressure = [e = l.pressure](Real t) {
        const double vars[] = {t};
        return (*e)(vars);
      };
    else
      load.traction = velocity_of<Dim>(l.traction);  // a vector function of t
    const Real half_spacing = 0.5 * spacing[l.body];
    for (std::size_t j = 0; j < faces[l.body].size(); ++j) {
      LatticeFaces<Dim> f = faces[l.body][j];
      const Vec<Dim>& X = p.X[first[l.body] + j];
      if (l.face >= 0) {  // the lattice face looking out along the face's normal
        const Real kept = f[l.face];
        f = {};
        f[l.face] = kept;
      }
      bool in = std::any_of(f.begin(), f.end(), [](Real a) { return a > 0; });
      for (int d = 0; in && d < Dim && !l.lo.empty(); ++d) in = X[d] >= l.lo[d] && X[d] <= l.hi[d];
      if (in) load.patches.push_back({p.id[first[l.body] + j], f, half_spacing});
    }
    loads.push_back(std::move(load));
  }
  return SurfaceLoads<Dim>(std::move(loads));
}

/// Rigid boxes of points at ppc per cell per axis, with their prescribed velocities.
template <int Dim>
std::vector<RigidBody<Dim>> rigid_bodies_of(const Scene& sc) {
  std::vector<RigidBody<Dim>> out;
  for (const SceneRigidBody& r : sc.rigid_bodies) {
    ParticleSet<Dim> points;
    const Real spacing = sc.h / r.ppc;
    fill_shape<Dim>(sc, r, 1.0, 0, points);
    if (points.size() == 0)
      throw InputError(sc.file.string() + ": rigid_bodies[" + std::to_string(out.size()) + "] (" + r.name +
                       "): the shape holds no point of its lattice (a finer ppc may)");
    RigidBody<Dim> body{r.name, points.x, Vec<Dim>::Constant(0.5 * spacing), velocity_of<Dim>(r.velocity)};
    for (int d = 0; d < Dim; ++d) body.imposes[d] = r.imposes[d];
    body.friction = r.friction;
    if (r.friction >= 0) body.outward = outward_normal_of<Dim>(r);
    body.holds_inside = r.holds_inside;  // a box's only (the reader)
    if (r.holds_inside) {
      body.lo = to_vec<Dim>(r.lo);
      body.hi = to_vec<Dim>(r.hi);
    }
    out.push_back(std::move(body));
  }
  return out;
}
}  // namespace

namespace {
/// What both engines' specs hold of the scene.
template <int Dim>
ModelSpec<Dim> make_model(const Scene& sc) {
  ModelSpec<Dim> model;
  model.grid_lo = to_vec<Dim>(sc.grid_lo);
  model.h = sc.h;
  for (int d = 0; d < Dim; ++d) model.cells[d] = sc.cells[d];
  model.kernel = sc.kernel;
  model.geometry = sc.geometry;
  model.materials = material_laws(sc);
  model.boundary = boundary_of<Dim>(sc);
  model.rigid_bodies = rigid_bodies_of<Dim>(sc);
  model.gravity = to_vec<Dim>(sc.gravity);
  model.body_force = body_force_of<Dim>(sc);
  model.surface_loads = surface_loads_of<Dim>(sc);
  model.flip_fraction = sc.flip_fraction;
  model.transfer = sc.transfer;
  return model;
}
}  // namespace

template <int Dim>
SimulationSpec<Dim> make_spec(const Scene& sc) {
  SimulationSpec<Dim> spec;
  static_cast<ModelSpec<Dim>&>(spec) = make_model<Dim>(sc);
  spec.integrator = sc.integrator;
  spec.dt = sc.dt;
  spec.cfl = sc.cfl;
  spec.reproject_light_nodes = sc.reproject_light_nodes;
  spec.local_damping = sc.local_damping;
  spec.account_load_power = true;  // history.csv's external work
  spec.contact.fields = sc.fields;
  for (const SceneContact& c : sc.contacts)
    spec.contact.pairs.push_back(
        {sc.body_field[c.groups[0][0]], sc.body_field[c.groups[1][0]], c.friction, c.normal, c.gap});
  validate(spec);
  return spec;
}

template <int Dim>
ParticleSet<Dim> seed_bodies(const Scene& sc) {
  ParticleSet<Dim> p;
  p.reserve(static_cast<std::size_t>(estimate_budget(sc).particles));  // no array grows past what it needs
  const Vec<Dim> grid_lo = to_vec<Dim>(sc.grid_lo), grid_hi = to_vec<Dim>(sc.grid_hi);
  for (std::size_t k = 0; k < sc.bodies.size(); ++k) {
    const SceneBody& b = sc.bodies[k];
    const Real density = sc.materials[b.material].density;
    const std::size_t first = p.size();
    const Real spacing = sc.h / b.ppc;
    seed_shape<Dim>(sc, k, p);
    const std::string name = "bodies[" + std::to_string(k) + "] (" + b.name + ")";
    if (p.size() == first) throw InputError(sc.file.string() + ": " + name + ": the body has no particles");
    if (!sc.body_field.empty())
      std::fill(p.field.begin() + static_cast<std::ptrdiff_t>(first), p.field.end(),
                static_cast<std::uint16_t>(sc.body_field[k]));
    if (sc.kernel == KernelKind::ugimp &&
        sc.gimp_length)  // the smoothing length l as half-lengths l/2, both engines
      for (std::size_t i = first; i < p.size(); ++i) p.l0[i] = Vec<Dim>::Constant(0.5 * *sc.gimp_length);
    for (std::size_t i = first; i < p.size(); ++i) {
      const Vec<Dim> X = p.X[i];
      for (int d = 0; d < Dim; ++d)
        if (!(X[d] >= grid_lo[d] && X[d] <= grid_hi[d]))
          throw InputError(sc.file.string() + ": " + name + ": particle " + std::to_string(i - first) +
                           " lies outside the grid");
      const std::span<const double> at(X.data(), Dim);
      if (!b.displacement.empty()) {
        p.x[i] = X + vector_value<Vec<Dim>>(b.displacement, at);
        if (!b.deformation.empty()) {
          for (int r = 0; r < Dim; ++r)
            for (int c = 0; c < Dim; ++c) p.F[i](r, c) = (*b.deformation[r * Dim + c])(at);
        } else {
          p.F[i] = gradient_of_displacement<Dim>(b.displacement, X, sc.h);
        }
      }
      if (!b.velocity.empty())
        p.v[i] = vector_value<Vec<Dim>>(b.velocity, std::span<const double>(X.data(), Dim));
    }
    check_initial_speed(sc, name + ".velocity", fastest_speed<Dim>(std::span(p.v).subspan(first)));
    if (b.k0 >= 0) {
      const Vec<Dim> g = to_vec<Dim>(sc.gravity);
      if (!(g.norm() > 0))
        throw InputError(sc.file.string() + ": " + name +
                         ".k0: a geostatic stress needs gravity (loads.gravity)");
      set_geostatic_stress<Dim>(p, first, p.size(), density, b.k0, g, spacing);
    }
  }
  if (!p.state.empty())
    p.state.resize_keeping(p.size());  // bodies seeded after the first one in geostatic stress
  return p;
}

template <int Dim>
ImplicitSpec<Dim> make_implicit_spec(const Scene& sc) {
  ImplicitSpec<Dim> spec;
  static_cast<ModelSpec<Dim>&>(spec) = make_model<Dim>(sc);
  const SceneImplicit& im = sc.implicit_step;
  spec.formulation = im.formulation;
  spec.solver = im.solver;
  spec.theta = im.theta;
  spec.newton = im.newton;
  spec.frozen_jacobian = im.frozen_jacobian;
  spec.scaled_residual = im.scaled_residual;
  spec.consistent_mass = im.consistent_mass;
  spec.move_with_projected_velocity = im.move_with_projected_velocity;
  spec.step = {sc.cfl, sc.dt, im.step_factor, im.start_factor, im.growth, im.max_retries};
  validate(spec, sc.file.string());
  return spec;
}

template SimulationSpec<1> make_spec<1>(const Scene&);
template SimulationSpec<2> make_spec<2>(const Scene&);
template SimulationSpec<3> make_spec<3>(const Scene&);
template ImplicitSpec<1> make_implicit_spec<1>(const Scene&);
template ImplicitSpec<2> make_implicit_spec<2>(const Scene&);
template ImplicitSpec<3> make_implicit_spec<3>(const Scene&);
template ParticleSet<1> seed_bodies<1>(const Scene&);
template ParticleSet<2> seed_bodies<2>(const Scene&);
template ParticleSet<3> seed_bodies<3>(const Scene&);

}  // namespace mpm
