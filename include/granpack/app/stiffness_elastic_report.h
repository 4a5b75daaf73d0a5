#pragma once
// The elastic tensor in `granpack stiffness`'s report: the JSON object `elastic_tensor` (keys
// in docs/stiffness.md, "The elastic tensor") and its lines in the printed table.
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "granpack/analysis/elastic_tensor.h"

namespace granpack {

/// c (the condensed tensor) and its affine part c_affine (the strain block before
/// condensation), both with the same pre-stress term: the summary of each, the tensors, and
/// the non-affine part c - c_affine.
template <int dim>
nlohmann::json elastic_tensor_json(const VoigtMatrix<dim>& c, const VoigtMatrix<dim>& affine);

/// Table lines (label, value) for `elastic_tensor` (null: moduli not defined).
std::vector<std::pair<std::string, std::string>> elastic_tensor_lines(const nlohmann::json& e);

} // namespace granpack
