#include "granpack/io/deck_seed.h"

#include <algorithm>
#include <limits>
#include <optional>
#include <regex>
#include <sstream>
#include <toml.hpp>
#include <vector>

#include "granpack/core/error.h"
#include "granpack/io/deck.h"

namespace granpack {

namespace {

constexpr std::uint64_t kMaxSeed =
    static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream is(text);
  for (std::string line; std::getline(is, line);)
    lines.push_back(line);
  return lines;
}

/// The seed of every stage in deck order (none for stages without random draws).
std::vector<std::optional<std::uint64_t>> stage_seeds(const Deck& deck) {
  std::vector<std::optional<std::uint64_t>> seeds;
  for (const auto& st : deck.stages)
    seeds.push_back(std::visit(
        [](const auto& p) -> std::optional<std::uint64_t> {
          if constexpr (requires { p.seed; })
            return p.seed;
          else
            return std::nullopt;
        },
        st.params));
  return seeds;
}

/// Replaces the `seed = ...` line `line` (1-based) of `lines` by `seed = value`.
void replace_seed_line(std::vector<std::string>& lines, std::size_t line, std::uint64_t value,
                       const std::string& file, const std::string& why) {
  static const std::regex seed_line(R"(^(\s*)seed\s*=\s*[0-9_+]+\s*(#.*)?$)");
  std::smatch m;
  if (line == 0 || line > lines.size() || !std::regex_match(lines[line - 1], m, seed_line))
    throw InputError(
        file + ":" + std::to_string(line) +
        ": cannot change the seed for --seed/--samples: write it as `seed = <integer>` "
        "on a line of its own");
  lines[line - 1] = m[1].str() + "seed = " + std::to_string(value) + "  # " + why;
}

} // namespace

std::string reseeded_deck_text(const std::string& text, const std::string& file,
                               std::uint64_t seed) {
  if (seed > kMaxSeed)
    throw InputError(file + ": seed " + std::to_string(seed) + " is out of range (0.." +
                     std::to_string(kMaxSeed) + ")");
  const Deck deck = parse_deck(text, file);
  const std::uint64_t own = deck.sample.seed;
  const std::uint64_t shift = seed - own; // unsigned: wraps, and wraps back below
  std::vector<std::string> lines = split_lines(text);
  std::istringstream is(text);
  const toml::value root = toml::parse(is, file);
  const std::string why = "granpack run --seed " + std::to_string(seed) + " (the deck says " +
                          std::to_string(own) + ")";

  const auto& sample = root.as_table().at("sample");
  // A deck without [sample] seed gets the line right after its [sample] header, which moves
  // every later line (the stage seeds found below) down by one.
  std::size_t inserted_after = 0; // 1-based line of the header; 0: nothing inserted
  if (sample.as_table().count("seed")) {
    replace_seed_line(lines, sample.as_table().at("seed").location().line(), seed, file, why);
  } else {
    static const std::regex header(R"(^\s*\[\s*sample\s*\]\s*(#.*)?$)");
    auto it = std::find_if(lines.begin(), lines.end(),
                           [](const std::string& l) { return std::regex_match(l, header); });
    if (it == lines.end())
      throw InputError(file +
                       ": cannot add the seed for --seed/--samples: no `[sample]` header line");
    inserted_after = static_cast<std::size_t>(it - lines.begin()) + 1;
    lines.insert(it + 1, "seed = " + std::to_string(seed) + "  # " + why);
  }
  const auto& stages = root.as_table().at("stage").as_array();
  for (const auto& st : stages) {
    if (!st.is_table() || !st.as_table().count("seed"))
      continue;
    const auto& v = st.as_table().at("seed");
    const std::uint64_t old = static_cast<std::uint64_t>(v.as_integer());
    const std::uint64_t shifted = old + shift;
    if (shifted > kMaxSeed)
      throw InputError(file + ":" + std::to_string(v.location().line()) + ": stage seed " +
                       std::to_string(old) + " shifted by the sample seed leaves 0.." +
                       std::to_string(kMaxSeed) + "; choose a smaller stage seed");
    std::size_t line = v.location().line();
    if (inserted_after && line > inserted_after)
      ++line;
    replace_seed_line(lines, line, shifted, file, why);
  }
  std::string out;
  for (const auto& l : lines)
    out += l + "\n";

  // The rewritten deck must be the same deck but for its seeds.
  const Deck check = parse_deck(out, file);
  auto want = stage_seeds(deck);
  for (auto& w : want)
    if (w)
      *w += shift;
  if (check.sample.seed != seed || stage_seeds(check) != want)
    throw InputError(file + ": cannot apply --seed " + std::to_string(seed) +
                     " to this deck: write [sample] seed and the stage seeds as `seed = <integer>` "
                     "lines inside their tables");
  return out;
}

} // namespace granpack
