// `mpm run SCENE` with a malformed scene or bad options: one line on stderr naming the file, the line, the
// key and what was expected; exit status 2; nothing written (the --out folder is not created).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "mpm/scene/scene.hpp"

namespace {

namespace fs = std::filesystem;

/// A valid scene (one step); every case breaks one thing in it. The line numbers of the cases refer to it.
const std::string base_scene = R"(# valid base scene: every case below breaks one thing
[simulation]
dimension = 2
end_time = 0.01
integrator = "musl"
kernel = "linear"
cfl = 0.4

[grid]
lo = [0.0, 0.0]
hi = [1.0, 1.0]
cells = [10, 10]

[[materials]]
name = "elastic"
E = 1000.0
nu = 0.3
density = 1000.0

[[bodies]]
name = "block"
shape = "box"
lo = [0.2, 0.2]
hi = [0.4, 0.4]
velocity = [0.1, "0.1 * x"]

[[bodies]]
name = "disk"
shape = "disk"
center = [0.7, 0.7]
radius = 0.1
ppc = 2
material = "elastic"
)";  // 33 lines: text appended by a case starts on line 34

/// The base scene up to (not including) `marker`.
std::string base_before(const std::string& marker) {
  return base_scene.substr(0, base_scene.find(marker));
}

/// Edits that turn the second body (the disk) into a particle file body reading particles.csv (file on line
/// 30).
const std::vector<std::pair<std::string, std::string>> disk_to_file{
    {"shape = \"disk\"", "shape = \"file\"\nfile = \"particles.csv\""},
    {"center = [0.7, 0.7]\n", ""},
    {"radius = 0.1\n", ""}};

/// Edits that turn the second body (the disk) into a polygon with the vertices `vertices` (on line 30).
std::vector<std::pair<std::string, std::string>> disk_to_polygon(const std::string& vertices) {
  return {{"shape = \"disk\"", "shape = \"polygon\"\nvertices = " + vertices},
          {"center = [0.7, 0.7]\n", ""},
          {"radius = 0.1\n", ""}};
}

/// The keys of a modified Cam-Clay material but its preconsolidation pressure, in place of the base scene's E
/// and nu.
const std::string cam_clay =
    "model = \"modified-cam-clay\"\nM = 1.2\ncompression_index = 0.1\nswelling_index = 0.02\nnu = 0.3";

struct BadScene {
  std::string name;
  /// Applied in order to the base scene: replace the first occurrence of `first` by `second`; an empty
  /// `first` appends `second` at the end (from line 34).
  std::vector<std::pair<std::string, std::string>> edits;
  std::string key;  ///< the key path the message must name ("" where none applies: TOML syntax)
  std::vector<std::string> expected;  ///< fragments the message must contain
  int line = 0;           ///< > 0: the message gives "scene.toml:LINE: key"; 0: it gives no line of the scene
  std::string args = "";  ///< extra arguments; {scene} and {dir} are replaced by the paths
  std::string csv = "";   ///< written as particles.csv next to the scene when not empty
  std::string names = "{scene}";   ///< the file the message must name ("" where none applies)
  std::string scene = base_scene;  ///< the text the edits apply to
};

std::ostream& operator<<(std::ostream& os, const BadScene& c) {
  return os << c.name;
}

struct Outcome {
  int status;
  std::string out, err;
};

std::string slurp(const fs::path& f) {
  std::ifstream is(f);
  std::stringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

Outcome run_mpm(const std::string& args, const fs::path& dir) {
  const std::string cmd = std::string(MPM_BINARY) + " " + args + " >" + (dir / "stdout").string() + " 2>" +
                          (dir / "stderr").string();
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(dir / "stdout"), slurp(dir / "stderr")};
}

std::string substitute(std::string s, const fs::path& scene, const fs::path& dir) {
  for (const auto& [from, to] : {std::pair{std::string("{scene}"), scene.string()}, {"{dir}", dir.string()}})
    for (std::size_t at; (at = s.find(from)) != std::string::npos;) s.replace(at, from.size(), to);
  return s;
}

/// A fresh folder for one case, removed afterwards.
struct CaseDir {
  fs::path path;
  explicit CaseDir(const std::string& name)
      : path(fs::temp_directory_path() / ("mpm_scene_errors_" + std::to_string(::getpid()) + "_" + name)) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~CaseDir() { fs::remove_all(path); }
  CaseDir(const CaseDir&) = delete;
  CaseDir& operator=(const CaseDir&) = delete;
};

class SceneError : public ::testing::TestWithParam<BadScene> {};

