#include "granpack/analysis/disjoint_sets.h"

#include <algorithm>

namespace granpack {

std::size_t DisjointSets::of(std::int64_t id) {
  const auto [it, added] = index.try_emplace(id, parent.size());
  if (added)
    parent.push_back(it->second);
  return it->second;
}

std::size_t DisjointSets::find(std::size_t x) {
  while (parent[x] != x)
    x = parent[x] = parent[parent[x]];
  return x;
}

bool DisjointSets::unite(std::int64_t id_a, std::int64_t id_b) {
  std::size_t a = find(of(id_a)), b = find(of(id_b));
  if (a == b)
    return false;
  parent[std::max(a, b)] = std::min(a, b);
  return true;
}

std::unordered_map<GlobalId, GlobalId>
smallest_member(std::span<const std::pair<GlobalId, GlobalId>> links) {
  DisjointSets sets;
  for (const auto& [a, b] : links)
    sets.unite(a, b);
  std::unordered_map<std::size_t, GlobalId> smallest; // root -> smallest id
  for (const auto& [id, x] : sets.index) {
    const auto [it, added] = smallest.try_emplace(sets.find(x), id);
    if (!added)
      it->second = std::min(it->second, GlobalId(id));
  }
  std::unordered_map<GlobalId, GlobalId> out;
  out.reserve(sets.index.size());
  for (const auto& [id, x] : sets.index)
    out.emplace(id, smallest.at(sets.find(x)));
  return out;
}

} // namespace granpack
