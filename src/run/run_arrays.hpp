#pragma once
// Particle arrays of Eigen vectors as the flat arrays of a checkpoint or a Python view, and back, and a
// checkpoint's entries by key.
#include <algorithm>
#include <string>
#include <vector>

#include "mpm/core/errors.hpp"

namespace mpm::scene_engines {

template <class V>
std::vector<double> flat(const std::vector<V>& a) {
  std::vector<double> out;
  for (const V& v : a) out.insert(out.end(), v.data(), v.data() + v.size());
  return out;
}
template <class V>
void unflat(const std::vector<double>& in, std::vector<V>& a, const std::string& name) {
  const std::size_t per = static_cast<std::size_t>(V::SizeAtCompileTime);
  if (in.size() != a.size() * per) throw InputError("checkpoint: array '" + name + "' has the wrong size");
  for (std::size_t i = 0; i < a.size(); ++i)
    std::copy(in.begin() + i * per, in.begin() + (i + 1) * per, a[i].data());
}
template <class Map>
const auto& entry(const Map& map, const std::string& key, const std::string& where) {
  auto it = map.find(key);
  if (it == map.end()) throw InputError(where + ": not a checkpoint of this kind of run (no '" + key + "')");
  return it->second;
}

}  // namespace mpm::scene_engines