TEST_P(SceneError, OneLineNamingFileLineAndKeyAndExitStatus2) {
  const BadScene& c = GetParam();
  const CaseDir dir(c.name);
  std::string text = c.scene;
  for (const auto& [from, to] : c.edits) {
    if (from.empty()) {
      text += to;
      continue;
    }
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << "the case edits text the scene does not have: " << from;
    text.replace(at, from.size(), to);
  }
  const fs::path scene = dir.path / "scene.toml", out = dir.path / "out";
  std::ofstream(scene) << text;
  if (!c.csv.empty()) std::ofstream(dir.path / "particles.csv") << c.csv;

  const Outcome o =
      run_mpm("run " + scene.string() + " --out " + out.string() + " " + substitute(c.args, scene, dir.path),
              dir.path);
  const std::string& err = o.err;
  EXPECT_EQ(o.status, 2) << "stderr: " << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << "stderr: " << err;
  EXPECT_TRUE(!err.empty() && err.back() == '\n') << "stderr: " << err;
  EXPECT_TRUE(o.out.empty()) << "stdout: " << o.out;
  EXPECT_FALSE(fs::exists(out)) << "bad input must not create the output folder";
  const std::string file = substitute(c.names, scene, dir.path);
  if (!file.empty()) {
    EXPECT_NE(err.find(file), std::string::npos) << "names no file " << file << ": " << err;
  }
  if (!c.key.empty()) {
    EXPECT_NE(err.find(c.key), std::string::npos) << "names no key " << c.key << ": " << err;
  }
  for (const std::string& fragment : c.expected)
    EXPECT_NE(err.find(fragment), std::string::npos) << "missing '" << fragment << "' in: " << err;
  const std::string at_line = scene.string() + ":";
  if (c.line > 0) {
    EXPECT_NE(err.find(at_line + std::to_string(c.line) + ": " + c.key), std::string::npos)
        << "expected line " << c.line << " and key " << c.key << " in: " << err;
  } else {
    for (std::size_t at = err.find(at_line); at != std::string::npos; at = err.find(at_line, at + 1)) {
      const std::size_t next = at + at_line.size();
      EXPECT_FALSE(next < err.size() && std::isdigit(static_cast<unsigned char>(err[next])))
          << "expected no line of the scene in: " << err;
    }
  }
}

/// A dotted key of n segments, "k.k.k...".
std::string dotted_key(int n) {
  std::string key = "k";
  for (int i = 1; i < n; ++i) key += ".k";
  return key;
}

