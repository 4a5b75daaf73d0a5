#pragma once
// What produced a stored state, beyond the grains: the contact law's parameters in force (the
// deck's [material] as the `set` and `stiffen` stages left it) and the stress target the
// packing was last equilibrated under. A run holds them in its RunContext, the stages change
// them there, and every file the run writes (configurations, checkpoints) stores them in the
// HDF5 group /parameters (docs/hdf5-schema.md): analyses and restarts read them from the file
// instead of replaying the deck.
#include <vector>

#include "granpack/contact/contact_law_params.h"
#include "granpack/io/deck.h"

namespace granpack {

/// The stress a packing was last equilibrated under: the target of the last `compress` stage
/// (or `pressure_steps` level) that ran. `stiffen` and `fix_rattlers` keep it.
struct StressTarget {
  int stage = -1;             ///< deck index of the stage that set it; -1: none yet
  std::vector<double> stress; ///< prescribed Σ_α per axis, Pa (dim entries; empty if none)
  std::vector<bool> fixed;    ///< axes held at constant length (dim entries; empty if none)
  double pressure = 0;        ///< mean Σ_α of the controlled axes, Pa
  bool set() const { return stage >= 0; }
  friend bool operator==(const StressTarget&, const StressTarget&) = default;
};

struct StateParameters {
  ContactLawParams contact_law;
  StressTarget stress_target;
  friend bool operator==(const StateParameters&, const StateParameters&) = default;
};

/// The contact law a deck's [material] describes (its values before any stage ran).
ContactLawParams contact_law_params(const MaterialSpec& m);

/// Files written before /parameters existed only: the parameters rebuilt by replaying the
/// stored deck up to the file's stage - the material changed by the `set` and `stiffen`
/// stages, the stress of the last `compress` stage with every axis stress-controlled (none
/// after a `pressure_steps` stage, whose levels such a file does not record). New files carry
/// the parameters themselves; this replay is kept so that the old ones still read alike.
StateParameters replayed_parameters(const Deck& deck, int stage_index);

} // namespace granpack
