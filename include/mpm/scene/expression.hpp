#pragma once
/// Scalar expressions written by users in scene files, parsed once with muParser and evaluated many times.
#include <array>
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

namespace mpm {

/// A scalar expression of named variables, e.g. "A*sin(2*pi*X)*cos(c*pi*t)". Functions: muParser's (sin, cos,
/// tan, exp, log, sqrt, abs, min, max, ...) plus pow(a, b); constants: pi and the scene's named constants.
/// Evaluation is thread-safe: each thread evaluates its own parser.
class Expression {
 public:
  /// Parse `text` over `variables`; throws InputError("<where>: ...") when it does not parse or uses a name
  /// that is neither a variable, a constant nor a function.
  Expression(const std::string& text, const std::vector<std::string>& variables,
             const std::map<std::string, double>& constants, const std::string& where);
  ~Expression();
  Expression(const Expression&) = delete;
  Expression& operator=(const Expression&) = delete;

  /// The value at the given variable values (in the order of `variables`).
  double operator()(std::span<const double> values) const;

 private:
  struct Evaluator;
  std::unique_ptr<Evaluator> make_evaluator() const;

  std::string text_;
  std::vector<std::string> variables_;
  std::map<std::string, double> constants_;
  static constexpr std::size_t max_threads = 512;
  mutable std::array<std::atomic<Evaluator*>, max_threads> per_thread_{};  ///< created on first use
  mutable std::vector<std::unique_ptr<Evaluator>> owned_;
  mutable std::mutex creating_;
};

using ExpressionPtr = std::shared_ptr<const Expression>;

/// The value of a vector of expressions (one per component) at the same variable values.
template <class VecT>
VecT vector_value(const std::vector<ExpressionPtr>& components, std::span<const double> values) {
  VecT out;
  for (std::size_t d = 0; d < components.size(); ++d) out[static_cast<int>(d)] = (*components[d])(values);
  return out;
}

}  // namespace mpm