std::string traction_on(const std::string& body, const std::string& face) {
  return "[loads]\n[[loads.traction]]\nbody = \"" + body + "\"\nface = \"" + face +
         "\"\ntraction = [1.0, 0.0]\n";
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, SceneError,
    ::testing::Values(
        // TOML itself
        BadScene{"SyntaxErrorInTableHeader", {{"[grid]", "[grid"}}, "", {"expected ']'"}, 9},
        BadScene{
            "UnterminatedString", {{"\"0.1 * x\"]", "\"0.1 * x]"}}, "", {"Error while parsing string"}, 25},
        BadScene{"KeyDefinedTwice",
                 {{"lo = [0.2, 0.2]", "lo = [0.2, 0.2]\nlo = [0.1, 0.1]"}},
                 "",
                 {"cannot redefine existing array 'lo'"},
                 24},
        // strict keys
        BadScene{"UnknownTopLevelTable",
                 {{"", "[outputs]\nevery = 0.1\n"}},
                 "outputs",
                 {"unknown table (expected one of simulation, output,"},
                 34},
        BadScene{"UnknownSimulationKey",
                 {{"end_time = 0.01", "end_tme = 0.01"}},
                 "simulation.end_tme",
                 {"unknown key (expected one of dimension, end_time,"},
                 4},
        BadScene{"UnknownBodyKey",
                 {{"ppc = 2", "ppc = 2\ncolour = \"red\""}},
                 "bodies[1].colour",
                 {"unknown key (expected one of name, shape,"},
                 33},
        BadScene{"UnknownFaceName",
                 {{"", "[grid.faces]\ntop = \"fixed\"\n"}},
                 "grid.faces.top",
                 {"unknown key (expected one of x-min, x-max, y-min, y-max)"},
                 35},
        BadScene{"UnknownFaceKind",
                 {{"", "[grid.faces]\ny-min = \"stuck\"\n"}},
                 "grid.faces.y-min",
                 {"expected one of free, fixed, symmetry, periodic, outflow, got 'stuck'"},
                 35},
        BadScene{"UnpairedPeriodicFace",
                 {{"", "[grid.faces]\nx-min = \"periodic\"\n"}},
                 "grid.faces.x-max",
                 {"expected \"periodic\", as the opposite face x-min is (periodic faces come in pairs)"},
                 34},
        BadScene{"FaceVelocityComponents",
                 {{"", "[grid.faces]\ny-min = { velocity = [0.0] }\n"}},
                 "grid.faces.y-min.velocity",
                 {"expected an array of 2 numbers or expression strings of t", "got an array of 1"},
                 35},
        // [simulation]
        BadScene{"Dimension4",
                 {{"dimension = 2", "dimension = 4"}},
                 "simulation.dimension",
                 {"expected 1, 2 or 3"},
                 3},
        BadScene{"EndTimeZero",
                 {{"end_time = 0.01", "end_time = 0.0"}},
                 "simulation.end_time",
                 {"expected a positive time"},
                 4},
        BadScene{"EndTimeInfinite",
                 {{"end_time = 0.01", "end_time = inf"}},
                 "simulation.end_time",
                 {"expected a finite number"},
                 4},
        BadScene{"EndTimeMissing",
                 {{"end_time = 0.01\n", ""}},
                 "simulation.end_time",
                 {"missing (a number is required)"},
                 2},
        BadScene{"EndTimeString",
                 {{"end_time = 0.01", "end_time = \"soon\""}},
                 "simulation.end_time",
                 {"expected a number, got 'soon'"},
                 4},
        BadScene{"DtAndCfl",
                 {{"cfl = 0.4", "cfl = 0.4\ndt = 0.001"}},
                 "simulation.dt",
                 {"give exactly one of dt [s] and cfl"},
                 8},
        BadScene{"NeitherDtNorCfl",
                 {{"cfl = 0.4\n", ""}},
                 "simulation.cfl",
                 {"give exactly one of dt [s] and cfl"},
                 2},
        BadScene{"CflAboveOne",
                 {{"cfl = 0.4", "cfl = 1.5"}},
                 "simulation.cfl",
                 {"expected a number in (0, 1]"},
                 7},
        BadScene{"CflZero", {{"cfl = 0.4", "cfl = 0"}}, "simulation.cfl", {"expected a number in (0, 1]"}, 7},
        BadScene{"UnknownIntegrator",
                 {{"\"musl\"", "\"rk4\""}},
                 "simulation.integrator",
                 {"expected one of usf, usl, cd, musl, implicit, got 'rk4'"},
                 5},
        BadScene{"UnknownKernel",
                 {{"\"linear\"", "\"cubic\""}},
                 "simulation.kernel",
                 {"expected one of linear, ugimp, cpgimp, bspline2, bspline3, bspline2-clamped, "
                  "bspline3-clamped, cpdi, "
                  "ugimp-wide, cpgimp-wide, cpdi2, got 'cubic'"},
                 6},
        BadScene{"ClampedCubicSplineOnTwoCells",
                 {{"\"linear\"", "\"bspline3-clamped\""}, {"cells = [10, 10]", "cells = [2, 2]"}},
                 "grid.cells",
                 {"kernel = \"bspline3-clamped\" needs at least 3 cells along every axis that is not "
                  "periodic, got 2 on "
                  "axis 0"},
                 12},
        BadScene{
            "KernelIsANumber", {{"\"linear\"", "3"}}, "simulation.kernel", {"expected a string, got 3"}, 6},
        BadScene{"UnknownTransfer",
                 {{"kernel = \"linear\"", "kernel = \"linear\"\ntransfer = \"mls\""}},
                 "simulation.transfer",
                 {"expected one of flip, apic, got 'mls'"},
                 7},
        BadScene{"FlipFractionWithApic",
                 {{"kernel = \"linear\"", "kernel = \"linear\"\ntransfer = \"apic\"\nflip_fraction = 0.5"}},
                 "simulation.flip_fraction",
                 {"applies to transfer = \"flip\" only"},
                 8},
        BadScene{"ConsistentMassWithApic",
                 {{"kernel = \"linear\"", "kernel = \"linear\"\ntransfer = \"apic\""},
                  {"", "[implicit]\nformulation = \"velocity\"\nmass = \"consistent\"\n"}},
                 "implicit.mass",
                 {"APIC (simulation.transfer = \"apic\") runs with the lumped mass"},
                 37},
        BadScene{
            "MomentumPositionsWithCpdi2",
            {{"kernel = \"linear\"", "kernel = \"cpdi2\""}, {"", "[implicit]\npositions = \"momentum\"\n"}},
            "implicit.positions",
            {"kernel = \"cpdi2\" moves them with \"projected-velocity\""},
            35},
        BadScene{"GimpLengthWithCpgimp",
                 {{"kernel = \"linear\"", "kernel = \"cpgimp\"\ngimp_length = 0.05"}},
                 "simulation.gimp_length",
                 {"applies to kernel = \"ugimp\" only"},
                 7},
        // [grid]
        BadScene{
            "GridHiBelowLo", {{"hi = [1.0, 1.0]", "hi = [1.0, 0.0]"}}, "grid.hi", {"expected hi > lo"}, 11},
        BadScene{"CellsZero",
                 {{"cells = [10, 10]", "cells = [0, 10]"}},
                 "grid.cells",
                 {"expected an array of 2 positive integers, got 0 in it"},
                 12},
        BadScene{"CellsNotSquare",
                 {{"cells = [10, 10]", "cells = [10, 20]"}},
                 "grid.cells",
                 {"cells must be square"},
                 12},
        BadScene{"GridLoThreeComponents",
                 {{"lo = [0.0, 0.0]", "lo = [0.0, 0.0, 0.0]"}},
                 "grid.lo",
                 {"expected an array of 2 numbers, got an array of 3"},
                 10},
        // [[materials]]
        BadScene{"DensityNegative",
                 {{"density = 1000.0", "density = -1.0"}},
                 "materials[0].density",
                 {"expected a positive density"},
                 18},
        BadScene{"YoungZero",
                 {{"E = 1000.0", "E = 0.0"}},
                 "materials[0].E",
                 {"expected a positive Young's modulus"},
                 16},
        BadScene{"PoissonHalf",
                 {{"nu = 0.3", "nu = 0.5"}},
                 "materials[0].nu",
                 {"expected a Poisson ratio in (-1, 0.5)"},
                 17},
        BadScene{"PoissonMinusOne",
                 {{"nu = 0.3", "nu = -1"}},
                 "materials[0].nu",
                 {"expected a Poisson ratio in (-1, 0.5)"},
                 17},
        BadScene{"YoungAndLame",
                 {{"nu = 0.3", "nu = 0.3\nlambda = 500.0\nmu = 400.0"}},
                 "materials[0].lambda",
                 {"give either E and nu, or lambda and mu"},
                 18},
        BadScene{"FrictionAngleNinetyFive",
                 {{"nu = 0.3", "nu = 0.3\nmodel = \"mohr-coulomb\"\ncohesion = 1.0\nfriction_angle = 95.0"}},
                 "materials[0].friction_angle",
                 {"expected an angle in [0, 90) degrees, got 95 degrees"},
                 20},
        BadScene{"DilatancyAboveFriction",
                 {{"nu = 0.3",
                   "nu = 0.3\nmodel = \"drucker-prager\"\nfriction_angle = 20.0\ndilatancy_angle = 25.0"}},
                 "materials[0].dilatancy_angle",
                 {"(at most the friction angle), got 25 degrees"},
                 20},
        BadScene{"CohesionOfAnElasticMaterial",
                 {{"nu = 0.3", "nu = 0.3\ncohesion = 1.0"}},
                 "materials[0].cohesion",
                 {"applies to model = \"drucker-prager\" or \"mohr-coulomb\" only"},
                 18},
        BadScene{"ConeMatchOfMohrCoulomb",
                 {{"nu = 0.3", "nu = 0.3\nmodel = \"mohr-coulomb\"\ncohesion = 1.0\nmatch = \"outer\""}},
                 "materials[0].match",
                 {"applies to model = \"drucker-prager\" only"},
                 20},
        BadScene{"YoungModulusOfCamClay",
                 {{"nu = 0.3", "nu = 0.3\nmodel = \"modified-cam-clay\""}},
                 "materials[0].E",
                 {"does not apply to model = \"modified-cam-clay\""},
                 16},
        BadScene{"CamClayKeyOfAnElasticMaterial",
                 {{"nu = 0.3", "nu = 0.3\nM = 1.2"}},
                 "materials[0].M",
                 {"applies to model = \"modified-cam-clay\" only"},
                 18},
        BadScene{"CamClayWithoutPreconsolidation",
                 {{"E = 1000.0\nnu = 0.3", cam_clay}},
                 "materials[0].preconsolidation_pressure",
                 {"missing: the initial preconsolidation pressure"},
                 14},
        BadScene{"CamClaySwellingSteeperThanCompression",
                 {{"E = 1000.0\nnu = 0.3", cam_clay + "\npreconsolidation_pressure = 1e4"},
                  {"swelling_index = 0.02", "swelling_index = 0.2"}},
                 "materials[0].compression_index",
                 {"the normal compression line must be steeper"},
                 18},
        BadScene{"CamClayBodyWithoutConfinement",
                 {{"E = 1000.0\nnu = 0.3", cam_clay + "\npreconsolidation_pressure = 1e4"}},
                 "materials[0]",
                 {"starts at mean effective stress p' = 0 Pa", "k0 under gravity"},
                 0},
        // Names appear in other keys' messages and in history.csv's columns: a 10,000-character one filled
        // them.
        BadScene{"BodyNameTooLong",
                 {{"name = \"block\"", "name = \"" + std::string(100, 'b') + "\""}},
                 "bodies[0].name",
                 {"expected a name of at most 64 characters, got 'bbbbbbbbbb", "bbb...'"},
                 21},
        BadScene{
            "YoungModulusOverflowsTheWaveSpeed",
            {{"E = 1000.0", "E = 1.7e308"}},
            "materials[0].E",
            {"gives the material a wave speed at rest that is not a finite number (its moduli overflow)"},
            16},
        BadScene{"ConstantNotANumber",
                 {{"", "[constants]\nc = nan\n"}},
                 "constants.c",
                 {"expected a finite number, got nan"},
                 35},
        BadScene{"ConstantInfinite",
                 {{"", "[constants]\nc = -inf\n"}},
                 "constants.c",
                 {"expected a finite number, got -inf"},
                 35},
        BadScene{"ParticleFileIsAFolder",
                 {{"shape = \"disk\"", "shape = \"file\"\nfile = \".\""}},
                 "bodies[1].file",
                 {"is not a regular file"},
                 30},
        // A name the file system refuses threw std::filesystem's error past the reader (the Python fuzzer's
        // find).
        BadScene{"ParticleFileNameTooLong",
                 {{"shape = \"disk\"", "shape = \"file\"\nfile = \"" + std::string(300, 'x') + "\""}},
                 "bodies[1].file",
                 {"cannot open '", "...' (File name too long)"},
                 30},
        BadScene{"KeysNestedTooDeep",
                 {{"", dotted_key(100) + " = 1\n"}},
                 "",
                 {"a key nested deeper than 64 levels"},
                 34},
        BadScene{"SetPathTooDeep",
                 {},
                 "",
                 {"--set", "a key path deeper than 64 levels"},
                 0,
                 "--set '" + dotted_key(100) + "=1'",
                 "",
                 ""},
        BadScene{"GeostaticNeoHookeanBody",
                 {{"ppc = 2", "ppc = 2\nk0 = 0.5"}},
                 "bodies[1].k0",
                 {"a geostatic stress needs a rate-form solid"},
                 33},
        BadScene{"MaterialUndefined",
                 {{"material = \"elastic\"", "material = \"steel\""}},
                 "bodies[1].material",
                 {"no material named 'steel' (defined: elastic)"},
                 33},
        BadScene{"MaterialDefinedTwice",
                 {{"", "[[materials]]\nname = \"elastic\"\nE = 1.0\nnu = 0.2\ndensity = 1.0\n"}},
                 "materials[1].name",
                 {"material 'elastic' is defined twice"},
                 35},
        BadScene{"NoMaterials",
                 {{"[[materials]]\nname = \"elastic\"\nE = 1000.0\nnu = 0.3\ndensity = 1000.0\n", ""}},
                 "materials",
                 {"missing: at least one [[materials]] table is needed"},
                 0},
        // [[bodies]]
        BadScene{"NoBodies",
                 {},
                 "bodies",
                 {"missing: at least one [[bodies]] table is needed"},
                 0,
                 "",
                 "",
                 "{scene}",
                 base_before("[[bodies]]")},
        BadScene{"BoxOutsideGrid",
                 {{"hi = [0.4, 0.4]", "hi = [0.4, 1.4]"}},
                 "bodies[0].hi",
                 {"the box must lie inside the grid [0, 1] x [0, 1]"},
                 24},
        BadScene{"DiskRadiusZero",
                 {{"radius = 0.1", "radius = 0.0"}},
                 "bodies[1].radius",
                 {"expected a positive radius"},
                 31},
        BadScene{"DiskOutsideGrid",
                 {{"radius = 0.1", "radius = 0.4"}},
                 "bodies[1].radius",
                 {"the disk (center +- radius) must lie inside the grid"},
                 31},
        BadScene{"DiskPastAFaceThatIsNoSymmetryPlane",
                 {{"cells = [10, 10]", "cells = [10, 10]\nfaces = { x-max = \"symmetry\" }"},
                  {"radius = 0.1", "radius = 0.35"}},
                 "bodies[1].radius",
                 {"the disk (center +- radius) must lie inside the grid [0, 1] x [0, 1] (or reach past its "
                  "symmetry faces: x-max)"},
                 32},
        BadScene{"DiskIn3D",
                 {{"dimension = 2", "dimension = 3"},
                  {"lo = [0.0, 0.0]", "lo = [0.0, 0.0, 0.0]"},
                  {"hi = [1.0, 1.0]", "hi = [1.0, 1.0, 1.0]"},
                  {"cells = [10, 10]", "cells = [10, 10, 10]"},
                  {"lo = [0.2, 0.2]", "lo = [0.2, 0.2, 0.2]"},
                  {"hi = [0.4, 0.4]", "hi = [0.4, 0.4, 0.4]"},
                  {"velocity = [0.1, \"0.1 * x\"]", "velocity = [0.1, \"0.1 * x\", 0.0]"}},
                 "bodies[1].shape",
                 {"\"disk\" is for 2-D scenes, \"sphere\" for 3-D"},
                 29},
        BadScene{
            "RingInnerRadiusTooLarge",
            {{"shape = \"disk\"", "shape = \"ring\""}, {"radius = 0.1", "radius = 0.1\ninner_radius = 0.1"}},
            "bodies[1].inner_radius",
            {"expected 0 <= inner_radius < radius"},
            32},
        BadScene{"PpcZero", {{"ppc = 2", "ppc = 0"}}, "bodies[1].ppc", {"expected at least 1"}, 32},
        BadScene{"PpcOverflowsInt",
                 {{"ppc = 2", "ppc = 4294967297"}},
                 "bodies[1].ppc",
                 {"expected an integer, got 4294967297 (out of range)"},
                 32},
        // expressions
        BadScene{"VelocitySyntaxError",
                 {{"\"0.1 * x\"", "\"0.1 * (x\""}},
                 "bodies[0].velocity[1]",
                 {"cannot evaluate '0.1 * (x'"},
                 25},
        BadScene{"VelocityUnknownVariable",
                 {{"\"0.1 * x\"", "\"0.1 * q\""}},
                 "bodies[0].velocity[1]",
                 {"cannot evaluate '0.1 * q'", "unknown name 'q'", "variables: x, y;"},
                 25},
        BadScene{"VelocityUsesTime",
                 {{"\"0.1 * x\"", "\"0.1 * t\""}},
                 "bodies[0].velocity[1]",
                 {"cannot evaluate '0.1 * t'", "unknown name 't'", "variables: x, y;"},
                 25},
        BadScene{"UndefinedConstant",
                 {{"\"0.1 * x\"", "\"v0 * x\""}},
                 "bodies[0].velocity[1]",
                 {"cannot evaluate 'v0 * x'", "unknown name 'v0'", "constants: pi)"},
                 25},
        BadScene{"ConstantWithReservedName",
                 {{"", "[constants]\nt = 1.0\n"}},
                 "constants.t",
                 {"'t' is reserved for a variable, pi or a function"},
                 35},
        BadScene{"ConstantNamedLikeAFunction",
                 {{"", "[constants]\nsin = 2.0\n"}},
                 "constants.sin",
                 {"'sin' is reserved for a variable, pi or a function"},
                 35},
        BadScene{"ConstantWithAnInvalidName",
                 {{"", "[constants]\na-b = 2.0\n"}},
                 "constants.a-b",
                 {"expected a name of letters, digits and '_' that starts with a letter"},
                 35},
        // [loads]
        BadScene{"TractionOnAParticleFileOffALattice",
                 {disk_to_file[0], disk_to_file[1], disk_to_file[2], {"", traction_on("disk", "x-max")}},
                 "bodies[1].file",
                 {"a surface load needs the file's particles on a lattice",
                  "its particle 2 at (0.755, 0.7) with volume 0.0001 is not"},
                 0,
                 "",
                 "0.7,0.7,0.0001\n0.755,0.7,0.0001\n"},
        BadScene{"TractionOnAParticleFileInAxisymmetry",
                 {disk_to_file[0],
                  disk_to_file[1],
                  disk_to_file[2],
                  {"dimension = 2", "dimension = 2\ngeometry = \"axisymmetric\""},
                  {"density = 1000.0", "density = 1000.0\nmodel = \"hypoelastic\""},
                  {"", traction_on("disk", "x-max")}},
                 "loads.traction[0].body",
                 {"surface loads on a particle file's body are for plane and 3-D scenes"},
                 37,
                 "",
                 "0.7,0.7,0.0001\n"},
        BadScene{"PressureInPlaneStress",
                 {{"dimension = 2", "dimension = 2\ngeometry = \"plane-stress\""},
                  {"density = 1000.0", "density = 1000.0\nmodel = \"hypoelastic\""},
                  {"", "[loads]\n[[loads.pressure]]\nbody = \"disk\"\npressure = 1.0\n"}},
                 "loads.pressure[0].pressure",
                 {"plane stress does not follow"},
                 39},
        BadScene{"PressureWithoutAValue",
                 {{"", "[loads]\n[[loads.pressure]]\nbody = \"disk\"\n"}},
                 "loads.pressure[0].pressure",
                 {"expected a number or an expression string of t"},
                 35},
        BadScene{"PressureRegionOutsideTheGrid",
                 {{"",
                   "[loads]\n[[loads.pressure]]\nbody = \"disk\"\npressure = 1.0\n"
                   "region = { lo = [0.5, 0.5], hi = [1.5, 1.0] }\n"}},
                 "loads.pressure[0].region.hi",
                 {"the region must lie inside the grid"},
                 38},
        BadScene{"TractionOnUnknownBody",
                 {{"", traction_on("blok", "x-max")}},
                 "loads.traction[0].body",
                 {"no body named 'blok'"},
                 36},
        BadScene{"TractionWithoutBody",
                 {{"", "[loads]\n[[loads.traction]]\nface = \"x-max\"\ntraction = [1.0, 0.0]\n"}},
                 "loads.traction[0].body",
                 {"missing"},
                 35},
        BadScene{"TractionOnUnknownFace",
                 {{"", traction_on("block", "top")}},
                 "loads.traction[0].face",
                 {"expected one of x-min, x-max, y-min, y-max, got 'top'"},
                 37},
        // particle files
        BadScene{"ParticleFileMissing", disk_to_file, "bodies[1].file", {"cannot open", "particles.csv"}, 30},
        BadScene{"ParticleFileBadRow",
                 disk_to_file,
                 "bodies[1].file",
                 {"particles.csv:3: ",
                  "expected 3 comma-separated numbers (position then volume), got '0.7,abc,0.001'"},
                 0,
                 "",
                 "x,y,volume\n0.7,0.7,0.001\n0.7,abc,0.001\n"},
        BadScene{"ParticleFileShortRow",
                 disk_to_file,
                 "bodies[1].file",
                 {"particles.csv:4: ", "expected 3 comma-separated numbers"},
                 0,
                 "",
                 "x,y,volume\n0.7,0.7,0.001\n\n0.7,0.7\n"},
        BadScene{
            "ParticleFileUnknownColumn",
            disk_to_file,
            "bodies[1].file",
            {"particles.csv:1: unknown column 'colour' (expected x, vx, y, vy, volume, material, sxx, syy, "
             "szz, sxy, sxz, syz, plastic_strain)"},
            30,
            "",
            "x,y,volume,colour\n0.7,0.7,0.001,1\n"},
        BadScene{"ParticleFileWithoutVolume",
                 disk_to_file,
                 "bodies[1].file",
                 {"particles.csv:1: no column 'volume'"},
                 30,
                 "",
                 "x,y,vx\n0.7,0.7,0.1\n"},
        BadScene{"ParticleFileMaterialTwice",
                 disk_to_file,
                 "bodies[1].material",
                 {"the particle file gives each particle's material (its column 'material'); drop material"},
                 32,
                 "",
                 "x,y,volume,material\n0.7,0.7,0.001,elastic\n"},
        BadScene{"ParticleFileVelocityTwice",
                 {disk_to_file[0],
                  disk_to_file[1],
                  disk_to_file[2],
                  {"ppc = 2", "ppc = 2\nvelocity = [1.0, 0.0]"}},
                 "bodies[1].velocity",
                 {"the particle file gives the velocities (its columns vx, ...); drop velocity"},
                 32,
                 "",
                 "x,y,volume,vx\n0.7,0.7,0.001,0.5\n"},
        BadScene{"ParticleFileUnknownMaterial",
                 {disk_to_file[0], disk_to_file[1], disk_to_file[2], {"material = \"elastic\"\n", ""}},
                 "bodies[1].file",
                 {"particles.csv:3: row of bodies[1].file in ",
                  "material 'steel': expected the name of a [[materials]] entry or its index from 0"},
                 0,
                 "",
                 "x,y,volume,material\n0.7,0.7,0.001,0\n0.7,0.6,0.001,steel\n"},
        BadScene{"ParticleFileNegativeVolume",
                 disk_to_file,
                 "bodies[1].file",
                 {"particles.csv:2: ", "volume must be a positive number"},
                 0,
                 "",
                 "x,y,volume\n0.7,0.7,-0.001\n"},
        // polygons
        BadScene{"PolygonOfTwoVertices",
                 disk_to_polygon("[[0.6, 0.6], [0.8, 0.6]]"),
                 "bodies[1].vertices",
                 {"expected at least 3 vertices, got 2"},
                 30},
        BadScene{"PolygonVertexNotAPair",
                 disk_to_polygon("[[0.6, 0.6], [0.8], [0.7, 0.8]]"),
                 "bodies[1].vertices",
                 {"vertex 1: expected a pair [x, y] of finite numbers, got an array of 1"},
                 30},
        BadScene{"PolygonCrossingItself",
                 disk_to_polygon("[[0.6, 0.6], [0.8, 0.8], [0.8, 0.6], [0.6, 0.8]]"),
                 "bodies[1].vertices",
                 {"edges 0 and 2 meet", "must not cross or touch itself"},
                 30},
        BadScene{"PolygonRepeatedVertex",
                 disk_to_polygon("[[0.6, 0.6], [0.8, 0.6], [0.8, 0.6], [0.7, 0.8]]"),
                 "bodies[1].vertices",
                 {"vertices 1 and 2 coincide"},
                 30},
        BadScene{"PolygonOutsideTheGrid",
                 disk_to_polygon("[[0.6, 0.6], [1.2, 0.6], [0.8, 0.8]]"),
                 "bodies[1].vertices",
                 {"the polygon must lie inside the grid [0, 1] x [0, 1]"},
                 30},
        BadScene{"PolygonVertexFileBadRow",
                 disk_to_polygon("\"particles.csv\""),
                 "bodies[1].vertices",
                 {"particles.csv:3: expected two finite numbers x, y, got '0.8,abc'"},
                 30,
                 "",
                 "x,y\n0.6,0.6\n0.8,abc\n0.7,0.8\n"},
        BadScene{"PolygonVertexFileMissing",
                 disk_to_polygon("\"outline.csv\""),
                 "bodies[1].vertices",
                 {"cannot open", "outline.csv"},
                 30},
        // command-line options
        BadScene{"SetWithoutEquals",
                 {},
                 "--set",
                 {"expected key.path=value, got 'simulation.end_time'"},
                 0,
                 "--set simulation.end_time",
                 "",
                 ""},
        BadScene{"SetUnknownKey",
                 {},
                 "simulation.end_tme (from --set simulation.end_tme=1)",
                 {"unknown key"},
                 0,
                 "--set simulation.end_tme=1"},
        BadScene{"SetBadValue",
                 {},
                 "simulation.end_time (from --set simulation.end_time=-1)",
                 {"expected a positive time"},
                 0,
                 "--set simulation.end_time=-1"},
        BadScene{"SetIndexPastEnd",
                 {},
                 "--set bodies.5.radius",
                 {"index 5 is past the end of the array"},
                 0,
                 "--set bodies.5.radius=1",
                 "",
                 ""},
        BadScene{"SetExpressionWithUnknownVariable",
                 {},
                 "bodies[0].velocity[0] (from --set bodies.0.velocity=",
                 {"cannot evaluate 'q'"},
                 0,
                 "--set 'bodies.0.velocity=[\"q\", 0]'"},
        BadScene{"RestartMissing",
                 {},
                 "--restart",
                 {"no checkpoint at"},
                 0,
                 "--restart {dir}/none.h5",
                 "",
                 "{dir}/none.h5"},
        BadScene{"RestartNotACheckpoint", {}, "--restart", {"not an HDF5 file"}, 0, "--restart {scene}"},
        BadScene{
            "ThreadsNegative", {}, "--threads", {"expected a non-negative count"}, 0, "--threads -1", "", ""},
        // More than 512 threads were taken as 512 without a word (issue 47, item 10).
        BadScene{"ThreadsTooMany",
                 {},
                 "--threads",
                 {"expected a non-negative count of at most 512, got 100000"},
                 0,
                 "--threads 100000",
                 "",
                 ""},
        BadScene{"SceneThreadsTooMany",
                 {{"cfl = 0.4", "cfl = 0.4\nthreads = 100000"}},
                 "simulation.threads",
                 {"expected 0 (all cores) or a positive count of at most 512"},
                 8},
        BadScene{"CheckpointEveryNegative",
                 {},
                 "--checkpoint-every",
                 {"expected a non-negative step count"},
                 0,
                 "--checkpoint-every -1",
                 "",
                 ""}),
    [](const ::testing::TestParamInfo<BadScene>& param) { return param.param.name; });

