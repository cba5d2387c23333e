#include "particle_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "mpm/core/errors.hpp"
#include "mpm/io/hdf5_columns.hpp"

namespace mpm {

namespace {
using Role = ParticleColumn::Role;

/// The comma-separated cells of a line, each trimmed of spaces.
std::vector<std::string> cells_of(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) {
    const std::size_t a = cell.find_first_not_of(" \t"), b = cell.find_last_not_of(" \t");
    out.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
  }
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

/// The cell as a number, or nothing.
std::optional<double> number_in(const std::string& cell) {
  try {
    std::size_t used = 0;
    const double v = std::stod(cell, &used);
    if (used == cell.size()) return v;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

/// The lines of a file, Windows line ends dropped.
struct Lines {
  std::ifstream is;
  int number = 0;
  std::string line;
  explicit Lines(const std::filesystem::path& file) : is(file) {}
  bool next() {
    if (!std::getline(is, line)) return false;
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  }
};

/// The data rows of a particle file as text cells: a CSV file's lines (its header, empty lines and comments
/// skipped), or the rows across an HDF5 file's datasets (io::read_hdf5_columns), each number written with 17
/// significant digits, which read back as the same double. `where` names the row ("FILE:LINE" or "FILE: row
/// N"), `line` is its text.
class Rows {
 public:
  explicit Rows(const std::filesystem::path& file) : file_(file), lines_(file) {
    if (io::is_hdf5_file(file)) hdf5_ = io::read_hdf5_columns(file);
  }
  bool next() {
    if (!hdf5_.names.empty()) return next_hdf5();
    while (lines_.next()) {
      if (lines_.line.empty() || lines_.line[0] == '#') continue;
      cells = cells_of(lines_.line);
      const bool header = !std::all_of(cells.begin(), cells.end(),
                                       [](const std::string& c) { return number_in(c).has_value(); });
      if (header && lines_.number == 1) continue;
      where = file_.string() + ":" + std::to_string(lines_.number);
      line = lines_.line;
      return true;
    }
    return false;
  }
  std::vector<std::string> cells;
  std::string where, line;

 private:
  bool next_hdf5() {
    if (row_ == hdf5_.values[0].size()) return false;
    cells.clear();
    line.clear();
    for (const std::vector<double>& column : hdf5_.values) {
      char text[32];
      std::snprintf(text, sizeof text, "%.17g", column[row_]);
      cells.emplace_back(text);
      line += (line.empty() ? "" : ",") + cells.back();
    }
    where = file_.string() + ": row " + std::to_string(++row_);
    return true;
  }
  std::filesystem::path file_;
  Lines lines_;
  io::NamedColumns hdf5_;
  std::size_t row_ = 0;
};

const char* const axis_names = "xyz";
const char* const stress_names[] = {"sxx", "syy", "szz", "sxy", "sxz", "syz"};  // SymTensor<3>'s order
}  // namespace

bool has_column(const std::vector<ParticleColumn>& columns, Role role) {
  return std::any_of(columns.begin(), columns.end(), [&](const ParticleColumn& c) { return c.role == role; });
}

namespace {
/// The columns `names` give (`at` prefixes the messages).
std::vector<ParticleColumn> named_columns(const std::vector<std::string>& names, const std::string& at,
                                          int dim, const std::vector<Material>& materials) {
  std::vector<std::pair<std::string, ParticleColumn>> known;
  for (int d = 0; d < dim; ++d) {
    known.push_back({std::string(1, axis_names[d]), {Role::position, d}});
    known.push_back({std::string("v") + axis_names[d], {Role::velocity, d}});
  }
  known.push_back({"volume", {Role::volume, 0}});
  known.push_back({"material", {Role::material, 0}});
  for (int k = 0; k < 6; ++k) known.push_back({stress_names[k], {Role::stress, k}});
  known.push_back({"plastic_strain", {Role::plastic_strain, 0}});
  for (const DeclaredColumn& c : declared_columns(materials))
    known.push_back({c.name, {Role::internal, static_cast<int>(c.column)}});
  std::vector<ParticleColumn> out;
  std::vector<std::string> seen;
  for (const std::string& name : names) {
    const auto it = std::find_if(known.begin(), known.end(), [&](const auto& k) { return k.first == name; });
    if (it == known.end()) {
      std::string expected;
      for (const auto& k : known) expected += (expected.empty() ? "" : ", ") + k.first;
      throw InputError(at + "unknown column " + in_quotes(shortened(name)) + " (expected " + expected + ")");
    }
    if (std::find(seen.begin(), seen.end(), name) != seen.end())
      throw InputError(at + "column " + in_quotes(name) + " appears twice");
    seen.push_back(name);
    out.push_back(it->second);
  }
  for (int d = 0; d < dim; ++d)
    if (std::find(seen.begin(), seen.end(), std::string(1, axis_names[d])) == seen.end())
      throw InputError(at + "no column " + in_quotes(std::string(1, axis_names[d])) + " (the position)");
  if (!has_column(out, Role::volume)) throw InputError(at + "no column 'volume'");
  return out;
}
}  // namespace

std::vector<ParticleColumn> particle_file_columns(const std::filesystem::path& file, int dim,
                                                  const std::vector<Material>& materials) {
  if (io::is_hdf5_file(file))
    return named_columns(io::read_hdf5_columns(file).names, file.string() + ": ", dim, materials);
  std::vector<ParticleColumn> positional;
  for (int d = 0; d < dim; ++d) positional.push_back({Role::position, d});
  positional.push_back({Role::volume, 0});
  Lines lines(file);
  if (!lines.next()) return positional;
  const std::vector<std::string> names = cells_of(lines.line);
  if (std::all_of(names.begin(), names.end(), [](const std::string& c) { return number_in(c).has_value(); }))
    return positional;  // no header
  return named_columns(names, file.string() + ":1: ", dim, materials);
}

template <int Dim>
void read_particle_rows(const Scene& sc, const SceneBody& b, const std::string& key, ParticleSet<Dim>& p) {
  const std::vector<ParticleColumn> columns = particle_file_columns(b.file, Dim, material_laws(sc));
  const bool stressed = has_column(columns, Role::stress) || has_column(columns, Role::plastic_strain);
  const bool given_internal = has_column(columns, Role::internal);
  const std::vector<DeclaredColumn> declared = declared_columns(material_laws(sc));
  Rows rows(b.file);
  const bool plain = columns.size() == Dim + 1;  // positions and volumes only
  const auto plain_error = [&](const std::string& where) {
    return InputError(where + "expected " + std::to_string(Dim + 1) +
                      " comma-separated numbers (position then volume), got " +
                      in_quotes(shortened(rows.line)));
  };
  while (rows.next()) {
    const std::vector<std::string>& cells = rows.cells;
    const std::string where = rows.where + ": row of " + key + ": ";
    if (cells.size() != columns.size()) {
      if (plain) throw plain_error(where);
      throw InputError(where + "expected " + std::to_string(columns.size()) +
                       " comma-separated values (one per column of line 1), got " +
                       in_quotes(shortened(rows.line)));
    }
    Vec<Dim> x = Vec<Dim>::Zero(), v = Vec<Dim>::Zero();
    SymTensor<3> sigma;
    Real V = 0, eps_bar = 0;
    InternalState internal = unset_internal_state;
    std::size_t material = b.material;
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const ParticleColumn& c = columns[k];
      const std::optional<double> value = number_in(cells[k]);
      if (c.role == Role::material) {
        const auto named = std::find_if(sc.materials.begin(), sc.materials.end(),
                                        [&](const SceneMaterial& m) { return m.name == cells[k]; });
        if (named != sc.materials.end()) {
          material = static_cast<std::size_t>(named - sc.materials.begin());
        } else if (value && *value >= 0 && *value < static_cast<double>(sc.materials.size()) &&
                   *value == std::floor(*value)) {
          material = static_cast<std::size_t>(*value);
        } else {
          throw InputError(where + "material " + in_quotes(shortened(cells[k])) +
                           ": expected the name of a [[materials]] entry or its index from 0");
        }
        continue;
      }
      if ((!value || !std::isfinite(*value)) && plain) throw plain_error(where);
      if (!value || !std::isfinite(*value))
        throw InputError(where + "expected a finite number in column " + std::to_string(k + 1) + ", got " +
                         in_quotes(shortened(cells[k])));
      switch (c.role) {
        case Role::position:
          x[c.component] = *value;
          break;
        case Role::volume:
          V = *value;
          break;
        case Role::velocity:
          v[c.component] = *value;
          break;
        case Role::stress:
          sigma.c[static_cast<std::size_t>(c.component)] = *value;
          break;
        case Role::plastic_strain:
          eps_bar = *value;
          break;
        case Role::internal:
          internal[static_cast<std::size_t>(c.component)] = *value;
          break;
        case Role::material:
          break;
      }
    }
    if (!(V > 0)) throw InputError(where + "volume must be a positive number");
    const Material& law = sc.materials[material].law;
    if (stressed && (!is_rate_form(law) || std::holds_alternative<NewtonianFluid>(law)))
      throw InputError(where + "material " + in_quotes(sc.materials[material].name) +
                       " takes no initial stress or plastic strain (a rate-form solid does)");
    if (stressed && !(eps_bar >= 0)) throw InputError(where + "plastic_strain must be >= 0");
    for (const DeclaredColumn& c : declared)  // a law's internal variables: its law must declare them
      if (!std::isnan(internal[c.column]) && !c.declared_by[material])
        throw InputError(where + "material " + in_quotes(sc.materials[material].name) + " keeps no " +
                         in_quotes(c.name) + " (a body of several laws gives it in a file of its own)");
    p.add(x, v, sc.materials[material].density * V, V, cube_half_lengths<Dim>(V, sc.h),
          static_cast<std::uint16_t>(material));
    if (stressed || given_internal) {
      p.state.keeps_internal = p.state.keeps_internal || given_internal;
      p.state.resize_keeping(p.size());  // earlier particles' internal variables unset, where not kept before
      p.state.sigma.back() = sigma;
      p.state.eps_bar.back() = eps_bar;
      if (given_internal) p.state.internal.back() = internal;
    }
  }
}

template void read_particle_rows<1>(const Scene&, const SceneBody&, const std::string&, ParticleSet<1>&);
template void read_particle_rows<2>(const Scene&, const SceneBody&, const std::string&, ParticleSet<2>&);
template void read_particle_rows<3>(const Scene&, const SceneBody&, const std::string&, ParticleSet<3>&);

}  // namespace mpm
