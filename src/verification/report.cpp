#include "mpm/verification/report.hpp"

#include <array>
#include <cmath>
#include <sstream>
#include <string_view>

#include "mpm/core/errors.hpp"

namespace mpm {

namespace {
// The names of the study options, in the order of their enumerators.
constexpr std::array<std::string_view, 2> cfl_speed_names{"particles", "reference"};
constexpr std::array<std::string_view, 2> transfer_names{"flip", "apic"};
constexpr std::array<std::string_view, 2> error_names{"particles", "nodal"};
constexpr std::array<std::string_view, 2> start_names{"halve", "exact"};
constexpr std::array<std::string_view, 2> acceleration_names{"zero", "velocity-difference"};

/// The enumerator named `name`; throws InputError naming `key` and the expected names.
template <class Enum, std::size_t N>
Enum pick(const std::string& name, const std::string& key, const std::array<std::string_view, N>& names) {
  for (std::size_t k = 0; k < N; ++k)
    if (name == names[k]) return static_cast<Enum>(k);
  std::string expected;
  for (std::size_t k = 0; k < N; ++k)
    expected += (k ? (k + 1 == N ? " or " : ", ") : "") + std::string(names[k]);
  throw InputError(key + ": expected " + expected + ", got '" + name + "'");
}
template <class Enum, std::size_t N>
std::string_view name_of(Enum e, const std::array<std::string_view, N>& names) {
  return names[static_cast<std::size_t>(e)];
}
}  // namespace

VerifyCase StudyRequest::resolve() {
  const VerifyCase c = parse_case(case_name);
  options.kernel = parse_kernel(kernel, "--kernel");
  options.transfer = pick<Transfer>(transfer, "--transfer", transfer_names);
  set_integrator(options, integrator, "--integrator");
  options.cfl_speed = pick<CflSpeed>(cfl_speed, "--cfl-speed", cfl_speed_names);
  options.error = pick<ErrorMeasure>(error, "--error", error_names);
  options.start = pick<HalfStepStart>(start, "--start", start_names);
  options.constrained_acceleration = pick<ConstrainedAcceleration>(
      constrained_acceleration, "--constrained-acceleration", acceleration_names);
  validate(options);
  return c;
}

nlohmann::json study_row(VerifyCase c, const VerifyOptions& o, const VerifyResult& r) {
  nlohmann::json j{{"case", to_string(c)},
                   {"dim", dimension(c, o)},
                   {"kernel", to_string(o.kernel)},
                   {"transfer", name_of(o.transfer, transfer_names)},
                   {"integrator", integrator_name(o)},
                   {"cells", o.cells},
                   {"ppc", o.ppc},
                   {"cfl", o.cfl},
                   {"cfl_speed", name_of(o.cfl_speed, cfl_speed_names)},
                   {"error", name_of(o.error, error_names)},
                   {"start", name_of(o.start, start_names)},
                   {"constrained_acceleration", name_of(o.constrained_acceleration, acceleration_names)},
                   {"dt", r.dt},
                   {"amplitude", o.amplitude},
                   {"nu", poisson_ratio(c, o)},
                   {"end_time", r.end_time},
                   {"steps", r.steps},
                   {"linf", r.error.linf},
                   {"l1", r.error.l1()},
                   {"l2", r.error.l2()},
                   {"status", r.ok ? "ok" : "failed"}};
  if (!r.ok) j["failure"] = r.failure;
  return j;
}

std::vector<StudySeries> parse_series(const std::string& text, Transfer transfer) {
  const std::string key = "--series";
  std::vector<StudySeries> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const std::size_t colon = item.find(':'), second = item.find(':', colon + 1);
    if (colon == std::string::npos)
      throw InputError(key + ": expected kernel:integrator pairs such as cpgimp:cd, got '" + item + "'");
    const std::string integrator =
        item.substr(colon + 1, second == std::string::npos ? std::string::npos : second - colon - 1);
    VerifyOptions check;
    set_integrator(check, integrator, key);
    const Transfer t =
        second == std::string::npos ? transfer : pick<Transfer>(item.substr(second + 1), key, transfer_names);
    out.push_back({parse_kernel(item.substr(0, colon), key), integrator, t});
  }
  if (out.empty()) throw InputError(key + ": expected at least one kernel:integrator pair");
  return out;
}

nlohmann::json convergence_rows(VerifyCase which, const VerifyOptions& base,
                                const std::vector<StudySeries>& series, bool vary_cells,
                                const std::vector<double>& values) {
  const auto at = [&](VerifyOptions o, const StudySeries& s, double v) {
    o.kernel = s.kernel;
    o.transfer = s.transfer;
    set_integrator(o, s.integrator, "--series");
    if (vary_cells) {
      if (v != std::floor(v)) throw InputError("--values: cells must be whole numbers");
      o.cells = static_cast<int>(v);
    } else {
      o.cfl = v;
    }
    return o;
  };
  for (const StudySeries& s : series)  // validate every point before running any
    for (const double v : values) validate(at(base, s, v));
  nlohmann::json rows = nlohmann::json::array();
  for (const StudySeries& s : series)
    for (std::size_t k = 0; k < values.size(); ++k) {
      const VerifyOptions o = at(base, s, values[k]);
      const VerifyResult r = verify(which, o);
      nlohmann::json row = study_row(which, o, r);
      if (k > 0) {
        const Real ratio = vary_cells ? values[k] / values[k - 1] : values[k - 1] / values[k];
        row["order"] = std::log(rows.back()["linf"].get<double>() / r.error.linf) / std::log(ratio);
      }
      rows.push_back(row);
    }
  return rows;
}

}  // namespace mpm
