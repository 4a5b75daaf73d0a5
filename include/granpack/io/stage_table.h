#pragma once
// What the parse() of a stage kind (io/stage_params.h) reads: its [[stage]] table, through a
// TableReader whose messages name "stage[i] (kind)", and the parts of the deck that bound it.
#include <string>
#include <toml.hpp>

#include "granpack/io/deck.h"
#include "granpack/io/deck_reader.h"

namespace granpack {

struct StageTable {
  TableReader& reader;          ///< the table's keys; parse_deck refuses the unread ones after
  const toml::value& table;     ///< the raw table (arrays that the reader does not check)
  const SampleSpec& sample;     ///< dimension, n, diameters, the sample's seed
  const MaterialSpec& material; ///< the deck's [material] (cohesion allows P = 0, ...)
  int index = 0;                ///< 0-based position in the deck
  bool after_compress = false;  ///< an earlier stage is a compress (P_0 is known)
};

/// The parameters of the stage kind `kind` (one of stage_kinds()), read by its parse().
StageParams parse_stage_params(const std::string& kind, StageTable& t);

} // namespace granpack
