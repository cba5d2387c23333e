#pragma once
/// What a law declares of its scene keys, so that the scene reader reads it without a reader of its own: each
/// key, the member it sets, whether it is required, its default, and what it means (cam_clay.hpp).
#include "mpm/core/types.hpp"

namespace mpm {

/// One number of a law's [[materials]] table (a number or an expression of the [constants]).
template <class Law>
struct Parameter {
  const char* key;
  Real Law::*member;
  bool required;
  Real fallback;     ///< when not given (NaN: "not given", for keys of which one of several is needed)
  const char* what;  ///< what it is, with its unit: the message of a missing key
};

/// A law whose keys are its `parameters()` and whose scene name is its `model`.
template <class Law>
concept DeclaresParameters = requires {
  Law::model;
  Law::parameters();
};

}  // namespace mpm
