// Reading the [[contact]] tables of a scene: which bodies get velocity fields of their own and how they meet.
#include <algorithm>
#include <cmath>
#include <limits>

#include "section.hpp"

namespace mpm::scene_reading {

namespace {
/// "[a, b]": the names of a group's bodies, for messages.
std::string group_names(const Scene& sc, const std::vector<std::size_t>& group) {
  std::string out = "[";
  for (std::size_t k = 0; k < group.size(); ++k) out += (k ? ", " : "") + sc.bodies[group[k]].name;
  return out + "]";
}

/// The body indices one side of `bodies` names: a body's name, or an array of names (a group).
std::vector<std::size_t> read_group(const Section& s, const Scene& sc, const toml::node& side) {
  std::vector<const toml::node*> names;
  if (const toml::array* a = side.as_array()) {
    for (const toml::node& e : *a) names.push_back(&e);
    if (names.empty()) s.fail("bodies", "a group of bodies is empty");
  } else {
    names.push_back(&side);
  }
  std::vector<std::size_t> group;
  for (const toml::node* n : names) {
    if (!n->is_string()) s.fail("bodies", "expected body names (strings), got " + describe(*n));
    const std::string name = n->value<std::string>().value();
    const auto found =
        std::find_if(sc.bodies.begin(), sc.bodies.end(), [&](const SceneBody& b) { return b.name == name; });
    if (found == sc.bodies.end()) {
      for (const SceneRigidBody& r : sc.rigid_bodies)
        if (r.name == name)
          s.fail("bodies",
                 in_quotes(name) +
                     " is a rigid body; give it a friction coefficient in its [[rigid_bodies]] table");
      std::string known;
      for (const SceneBody& b : sc.bodies)
        known += (known.empty() ? "" : ", ") + b.name;  // names: 64 characters
      s.fail("bodies", "unknown body " + in_quotes(name) + " (the bodies are " + known + ")");
    }
    group.push_back(static_cast<std::size_t>(found - sc.bodies.begin()));
  }
  std::sort(group.begin(), group.end());
  if (std::adjacent_find(group.begin(), group.end()) != group.end())
    s.fail("bodies", "a body is named twice in " + group_names(sc, group));
  return group;
}
}  // namespace

void read_contact(const Section& s, Scene& sc) {
  if (sc.implicit)
    s.fail("bodies",
           "contact between bodies is for the explicit integrators (usf, usl, cd, musl); the implicit step "
           "has one velocity field");
  const toml::array& sides =
      s.array("bodies", 2, "two bodies, or groups of bodies (arrays of names), that meet");
  SceneContact c;
  for (int k = 0; k < 2; ++k) c.groups[k] = read_group(s, sc, *sides.get(static_cast<std::size_t>(k)));
  for (std::size_t b : c.groups[0])
    if (std::binary_search(c.groups[1].begin(), c.groups[1].end(), b))
      s.fail("bodies", "body '" + sc.bodies[b].name + "' is on both sides");
  // A group is one velocity field: a body belongs to one group, the same in every table.
  for (const SceneContact& earlier : sc.contacts)
    for (const std::vector<std::size_t>& old : earlier.groups)
      for (const std::vector<std::size_t>& now : c.groups) {
        for (std::size_t b : now)
          if (old != now && std::binary_search(old.begin(), old.end(), b))
            s.fail("bodies", "body '" + sc.bodies[b].name + "' is in two groups, " + group_names(sc, old) +
                                 " and " + group_names(sc, now) + " (a group shares one velocity field)");
      }
  for (const SceneContact& earlier : sc.contacts)
    if ((earlier.groups[0] == c.groups[0] && earlier.groups[1] == c.groups[1]) ||
        (earlier.groups[0] == c.groups[1] && earlier.groups[1] == c.groups[0]))
      s.fail("bodies", "these two groups meet in an earlier [[contact]] table already");
  if (!s.has("friction"))
    s.fail("friction",
           "missing (a friction coefficient >= 0: 0 is frictionless, \"no-slip\" sticks while in contact)");
  const toml::node* mu = s.get("friction");
  if (mu->is_string() && mu->value<std::string>().value() == "no-slip") {
    c.friction = std::numeric_limits<double>::infinity();
  } else {
    c.friction = s.constant_number("friction", 0.0, sc.constants);
    if (!(c.friction >= 0))
      s.fail("friction", "expected a friction coefficient >= 0, got " + std::to_string(c.friction));
  }
  if (s.has("gap")) {
    c.gap = s.constant_number("gap", 0.0, sc.constants);
    if (!(c.gap > 0)) s.fail("gap", "expected a gap > 0 [cells], got " + std::to_string(c.gap));
    for (const SceneFace& f : sc.faces)
      if (f.kind == SceneFace::Kind::periodic)
        s.fail(
            "gap",
            "the gap of mass centres is not measured across periodic faces; drop gap or the periodic faces");
  }
  const std::string normal = s.choice("normals", "average", {"average", "larger", "first"});
  c.normal = normal == "larger"  ? ContactNormal::larger
             : normal == "first" ? ContactNormal::first
                                 : ContactNormal::average;
  sc.contacts.push_back(std::move(c));
}

void assign_fields(Scene& sc) {
  sc.body_field.assign(sc.bodies.size(), 0);
  std::vector<const std::vector<std::size_t>*> groups;
  for (const SceneContact& c : sc.contacts)
    for (const std::vector<std::size_t>& g : c.groups)
      if (std::none_of(groups.begin(), groups.end(), [&](const auto* known) { return *known == g; }))
        groups.push_back(&g);
  // The bodies no table names share field 0; then each group, in the order the tables name them (the groups
  // are disjoint: read_contact).
  std::size_t named = 0;
  for (const auto* g : groups) named += g->size();
  const bool rest = named < sc.bodies.size();
  const int first = rest ? 1 : 0;
  for (std::size_t k = 0; k < groups.size(); ++k)
    for (std::size_t b : *groups[k]) sc.body_field[b] = first + static_cast<int>(k);
  sc.fields = first + static_cast<int>(groups.size());
}

}  // namespace mpm::scene_reading
