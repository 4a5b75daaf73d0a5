// libFuzzer driver of parse_deck (docs/fuzzing.md). The property is check_deck of
// fuzz_inputs.h; a violation aborts, so libFuzzer saves the input as a crash.
// Half of the mutations are libFuzzer's byte-level ones, half the deck-aware ones of the CI
// corpus (real keys, interesting values, duplicated tables, deep nesting).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fuzz_inputs.h"

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t max_size);

namespace {
const std::vector<std::string>& seeds() {
  static const auto s = granpack::fuzz::deck_seeds(GRANPACK_SOURCE_DIR);
  return s;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  granpack::fuzz::abort_if_violated(
      granpack::fuzz::check_deck(std::string(reinterpret_cast<const char*>(data), size)));
  return 0;
}

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t max_size,
                                          unsigned int seed) {
  granpack::fuzz::Rng rng(seed);
  if (rng.chance(0.5))
    return LLVMFuzzerMutate(data, size, max_size);
  std::string text(reinterpret_cast<const char*>(data), size);
  if (rng.chance(0.1))
    text = rng.pick(seeds());
  granpack::fuzz::mutate_deck_once(text, rng, seeds());
  if (text.size() > max_size)
    text.resize(max_size);
  std::memcpy(data, text.data(), text.size());
  return text.size();
}
