#pragma once
// The particle fields of one ParaView frame of a scene run (particles_NNNN.vtp).
#include <string>
#include <vector>

#include "mpm/io/vtk.hpp"
#include "mpm/materials/material.hpp"
#include "mpm/particles/particles.hpp"
#include "mpm/scene/expression.hpp"
#include "run_units.hpp"
#include "scene_engine.hpp"

namespace mpm {

/// The scene's [check] block as an exact solution for ErrorNorms.
template <int Dim>
struct ExactFromScene {
  const std::vector<ExpressionPtr>* u;
  Vec<Dim> displacement(const Vec<Dim>& X, Real t) const {
    double vars[Dim + 1];
    for (int d = 0; d < Dim; ++d) vars[d] = X[d];
    vars[Dim] = t;
    return vector_value<Vec<Dim>>(*u, vars);
  }
};

/// The units of the engines' own frame fields (add_fields): the rate-form state's and the laws' declared
/// columns (StateColumn::unit); the rest (field, failed) are indices.
inline std::string engine_field_unit(const std::string& name, const std::vector<Material>& materials,
                                     const std::string& extent) {
  if (name == "plastic_strain") return "1";
  if (name == "temperature_rise") return "K";
  if (name == "internal_energy") return "J" + extent;
  for (const DeclaredColumn& column : declared_columns(materials))
    if (column.name == name) return column.unit;
  return "";
}

/// Points (3 coordinates each) and fields of the engine's particles at time t: velocity, displacement, Cauchy
/// stress (xx yy zz xy yz xz, VTK's order of a symmetric tensor), F (3 x 3 by columns, VTK's order of a
/// tensor: component a + 3 c is F(a, c)), J, volume, mass, material, id (Int64), the [check] error |u -
/// u_exact| when `exact` is given, and the engine's own fields; each with its components' names and its unit
/// (mass, volume and energy per metre of thickness or per radian in 2-D: per_extent).
template <int Dim>
void frame_fields(const SceneEngine<Dim>& engine, const std::vector<Material>& materials, Geometry geometry,
                  const std::vector<ExpressionPtr>& exact, Real t, std::vector<double>& points,
                  std::vector<io::PointField>& fields) {
  const ParticleSet<Dim>& p = engine.particles();
  const std::size_t n = p.size();
  const std::string extent = per_extent<Dim>(geometry);
  points.assign(3 * n, 0.0);
  const std::vector<std::string> xyz{"x", "y", "z"};
  io::PointField velocity{"velocity", 3, std::vector<double>(3 * n, 0.0), false, xyz, "m/s"};
  io::PointField displacement{"displacement", 3, std::vector<double>(3 * n, 0.0), false, xyz, "m"};
  io::PointField stress{
      "stress", 6, std::vector<double>(6 * n, 0.0), false, {"xx", "yy", "zz", "xy", "yz", "xz"}, "Pa"};
  io::PointField deformation{
      "F", 9, std::vector<double>(9 * n, 0.0), false, {"xx", "yx", "zx", "xy", "yy", "zy", "xz", "yz", "zz"},
      "1"};
  io::PointField J{"J", 1, {}, false, {}, "1"}, volume{"volume", 1, {}, false, {}, "m^3" + extent};
  io::PointField mass{"mass", 1, {}, false, {}, "kg" + extent}, material{"material", 1, {}};
  io::PointField error{"error", 1, {}, false, {}, "m"}, id{"id", 1, {}, true};
  for (io::PointField* f : {&J, &volume, &mass, &material, &id, &error}) f->values.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Real Ji = p.F[i].determinant();
    for (int d = 0; d < Dim; ++d) {
      points[3 * i + d] = p.x[i][d];
      velocity.values[3 * i + d] = p.v[i][d];
      displacement.values[3 * i + d] = p.x[i][d] - p.X[i][d];
    }
    engine.stress(i, &stress.values[6 * i]);
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        deformation.values[9 * i + a + 3 * c] = (a < Dim && c < Dim) ? p.F[i](a, c) : (a == c ? 1.0 : 0.0);
    J.values.push_back(Ji);
    volume.values.push_back(p.V[i]);
    mass.values.push_back(p.m[i]);
    material.values.push_back(p.material[i]);
    id.values.push_back(static_cast<double>(p.id[i]));
    if (!exact.empty())
      error.values.push_back(
          ((p.x[i] - p.X[i]) - ExactFromScene<Dim>{&exact}.displacement(p.X[i], t)).norm());
  }
  fields.clear();
  for (io::PointField* f :
       {&velocity, &displacement, &stress, &deformation, &J, &volume, &mass, &material, &id})
    fields.push_back(std::move(*f));
  if (!exact.empty()) fields.push_back(std::move(error));
  const std::size_t own = fields.size();
  engine.add_fields(fields);
  for (std::size_t k = own; k < fields.size(); ++k)
    fields[k].unit = engine_field_unit(fields[k].name, materials, extent);
}

}  // namespace mpm
