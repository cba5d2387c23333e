// The particle writers read back by VTK itself: a .vtp written by mpm::io::write_vtp is opened with
// vtkXMLPolyDataReader (Debian's python3-vtk9) and every coordinate and field value must come back bit for
// bit; the .pvd written by PvdSeries is parsed with Python's xml.etree and must list the times (bit for bit)
// and files in order. PvdSeries::resume must keep exactly the entries with time <= t_max.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/io/vtk.hpp"

namespace {

namespace fs = std::filesystem;
using mpm::io::PointField;
using mpm::io::PvdSeries;

// Prints what VTK's reader sees, one record per line:
//   points N / verts N / array LABEL TYPE COMPONENTS COUNT v0 v1 ... (values as %.17g) / dataset TIME FILE
constexpr const char* kReaderScript = R"py(import sys
try:
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
except ImportError as e:
    print("NO_VTK", e)
    sys.exit(5)
import xml.etree.ElementTree as ET

reader = vtkXMLPolyDataReader()
reader.SetFileName(sys.argv[1])
reader.Update()
poly = reader.GetOutput()
print("points", poly.GetNumberOfPoints())
print("verts", poly.GetNumberOfVerts())


def dump(label, a):
    n, k = a.GetNumberOfTuples(), a.GetNumberOfComponents()
    values = ["%.17g" % a.GetComponent(i, c) for i in range(n) for c in range(k)]
    print("array", label, a.GetDataTypeAsString(), k, len(values), *values)


dump("coordinates", poly.GetPoints().GetData())
data = poly.GetPointData()
for i in range(data.GetNumberOfArrays()):
    dump(data.GetArrayName(i), data.GetArray(i))
for ds in ET.parse(sys.argv[2]).getroot().iter("DataSet"):
    print("dataset", ds.get("timestep"), ds.get("file"))
)py";

std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

/// One array as read back by VTK.
struct ReadArray {
  std::string type;
  int components = 0;
  std::vector<double> values;
};

/// Everything the reader script printed.
struct ReadBack {
  long points = -1, verts = -1;
  std::map<std::string, ReadArray> arrays;
  std::vector<std::pair<std::string, std::string>> datasets;  // (timestep text, file)
};

class VtkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "mpm-vtk-XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }

  /// Run the reader script on `vtp` and `pvd` with /usr/bin/python3 and parse its output.
  ReadBack read_with_vtk(const fs::path& vtp, const fs::path& pvd) {
    const fs::path script = dir_ / "read.py";
    std::ofstream(script) << kReaderScript;
    const std::string command =
        "/usr/bin/python3 '" + script.string() + "' '" + vtp.string() + "' '" + pvd.string() + "' 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) ADD_FAILURE() << "cannot run " << command;
    std::string output;
    char buffer[4096];
    while (pipe && fgets(buffer, sizeof buffer, pipe)) output += buffer;
    const int status = pipe ? pclose(pipe) : -1;
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code == 5 || code == 127)
      ADD_FAILURE() << "/usr/bin/python3 cannot import VTK; install Debian's python3-vtk9 "
                       "(scripts/install-deps.sh does):\n"
                    << output;
    else if (code != 0)
      ADD_FAILURE() << "the VTK reader script failed (exit " << code << "):\n" << output;

    ReadBack r;
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);) {
      std::istringstream in(line);
      std::string kind;
      in >> kind;
      if (kind == "points") in >> r.points;
      if (kind == "verts") in >> r.verts;
      if (kind == "dataset") {
        std::string time, file;
        in >> time >> file;
        r.datasets.emplace_back(time, file);
      }
      if (kind == "array") {
        std::string label, value;
        ReadArray a;
        std::size_t count = 0;
        in >> label >> a.type >> a.components >> count;
        while (in >> value) a.values.push_back(std::strtod(value.c_str(), nullptr));
        EXPECT_EQ(a.values.size(), count) << line;
        r.arrays[label] = a;
      }
    }
    return r;
  }

  fs::path dir_;
};

/// Expect `read` to equal `written` bit for bit.
void expect_bitwise_equal(const std::vector<double>& written, const ReadArray& read,
                          const std::string& name) {
  ASSERT_EQ(read.values.size(), written.size()) << name;
  for (std::size_t i = 0; i < written.size(); ++i)
    EXPECT_EQ(bits(read.values[i]), bits(written[i]))
        << name << "[" << i << "]: wrote " << written[i] << ", VTK read " << read.values[i];
}