/// The base scenes the cases break are valid: each failure above comes from its one change.
TEST(SceneErrorBase, BaseScenesRun) {
  const CaseDir dir("valid");
  const fs::path scene = dir.path / "scene.toml", out = dir.path / "out";
  std::ofstream(scene) << base_scene;
  Outcome o = run_mpm("run " + scene.string() + " --quiet --out " + out.string(), dir.path);
  EXPECT_EQ(o.status, 0) << o.err;
  EXPECT_TRUE(fs::exists(out / "summary.json"));

  std::string text = base_scene;
  for (const auto& [from, to] : disk_to_file) text.replace(text.find(from), from.size(), to);
  std::ofstream(scene) << text;
  std::ofstream(dir.path / "particles.csv") << "x,y,volume\n0.7,0.7,0.001\n\n0.7,0.75,0.001\n";
  o = run_mpm("run " + scene.string() + " --quiet --out " + out.string(), dir.path);
  EXPECT_EQ(o.status, 0) << o.err;
}

/// A number is read whatever its TOML type: an integer beyond 2^53, which toml++ gives no exact double for,
/// rounds to the nearest one (the fuzzer's input fuzz/regressions/fuzz_scene/integer-constant-beyond-2-53
/// stopped the reader).
TEST(SceneErrorBase, AnIntegerBeyondTwoToThe53IsReadAsTheNearestDouble) {
  const CaseDir dir("big-integer");
  const fs::path scene = dir.path / "scene.toml";
  std::ofstream(scene) << "[constants]\nbig = 38461534846153846\n" << base_scene;
  const mpm::Scene sc = mpm::read_scene(scene);
  EXPECT_EQ(sc.constants.at("big"), 38461534846153846.0);
}

}  // namespace
