#include "mpm/contact/multi_field.hpp"

#include <algorithm>
#include <string>

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"

namespace mpm {

void validate(const ContactSpec& contact) {
  if (contact.fields < 1 || contact.fields > 255)
    throw InputError("contact: " + std::to_string(contact.fields) + " velocity fields (expected 1 to 255)");
  std::vector<bool> seen(static_cast<std::size_t>(contact.fields * contact.fields), false);
  for (const ContactPair& p : contact.pairs) {
    const std::string at = "contact: pair (" + std::to_string(p.a) + ", " + std::to_string(p.b) + ")";
    if (p.a < 0 || p.b < 0 || p.a >= contact.fields || p.b >= contact.fields || p.a == p.b)
      throw InputError(at + ": expected two different fields of 0 to " + std::to_string(contact.fields - 1));
    if (!(p.friction >= 0))
      throw InputError(at + ": friction " + std::to_string(p.friction) + " (expected a coefficient >= 0)");
    if (!(p.gap > 0)) throw InputError(at + ": gap " + std::to_string(p.gap) + " (expected > 0 cells)");
    const std::size_t key =
        static_cast<std::size_t>(std::min(p.a, p.b) * contact.fields + std::max(p.a, p.b));
    if (seen[key]) throw InputError(at + ": the pair is given twice");
    seen[key] = true;
  }
}

bool measures_gaps(const ContactSpec& contact) {
  for (const ContactPair& p : contact.pairs)
    if (std::isfinite(p.gap)) return true;
  return false;
}

template <int Dim>
MultiFieldContact<Dim>::MultiFieldContact(const ContactSpec& spec)
    : spec_(spec),
      pair_of_(static_cast<std::size_t>(spec.fields * spec.fields), -1),
      sums_(spec.pairs.size()) {
  validate(spec);
  for (std::size_t k = 0; k < spec.pairs.size(); ++k) {
    const ContactPair& p = spec.pairs[k];
    pair_of_[static_cast<std::size_t>(p.a * spec.fields + p.b)] = static_cast<std::int32_t>(k);
    pair_of_[static_cast<std::size_t>(p.b * spec.fields + p.a)] = static_cast<std::int32_t>(k);
  }
}

template <int Dim>
void MultiFieldContact<Dim>::locate(const std::vector<Grid<Dim>*>& fields, Real min_mass,
                                    const IVec<Dim>& owned, const std::vector<Grid<Dim>>* positions) {
  const GridGeometry<Dim>& g = fields[0]->geometry;
  const auto nodes = static_cast<std::ptrdiff_t>(g.node_count());
  const int K = spec_.fields;
  // Chunks of nodes fixed by the grid, each scanned into its own list, joined in chunk order: the same list
  // whatever the thread count.
  constexpr std::ptrdiff_t chunk = 4096;
  const std::ptrdiff_t chunks = (nodes + chunk - 1) / chunk;
  std::vector<std::vector<Meeting>> found(static_cast<std::size_t>(chunks));
  parallel_for(
      chunks,
      [&](std::ptrdiff_t c) {
        std::vector<Meeting>& list = found[static_cast<std::size_t>(c)];
        for (std::ptrdiff_t n = c * chunk; n < std::min(nodes, (c + 1) * chunk); ++n) {
          std::array<std::uint16_t, 256> present;
          int count = 0;
          for (int k = 0; k < K; ++k)
            if (fields[k]->nodes[n].m > min_mass) present[count++] = static_cast<std::uint16_t>(k);
          if (count < 2) continue;
          const IVec<Dim> i = g.coords(n), global = g.global(i);
          bool mine = true;
          for (int d = 0; d < Dim; ++d) {
            const int last =
                g.periodic[d] ? g.cells[d] - 1 : g.cells[d];  // a periodic axis's node cells is node 0
            mine = mine && i[d] + g.ghost < owned[d] && global[d] >= 0 && global[d] <= last;
          }
          for (int x = 0; x < count; ++x)
            for (int y = x + 1; y < count; ++y) {
              const int a = present[x], b = present[y];
              const std::int32_t pair = pair_of_[static_cast<std::size_t>(a * K + b)];
              // From a into b, as the pair's first field's choice gives it (ContactNormal::first names that
              // field).
              const ContactNormal choice = pair < 0 ? ContactNormal::average : spec_.pairs[pair].normal;
              const Vec<Dim>& g_a = fields[a]->nodes[n].v_new;
              const Vec<Dim>& g_b = fields[b]->nodes[n].v_new;
              const Vec<Dim> n_ab = pair >= 0 && spec_.pairs[pair].a != a
                                        ? Vec<Dim>(-contact_normal<Dim>(g_b, g_a, choice))
                                        : contact_normal<Dim>(g_a, g_b, choice);
              // Nairn 2013: the mass centres' distance along the normal less the pair's gap.
              Real separation = -std::numeric_limits<Real>::infinity();
              if (pair >= 0 && std::isfinite(spec_.pairs[pair].gap) && positions) {
                const Vec<Dim> centre_a = (*positions)[a].nodes[n].v / fields[a]->nodes[n].m;
                const Vec<Dim> centre_b = (*positions)[b].nodes[n].v / fields[b]->nodes[n].m;
                separation = (centre_b - centre_a).dot(n_ab) - spec_.pairs[pair].gap * g.h;
              }
              list.push_back(Meeting{static_cast<std::int32_t>(n), static_cast<std::uint16_t>(a),
                                     static_cast<std::uint16_t>(b), pair, mine, n_ab, separation});
            }
        }
      },
      2);
  meetings_.clear();
  node_begin_.clear();
  for (const std::vector<Meeting>& list : found)
    for (const Meeting& m : list) {
      if (meetings_.empty() || meetings_.back().node != m.node) node_begin_.push_back(meetings_.size());
      meetings_.push_back(m);
    }
  node_begin_.push_back(meetings_.size());
  recorded_.assign(meetings_.size(), {});
}

template <int Dim>
Vec<Dim> MultiFieldContact<Dim>::momentum_change(const Meeting& m, const GridNode<Dim>& a,
                                                 const Vec<Dim>& v_a, const GridNode<Dim>& b,
                                                 const Vec<Dim>& v_b, Real dt) const {
  // Nairn 2013: the separation at the end of the step, closed by the relative velocity along the normal.
  if (m.separation + (v_b - v_a).dot(m.normal) * dt > 0) return Vec<Dim>::Zero();
  return pair_momentum_change<Dim>(a.m, v_a, b.m, v_b, m.normal, friction(m.pair));
}

template <int Dim>
void MultiFieldContact<Dim>::correct_velocity(const std::vector<Grid<Dim>*>& fields,
                                              NodeVelocity<Dim> v) const {
  // One node's meetings in order (pairs of three or more fields one after the other), nodes in parallel.
  parallel_for(static_cast<std::ptrdiff_t>(contact_nodes()), [&](std::ptrdiff_t k) {
    for (std::size_t j = node_begin_[k]; j < node_begin_[k + 1]; ++j) {
      const Meeting& m = meetings_[j];
      GridNode<Dim>& a = fields[m.a]->nodes[m.node];
      GridNode<Dim>& b = fields[m.b]->nodes[m.node];
      const Vec<Dim> dp = momentum_change(m, a, a.*v, b, b.*v, 0);
      a.*v += dp / a.m;
      b.*v -= dp / b.m;
    }
  });
}

template <int Dim>
void MultiFieldContact<Dim>::correct_update(const std::vector<Grid<Dim>*>& fields, Real dt) {
  parallel_for(static_cast<std::ptrdiff_t>(contact_nodes()), [&](std::ptrdiff_t k) {
    for (std::size_t j = node_begin_[k]; j < node_begin_[k + 1]; ++j) {
      const Meeting& m = meetings_[j];
      GridNode<Dim>& a = fields[m.a]->nodes[m.node];
      GridNode<Dim>& b = fields[m.b]->nodes[m.node];
      const Vec<Dim> dp = momentum_change(m, a, a.v_new, b, b.v_new, dt);
      a.v_new += dp / a.m;
      b.v_new -= dp / b.m;
      a.a += dp / (a.m * dt);
      b.a -= dp / (b.m * dt);
      // On field a by field b: the force, its compressive normal and tangential parts, and the power friction
      // dissipates, minus the force times the relative velocity after the correction.
      const Vec<Dim> f = dp / dt;
      const Real f_n = f.dot(m.normal);
      std::array<Real, Dim + 3>& r = recorded_[j];
      for (int d = 0; d < Dim; ++d) r[d] = f[d];
      r[Dim] = -f_n;
      r[Dim + 1] = (f - f_n * m.normal).norm();
      r[Dim + 2] = -f.dot(a.v_new - b.v_new);
    }
  });
  for (auto& s : sums_) s = {};
  for (std::size_t j = 0; j < meetings_.size(); ++j) {
    const Meeting& m = meetings_[j];
    if (m.pair < 0 || !m.owned) continue;
    // The pair's first field is spec a: a meeting (a, b) with a > b in the pair's order gives the opposite
    // force.
    const bool flipped = spec_.pairs[m.pair].a != m.a;
    for (int d = 0; d < Dim; ++d) sums_[m.pair][d].add(flipped ? -recorded_[j][d] : recorded_[j][d]);
    for (int q = Dim; q < Dim + 3; ++q) sums_[m.pair][q].add(recorded_[j][q]);
  }
}

template class MultiFieldContact<1>;
template class MultiFieldContact<2>;
template class MultiFieldContact<3>;

}  // namespace mpm