TEST_F(VtkTest, VtkReaderReadsBackEveryValueBitForBit) {
  constexpr int n = 5;
  std::vector<double> points, velocity, stress, J;
  for (int p = 0; p < n; ++p) {
    points.insert(points.end(), {1.0 / 7 + 0.1 * p, -0.3 * p + 1e-10, 0.0});  // 2-D, z padded with 0
    velocity.insert(velocity.end(), {p + 1.0 / 3, -2.5e-7 * (p + 1), std::ldexp(1.0, -p - 40)});
    J.push_back(1 + (p + 1) * std::numeric_limits<double>::epsilon());
  }
  // Extreme and awkward doubles: -0, the smallest subnormal, the largest finite, pi, values one ulp apart.
  stress = {-0.0,
            5e-324,
            1.7976931348623157e308,
            M_PI,
            std::nextafter(1.0, 2.0),
            -1e-300,
            -12345.678901234567,
            1e5 / 3,
            2.0 / 3,
            0.1,
            0.2,
            0.30000000000000004};
  for (int i = 0; i < 3 * 6; ++i) stress.push_back(std::sin(1.0 + i) * std::pow(10.0, i % 7 - 3));

  const fs::path vtp = dir_ / "particles_0001.vtp", pvd = dir_ / "particles.pvd";
  mpm::io::write_vtp(vtp, points, {{"velocity", 3, velocity}, {"stress", 6, stress}, {"J", 1, J}});
  PvdSeries series(pvd);
  EXPECT_TRUE(series.entries().empty());
  series.add(0.0, "particles_0000.vtp");
  series.add(0.1, "particles_0001.vtp");
  EXPECT_FALSE(fs::exists(dir_ / "particles_0001.vtp.tmp"));
  EXPECT_FALSE(fs::exists(dir_ / "particles.pvd.tmp"));

  const ReadBack r = read_with_vtk(vtp, pvd);
  EXPECT_EQ(r.points, n);
  EXPECT_EQ(r.verts, n);
  ASSERT_EQ(r.arrays.size(), 4u);  // coordinates + 3 fields
  const std::map<std::string, std::pair<int, const std::vector<double>*>> expected = {
      {"coordinates", {3, &points}}, {"velocity", {3, &velocity}}, {"stress", {6, &stress}}, {"J", {1, &J}}};
  for (const auto& [name, want] : expected) {
    ASSERT_TRUE(r.arrays.count(name)) << name;
    const ReadArray& a = r.arrays.at(name);
    EXPECT_EQ(a.type, "double") << name;
    EXPECT_EQ(a.components, want.first) << name;
    expect_bitwise_equal(*want.second, a, name);
  }

  ASSERT_EQ(r.datasets.size(), 2u);
  EXPECT_EQ(bits(std::strtod(r.datasets[0].first.c_str(), nullptr)), bits(0.0));
  EXPECT_EQ(bits(std::strtod(r.datasets[1].first.c_str(), nullptr)), bits(0.1));
  EXPECT_EQ(r.datasets[0].second, "particles_0000.vtp");
  EXPECT_EQ(r.datasets[1].second, "particles_0001.vtp");
}

TEST_F(VtkTest, ResumeKeepsEntriesUpToTMaxAndRewritesTheFile) {
  const fs::path pvd = dir_ / "particles.pvd";
  const std::vector<double> times = {0.0, 0.1, 1.0 / 3, 0.7, 1.1};
  {
    PvdSeries series(pvd);
    for (std::size_t i = 0; i < times.size(); ++i) series.add(times[i], "p_" + std::to_string(i) + ".vtp");
  }
  const PvdSeries all = PvdSeries::resume(pvd, 10.0);
  ASSERT_EQ(all.entries().size(), times.size());
  for (std::size_t i = 0; i < times.size(); ++i) {
    EXPECT_EQ(bits(all.entries()[i].first), bits(times[i])) << i;  // 17 digits round-trip
    EXPECT_EQ(all.entries()[i].second, "p_" + std::to_string(i) + ".vtp");
  }

  // t_max equal to a written time keeps it (the time reads back exactly); later ones are dropped.
  PvdSeries resumed = PvdSeries::resume(pvd, 1.0 / 3);
  ASSERT_EQ(resumed.entries().size(), 3u);
  EXPECT_EQ(bits(resumed.entries()[2].first), bits(1.0 / 3));
  EXPECT_EQ(resumed.entries()[2].second, "p_2.vtp");
  EXPECT_EQ(PvdSeries::resume(pvd, 100.0).entries().size(), 3u);  // the file was rewritten without them

  resumed.add(0.5, "restart & more.vtp");  // appends after the kept entries; the name needs XML escaping
  const PvdSeries again = PvdSeries::resume(pvd, 100.0);
  ASSERT_EQ(again.entries().size(), 4u);
  EXPECT_EQ(bits(again.entries()[3].first), bits(0.5));
  EXPECT_EQ(again.entries()[3].second, "restart & more.vtp");
  EXPECT_EQ(PvdSeries::resume(pvd, -1.0).entries().size(), 0u);
}

// Bad fields are input errors; a path that cannot be written is an output failure (exit status 1).
TEST_F(VtkTest, BadInputThrowsInputErrorAndUnwritablePathsOutputError) {
  const std::vector<double> points = {0, 0, 0, 1, 0, 0};
  const fs::path missing = dir_ / "no-such-folder" / "p.vtp";
  try {
    mpm::io::write_vtp(missing, points, {});
    FAIL() << "writing into a missing folder did not throw";
  } catch (const mpm::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_THROW(mpm::io::write_vtp(dir_ / "p.vtp", {0, 0}, {}), mpm::InputError);  // not 3 per point
  EXPECT_THROW(mpm::io::write_vtp(dir_ / "p.vtp", points, {{"v", 3, {1, 2, 3}}}), mpm::InputError);
  EXPECT_THROW(mpm::io::write_vtp(dir_ / "p.vtp", points, {{"J", 1, {1, 2}}, {"J", 1, {1, 2}}}),
               mpm::InputError);
  EXPECT_THROW(mpm::io::write_vtp(dir_ / "p.vtp", points, {{"v", 2, {1, 2, 3, 4}, false, {"x", "y", "z"}}}),
               mpm::InputError);  // three names for two components
  EXPECT_FALSE(fs::exists(dir_ / "p.vtp"));

  PvdSeries series(dir_ / "no-such-folder" / "s.pvd");
  EXPECT_THROW(series.add(0.0, "a.vtp"), mpm::OutputError);
  EXPECT_TRUE(series.entries().empty());  // a failed add leaves the series as it was
  EXPECT_THROW(PvdSeries(dir_ / "s.pvd").add(std::nan(""), "a.vtp"), mpm::InputError);
  EXPECT_THROW(PvdSeries::resume(dir_ / "missing.pvd", 1.0), mpm::InputError);
}

}  // namespace
