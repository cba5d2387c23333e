#include "mpm/scene/expression.hpp"

#include <muParser.h>

#include <cmath>

#include "mpm/core/errors.hpp"
#include "mpm/core/parallel.hpp"

namespace mpm {

struct Expression::Evaluator {
  mu::Parser parser;
  std::vector<double> values;  ///< the variables muParser reads by address
};

namespace {
double power(double a, double b) {
  return std::pow(a, b);
}
}  // namespace

Expression::Expression(const std::string& text, const std::vector<std::string>& variables,
                       const std::map<std::string, double>& constants, const std::string& where)
    : text_(text), variables_(variables), constants_(constants) {
  try {
    owned_.push_back(make_evaluator());
    owned_.back()->parser.Eval();  // muParser parses lazily: force it now so errors surface here
  } catch (const mu::Parser::exception_type& err) {
    std::string names;
    for (const std::string& v : variables) names += (names.empty() ? "" : ", ") + v;
    const std::string reason = err.GetCode() == mu::ecUNASSIGNABLE_TOKEN
                                   ? "unknown name " + in_quotes(err.GetToken())
                                   : shortened(err.GetMsg());
    throw InputError(where + ": cannot evaluate " + in_quotes(text) + ": " + reason +
                     " (variables: " + (names.empty() ? "none" : names) + "; constants: pi" +
                     (constants.empty() ? "" : " and [constants]") + ")");
  }
  per_thread_[0] = owned_.back().get();
}

Expression::~Expression() = default;

std::unique_ptr<Expression::Evaluator> Expression::make_evaluator() const {
  auto e = std::make_unique<Evaluator>();
  e->values.assign(variables_.size(), 0.0);
  e->parser.DefineConst("pi", 3.14159265358979323846);
  for (const auto& [name, value] : constants_) e->parser.DefineConst(name, value);
  for (std::size_t v = 0; v < variables_.size(); ++v) e->parser.DefineVar(variables_[v], &e->values[v]);
  e->parser.DefineFun("pow", power);
  e->parser.SetExpr(text_);
  return e;
}

double Expression::operator()(std::span<const double> values) const {
  const auto k = static_cast<std::size_t>(thread_index());
  Evaluator* e = per_thread_.at(k).load(std::memory_order_acquire);
  if (!e) {  // first evaluation on this thread: give it its own parser
    const std::lock_guard<std::mutex> lock(creating_);
    owned_.push_back(make_evaluator());
    e = owned_.back().get();
    per_thread_[k].store(e, std::memory_order_release);
  }
  std::copy(values.begin(), values.end(), e->values.begin());
  return e->parser.Eval();
}

}  // namespace mpm
