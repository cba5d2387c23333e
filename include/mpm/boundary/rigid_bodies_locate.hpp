#pragma once
/// RigidBodies::locate: the nodes each rigid body's points touch through a kernel's stencil. Included where
/// an engine is compiled (src/explicit/simulation_impl.hpp, src/implicit/simulation_impl.hpp).
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mpm/boundary/rigid_bodies.hpp"
#include "mpm/shape/stencil.hpp"

namespace mpm {

template <int Dim>
template <class Kernel>
void RigidBodies<Dim>::locate(const GridGeometry<Dim>& g, const std::string& when, const IVec<Dim>& owned) {
  const Real inv_h = 1 / g.h;
  owned_.resize(bodies_.size());
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const RigidBody<Dim>& body = bodies_[b];
    std::vector<std::pair<std::int32_t, bool>> touched;
    std::vector<std::pair<std::int32_t, Vec<Dim>>>
        gradients;  // a Coulomb body's: sum_p grad S_i(x_p), by node
    if (body.holds_inside)
      touched = nodes_inside(g, body.lo + displacement_[b], body.hi + displacement_[b], owned);
    for (const Vec<Dim>& x0 : body.points) {
      const Vec<Dim> x = x0 + displacement_[b];
      if (!g.contains(x)) throw SimulationFailure(when + ": rigid body '" + body.name + "' left the grid");
      if (body.holds_inside) continue;
      // The point's stencil as make_stencil locates it, its weights as for_each_node multiplies them.
      using Point = BoxKernel<Kernel>;  // an axis-aligned box: CPDI's is a tensor product too
      constexpr int N = Point::width;
      IVec<Dim> first;
      Real w[Dim][N], dw[Dim][N];
      for (int d = 0; d < Dim; ++d) {
        typename Point::Axis axis;
        first[d] = locate_axis<Point>(g, d, (x[d] - g.lo[d]) * inv_h, body.half_length[d] * inv_h, axis) +
                   g.ghost - g.offset[d];
        Point::weights_at(axis, w[d], dw[d]);
      }
      std::array<int, 3> k{};
      for (k[2] = 0; k[2] < (Dim > 2 ? N : 1); ++k[2])
        for (k[1] = 0; k[1] < (Dim > 1 ? N : 1); ++k[1])
          for (k[0] = 0; k[0] < N; ++k[0]) {
            Real S = w[0][k[0]];
            if constexpr (Dim == 2) S = w[0][k[0]] * w[1][k[1]];
            if constexpr (Dim == 3) S = w[0][k[0]] * (w[1][k[1]] * w[2][k[2]]);
            bool inside = S > 0, mine = true;
            std::int32_t flat = 0;
            IVec<Dim> layers;
            for (int d = Dim - 1; d >= 0; --d) {
              layers[d] = first[d] + k[d];
              inside = inside && layers[d] >= 0 && layers[d] < g.nodes_along(d);
              mine = mine && layers[d] < owned[d];
              flat = flat * g.nodes_along(d) + layers[d];
            }
            if (!inside) continue;
            touched.emplace_back(flat,
                                 mine && !repeats_another<Dim>(faces_, g.cells, global_node(g, layers)));
            if (body.friction < 0 || body.outward) continue;
            Vec<Dim> grad;
            for (int d = 0; d < Dim; ++d) {
              grad[d] = dw[d][k[d]];
              for (int e = 0; e < Dim; ++e)
                if (e != d) grad[d] *= w[e][k[e]];
            }
            gradients.emplace_back(flat, grad);
          }
    }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    nodes_[b].clear();
    owned_[b].clear();
    for (const auto& [n, mine] : touched) {
      nodes_[b].push_back(n);
      owned_[b].push_back(mine);
    }
    normals_[b].assign(nodes_[b].size(), Vec<Dim>::Zero());
    if (body.friction < 0) continue;
    if (body.outward) {  // the material meets the surface along minus its outward normal
      for (std::size_t k = 0; k < nodes_[b].size(); ++k)
        normals_[b][k] = -body.outward(g.position(g.coords(nodes_[b][k])) - displacement_[b]);
      continue;
    }
    // The points' gradient at a node points out of the body; the material meets it along minus that. Added
    // per node in the points' order, so the normals do not depend on how the grid is divided.
    std::stable_sort(gradients.begin(), gradients.end(),
                     [](const auto& a, const auto& c) { return a.first < c.first; });
    std::size_t at = 0;
    for (std::size_t k = 0; k < nodes_[b].size(); ++k) {
      Vec<Dim> sum = Vec<Dim>::Zero();
      for (; at < gradients.size() && gradients[at].first == nodes_[b][k]; ++at) sum += gradients[at].second;
      const Real length = sum.norm();
      if (length > 0) normals_[b][k] = -sum / length;
    }
  }
}

}  // namespace mpm
