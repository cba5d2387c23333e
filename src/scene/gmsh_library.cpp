#include "gmsh_library.hpp"

#include <dlfcn.h>
#include <gmshc.h>  // the C API's declarations only: the library is loaded below

#include <mutex>
#include <type_traits>

namespace mpm::scene_reading {

namespace {
/// The C API's functions that reading a mesh calls, resolved in the library MPM_GMSH_LIBRARY (its path when
/// the program was configured).
struct Api {
  decltype(&gmshInitialize) initialize;
  decltype(&gmshFinalize) finalize;
  decltype(&gmshOptionSetNumber) set_number;
  decltype(&gmshLoggerStart) logger_start;
  decltype(&gmshLoggerStop) logger_stop;
  decltype(&gmshLoggerGetLastError) last_error;
  decltype(&gmshFree) free;
  decltype(&gmshOpen) open;
  decltype(&gmshModelGetEntities) entities;
  decltype(&gmshModelGetPhysicalGroups) physical_groups;
  decltype(&gmshModelGetPhysicalName) physical_name;
  decltype(&gmshModelGetPhysicalGroupsForEntity) groups_of_entity;
  decltype(&gmshModelMeshGetElementTypes) element_types;
  decltype(&gmshModelMeshGetElementProperties) element_properties;
  decltype(&gmshModelMeshGetIntegrationPoints) integration_points;
  decltype(&gmshModelMeshGetJacobians) jacobians;
  decltype(&gmshModelMeshGetElementsByType) elements;
};

Api load() {
  void* library = dlopen(MPM_GMSH_LIBRARY, RTLD_NOW | RTLD_LOCAL);
  if (!library) throw GmshError(std::string("cannot load Gmsh's library: ") + dlerror());
  Api api{};
  const auto resolve = [&](auto& function, const char* name) {
    function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(dlsym(library, name));
    if (!function) throw GmshError(std::string("Gmsh's library lacks ") + name);
  };
  resolve(api.initialize, "gmshInitialize");
  resolve(api.finalize, "gmshFinalize");
  resolve(api.set_number, "gmshOptionSetNumber");
  resolve(api.logger_start, "gmshLoggerStart");
  resolve(api.logger_stop, "gmshLoggerStop");
  resolve(api.last_error, "gmshLoggerGetLastError");
  resolve(api.free, "gmshFree");
  resolve(api.open, "gmshOpen");
  resolve(api.entities, "gmshModelGetEntities");
  resolve(api.physical_groups, "gmshModelGetPhysicalGroups");
  resolve(api.physical_name, "gmshModelGetPhysicalName");
  resolve(api.groups_of_entity, "gmshModelGetPhysicalGroupsForEntity");
  resolve(api.element_types, "gmshModelMeshGetElementTypes");
  resolve(api.element_properties, "gmshModelMeshGetElementProperties");
  resolve(api.integration_points, "gmshModelMeshGetIntegrationPoints");
  resolve(api.jacobians, "gmshModelMeshGetJacobians");
  resolve(api.elements, "gmshModelMeshGetElementsByType");
  return api;
}

/// The loaded API (loaded on the first call; a failed load is tried again on the next).
const Api& api() {
  static const Api loaded = load();
  return loaded;
}

std::mutex& session_mutex() {
  static std::mutex m;
  return m;
}

/// Throws GmshError with Gmsh's last error when a call failed.
void check(int ierr) {
  if (ierr == 0) return;
  char* error = nullptr;
  int ignored = 0;
  api().last_error(&error, &ignored);
  const std::string what = error && *error ? error : "error " + std::to_string(ierr);
  api().free(error);
  throw GmshError(what);
}

/// A C array the API allocated, copied and freed.
template <class T>
std::vector<T> take(T* data, std::size_t n) {
  std::vector<T> out(data, data + n);
  api().free(data);
  return out;
}

std::string take(char* text) {
  std::string out = text ? text : "";
  api().free(text);
  return out;
}

std::vector<std::pair<int, int>> pairs(const std::vector<int>& flat) {
  std::vector<std::pair<int, int>> out;
  for (std::size_t k = 0; k + 1 < flat.size(); k += 2) out.emplace_back(flat[k], flat[k + 1]);
  return out;
}
/// The (dim, tag) pairs of dimension `dim` that one of the API's listing calls gives.
template <class Listing>
std::vector<std::pair<int, int>> dim_tags(Listing listing, int dim) {
  int* tags = nullptr;
  std::size_t n = 0;
  int ierr = 0;
  listing(&tags, &n, dim, &ierr);
  check(ierr);
  return pairs(take(tags, n));
}
}  // namespace

GmshSession::GmshSession() {
  api();
  session_mutex().lock();
  int ierr = 0;
  api().initialize(0, nullptr, 0, &ierr);
  if (ierr == 0) api().set_number("General.Terminal", 0, &ierr);
  if (ierr == 0) api().logger_start(&ierr);
  if (ierr != 0) {
    session_mutex().unlock();
    throw GmshError("cannot start Gmsh");
  }
}

GmshSession::~GmshSession() {
  int ierr = 0;
  api().logger_stop(&ierr);
  api().finalize(&ierr);
  session_mutex().unlock();
}

void GmshSession::open(const std::string& file) const {
  int ierr = 0;
  api().open(file.c_str(), &ierr);
  check(ierr);
}

std::vector<std::pair<int, int>> GmshSession::entities(int dim) const {
  return dim_tags(api().entities, dim);
}

std::vector<std::pair<int, int>> GmshSession::physical_groups(int dim) const {
  return dim_tags(api().physical_groups, dim);
}

std::string GmshSession::physical_name(int dim, int tag) const {
  char* name = nullptr;
  int ierr = 0;
  api().physical_name(dim, tag, &name, &ierr);
  check(ierr);
  return take(name);
}

std::vector<int> GmshSession::physical_groups_of_entity(int dim, int tag) const {
  int* tags = nullptr;
  std::size_t n = 0;
  int ierr = 0;
  api().groups_of_entity(dim, tag, &tags, &n, &ierr);
  check(ierr);
  return take(tags, n);
}

std::vector<int> GmshSession::element_types(int dim, int tag) const {
  int* types = nullptr;
  std::size_t n = 0;
  int ierr = 0;
  api().element_types(&types, &n, dim, tag, &ierr);
  check(ierr);
  return take(types, n);
}

std::string GmshSession::element_name(int type) const {
  char* name = nullptr;
  int dim = 0, order = 0, nodes = 0, primary = 0, ierr = 0;
  double* local = nullptr;
  std::size_t n = 0;
  api().element_properties(type, &name, &dim, &order, &nodes, &local, &n, &primary, &ierr);
  check(ierr);
  take(local, n);
  return take(name);
}

std::pair<std::vector<double>, std::vector<double>> GmshSession::integration_points(
    int type, const std::string& rule) const {
  double *local = nullptr, *weights = nullptr;
  std::size_t n_local = 0, n_weights = 0;
  int ierr = 0;
  api().integration_points(type, rule.c_str(), &local, &n_local, &weights, &n_weights, &ierr);
  check(ierr);
  return {take(local, n_local), take(weights, n_weights)};
}

std::pair<std::vector<double>, std::vector<double>> GmshSession::jacobians(int type,
                                                                           std::vector<double> local,
                                                                           int tag) const {
  double *jacobians = nullptr, *determinants = nullptr, *x = nullptr;
  std::size_t n_jacobians = 0, n_determinants = 0, n_x = 0;
  int ierr = 0;
  api().jacobians(type, local.data(), local.size(), &jacobians, &n_jacobians, &determinants, &n_determinants,
                  &x, &n_x, tag, 0, 1, &ierr);
  check(ierr);
  take(jacobians, n_jacobians);
  return {take(determinants, n_determinants), take(x, n_x)};
}

std::vector<std::size_t> GmshSession::elements(int type, int tag) const {
  std::size_t *elements = nullptr, *nodes = nullptr;
  std::size_t n_elements = 0, n_nodes = 0;
  int ierr = 0;
  api().elements(type, &elements, &n_elements, &nodes, &n_nodes, tag, 0, 1, &ierr);
  check(ierr);
  take(nodes, n_nodes);
  return take(elements, n_elements);
}

}  // namespace mpm::scene_reading
