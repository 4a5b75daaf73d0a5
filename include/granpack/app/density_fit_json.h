#pragma once
// The JSON of [GRC] sec. V's fits (`granpack analyze`'s density section, docs/analysis.md) and
// of their ensemble form: the samples' I(k) pooled and fitted once, as [GRC] fit the I(k)
// averaged over six samples (fig. 23, table VII) rather than averaging per-sample fits.
#include <nlohmann/json.hpp>
#include <vector>

#include "granpack/analysis/density_correlation.h"

namespace granpack {

/// One fit's keys in units of a; the values are null when the fit is undetermined (`reason`
/// says why), and `fractal_regime` is the condition of fractal_regime_failure with the smaller
/// cell side l_cell.
nlohmann::json fractal_fit_json(const FractalFit& f, double a, double l_cell);

/// The `density_pooled` section of ensemble.json from the samples' `density` sections (the
/// analysis files of one configuration stem): K, the pooled I(k) (pooled_scattering, units of
/// a) and the fit of eq. (28) to it over the samples' common window, with `fractal_regime` for
/// the smallest cell. Sections without I(k) are skipped; with none left, K = 0 and no fit.
nlohmann::json pooled_density_json(const std::vector<nlohmann::json>& density_sections);

} // namespace granpack
