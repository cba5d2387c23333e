#include "mpm/io/vtk.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>
#include <string_view>
#include <system_error>

#include "mpm/core/errors.hpp"
#include "mpm/io/files.hpp"

namespace mpm::io {

namespace {

/// `text` with the five XML special characters replaced by entities, for attribute values.
std::string xml_escape(std::string_view text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

/// The inverse of xml_escape (the five predefined entities only).
std::string xml_unescape(std::string_view text) {
  static constexpr std::pair<std::string_view, char> entities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    bool replaced = false;
    for (const auto& [entity, c] : entities) {
      if (text.substr(i, entity.size()) == entity) {
        out += c;
        i += entity.size();
        replaced = true;
        break;
      }
    }
    if (!replaced) out += text[i++];
  }
  return out;
}

/// Append `values` to `out` as little-endian bytes, preceded by their byte count as a little-endian UInt64
/// (the block layout of <AppendedData encoding="raw"> with header_type="UInt64").
template <class T>
void append_block(std::string& out, const T* values, std::size_t count) {
  static_assert(sizeof(T) == 8);
  const auto put_le = [&out](std::uint64_t bits) {
    for (int b = 0; b < 8; ++b) out += static_cast<char>((bits >> (8 * b)) & 0xffu);
  };
  put_le(static_cast<std::uint64_t>(count * sizeof(T)));
  if constexpr (std::endian::native == std::endian::little) {
    out.append(reinterpret_cast<const char*>(values), count * sizeof(T));
  } else {
    for (std::size_t i = 0; i < count; ++i) put_le(std::bit_cast<std::uint64_t>(values[i]));
  }
}

/// The attributes type, Name, NumberOfComponents and ComponentName0... of a (P)DataArray tag.
std::string array_attributes(std::string_view type, std::string_view name, int components,
                             const std::vector<std::string>& component_names) {
  std::string text = "type=\"" + std::string(type) + "\"";
  if (!name.empty()) text += " Name=\"" + xml_escape(name) + "\"";
  text += " NumberOfComponents=\"" + std::to_string(components) + "\"";
  for (std::size_t c = 0; c < component_names.size(); ++c)
    text += " ComponentName" + std::to_string(c) + "=\"" + xml_escape(component_names[c]) + "\"";
  return text;
}

/// One <DataArray ... format="appended" offset="..."/> line.
std::string data_array(std::string_view type, std::string_view name, int components, std::size_t offset,
                       const std::vector<std::string>& component_names = {}) {
  return "<DataArray " + array_attributes(type, name, components, component_names) +
         " format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
}

/// The <FieldData> block of the fields' units: a VTK string array `units` of "name: unit" entries, written
/// as VTK's ASCII string arrays are, each string's bytes as numbers, each ended by 0.
std::string units_field_data(const std::vector<PointField>& fields) {
  std::vector<std::string> entries{"Points: m"};
  for (const PointField& f : fields)
    if (!f.unit.empty()) entries.push_back(f.name + ": " + f.unit);
  std::string bytes;
  for (const std::string& e : entries) {
    for (const char c : e) bytes += std::to_string(static_cast<unsigned char>(c)) + " ";
    bytes += "0 ";
  }
  bytes.pop_back();
  return "<FieldData>\n<Array type=\"String\" Name=\"units\" NumberOfTuples=\"" +
         std::to_string(entries.size()) + "\" format=\"ascii\">\n" + bytes + "\n</Array>\n</FieldData>\n";
}

/// `time` with 17 significant digits, enough for any double to read back exactly.
std::string round_trip(double time) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, time, std::chars_format::general, 17);
  return std::string(buffer, result.ptr);
}

/// Set `value` to attribute `name` of the tag text `tag` (between `<` and `>`); false when it is absent.
bool attribute(std::string_view tag, std::string_view name, std::string& value) {
  std::string key(" ");  // built by appends: `" " + std::string` trips a GCC 12 -Wrestrict false positive
  key.append(name).append("=\"");
  const std::size_t start = tag.find(key);
  if (start == std::string_view::npos) return false;
  const std::size_t begin = start + key.size(), end = tag.find('"', begin);
  if (end == std::string_view::npos) return false;
  value = xml_unescape(tag.substr(begin, end - begin));
  return true;
}

}  // namespace

