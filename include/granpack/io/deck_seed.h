#pragma once
// `granpack run --seed S` and the samples of an ensemble: one deck, another seed. The deck's
// text is rewritten, not only the parsed struct, so the /deck stored in every file says the
// seed the run used and a re-parse of it (restart, analyze) gives the same deck.
//
// How the seed enters every random choice (docs/deck.md, "Seeds"): [sample] seed drives the
// `random` stage's positions; each stage with random draws (ed_gas and ls_compress Maxwell
// velocities, aggregate velocities, fix_rattlers push directions) has its own seed,
// by default [sample] seed + 1000 + the stage's index. Reseeding to S sets [sample] seed = S
// and shifts every explicit stage seed by S minus the deck's [sample] seed, so each sample
// differs in every draw and `--seed <the deck's own seed>` is the deck unchanged.
#include <cstdint>
#include <string>

namespace granpack {

/// The deck text with [sample] seed = `seed` and every explicit stage seed shifted alike.
/// Throws InputError (naming the file and line) if the deck does not parse, if a seed is not
/// written as `seed = <integer>` on a line of its own, or if a shifted seed leaves 0..2^63-1.
std::string reseeded_deck_text(const std::string& text, const std::string& file,
                               std::uint64_t seed);

} // namespace granpack