void write_vtp(const std::filesystem::path& file, const std::vector<double>& points,
               const std::vector<PointField>& fields) {
  if (points.size() % 3 != 0)
    throw InputError(file.string() + ": points must hold 3 coordinates per point, got " +
                     std::to_string(points.size()) + " values");
  const std::size_t n = points.size() / 3;
  std::set<std::string> names;
  for (const PointField& f : fields) {
    if (f.name.empty()) throw InputError(file.string() + ": a point field has no name");
    if (!names.insert(f.name).second) throw InputError(file.string() + ": two point fields named " + f.name);
    if (f.integer)
      for (double v : f.values)
        if (!(std::abs(v) < 0x1p53 && std::trunc(v) == v))
          throw InputError(file.string() + ": integer point field " + f.name + " holds " + std::to_string(v));
    if (!f.component_names.empty() && f.component_names.size() != static_cast<std::size_t>(f.components))
      throw InputError(file.string() + ": point field " + f.name + " names " +
                       std::to_string(f.component_names.size()) + " of its " + std::to_string(f.components) +
                       " components");
    if (f.components < 1 || f.values.size() != static_cast<std::size_t>(f.components) * n)
      throw InputError(file.string() + ": point field " + f.name + " has " + std::to_string(f.values.size()) +
                       " values for " + std::to_string(n) + " points of " + std::to_string(f.components) +
                       " components");
  }

  // Vertex cells: cell i is point i; offsets are the end of each cell in the connectivity.
  std::vector<std::int64_t> connectivity(n), offsets(n);
  for (std::size_t i = 0; i < n; ++i) {
    connectivity[i] = static_cast<std::int64_t>(i);
    offsets[i] = static_cast<std::int64_t>(i + 1);
  }

  // Lay out the appended blocks: fields, points, connectivity, offsets; each is an 8-byte count plus data.
  std::string header =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "<PolyData>\n" +
      units_field_data(fields) + "<Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"" +
      std::to_string(n) + "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n<PointData>\n";
  std::string data;
  std::size_t data_bytes = (2 * n + points.size()) * 8 + 8 * (fields.size() + 3);  // blocks with their counts
  for (const PointField& f : fields) data_bytes += f.values.size() * 8;
  data.reserve(data_bytes);  // appends never reallocate: the peak memory is the file's size once more
  for (const PointField& f : fields) {
    header +=
        data_array(f.integer ? "Int64" : "Float64", f.name, f.components, data.size(), f.component_names);
    if (f.integer) {
      const std::vector<std::int64_t> whole(f.values.begin(), f.values.end());
      append_block(data, whole.data(), whole.size());
    } else {
      append_block(data, f.values.data(), f.values.size());
    }
  }
  header += "</PointData>\n<Points>\n" + data_array("Float64", "", 3, data.size());
  append_block(data, points.data(), points.size());
  header += "</Points>\n<Verts>\n" + data_array("Int64", "connectivity", 1, data.size());
  append_block(data, connectivity.data(), n);
  header += data_array("Int64", "offsets", 1, data.size());
  append_block(data, offsets.data(), n);
  header += "</Verts>\n</Piece>\n</PolyData>\n<AppendedData encoding=\"raw\">\n_";

  std::string content = std::move(header);
  content.reserve(content.size() + data.size() + 64);
  content += data;
  data = std::string();
  content += "\n</AppendedData>\n</VTKFile>\n";
  write_file_atomically(file, content);
}

void write_pvtp(const std::filesystem::path& file, const std::vector<PointField>& fields,
                const std::vector<std::string>& pieces) {
  std::string text =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PPolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "<PPolyData GhostLevel=\"0\">\n<PPointData>\n";
  for (const PointField& f : fields)
    text += "<PDataArray " +
            array_attributes(f.integer ? "Int64" : "Float64", f.name, f.components, f.component_names) +
            "/>\n";
  text += "</PPointData>\n<PPoints>\n<PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n</PPoints>\n";
  for (const std::string& piece : pieces) text += "<Piece Source=\"" + xml_escape(piece) + "\"/>\n";
  text += "</PPolyData>\n</VTKFile>\n";
  write_file_atomically(file, text);
}

PvdSeries::PvdSeries(std::filesystem::path pvd_file) : file_(std::move(pvd_file)) {}

void PvdSeries::add(double time, const std::string& dataset) {
  if (!std::isfinite(time))
    throw InputError(file_.string() + ": output time of " + dataset + " is not finite");
  entries_.emplace_back(time, dataset);
  try {
    write();
  } catch (...) {
    entries_.pop_back();
    throw;
  }
}

void PvdSeries::write() const {
  std::string text =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n";
  for (const auto& [time, dataset] : entries_)
    text += "<DataSet timestep=\"" + round_trip(time) + "\" group=\"\" part=\"0\" file=\"" +
            xml_escape(dataset) + "\"/>\n";
  text += "</Collection>\n</VTKFile>\n";
  write_file_atomically(file_, text);
}

PvdSeries PvdSeries::resume(std::filesystem::path pvd_file, double t_max) {
  std::ifstream in(pvd_file, std::ios::binary);
  if (!in) throw InputError("cannot read " + pvd_file.string());
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (text.find("<VTKFile type=\"Collection\"") == std::string::npos)
    throw InputError(pvd_file.string() + " is not a VTK collection (.pvd) file");

  PvdSeries series(std::move(pvd_file));
  bool dropped = false;
  for (std::size_t at = text.find("<DataSet"); at != std::string::npos; at = text.find("<DataSet", at + 1)) {
    const std::size_t close = text.find('>', at);
    if (close == std::string::npos) throw InputError(series.file_.string() + ": unterminated <DataSet> tag");
    const std::string_view tag(text.data() + at, close - at);
    std::string time_text, dataset;
    double time = 0;
    const bool ok = attribute(tag, "timestep", time_text) && attribute(tag, "file", dataset);
    const auto parsed = std::from_chars(time_text.data(), time_text.data() + time_text.size(), time);
    if (!ok || parsed.ec != std::errc() || parsed.ptr != time_text.data() + time_text.size())
      throw InputError(series.file_.string() + ": cannot read the timestep and file of " + std::string(tag) +
                       ">");
    if (time <= t_max)
      series.entries_.emplace_back(time, dataset);
    else
      dropped = true;
  }
  if (dropped) series.write();
  return series;
}

}  // namespace mpm::io
