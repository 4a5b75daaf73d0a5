#pragma once
// Contact records keyed by the pair of global ids, with their history.
//
// A contact (or a cohesive "distant" interaction) between grains a and b is stored once, under
// the key (min id, max id); "first" is always the smaller id, so the normal n points from the
// smaller-id grain to the larger-id one. Exactly one rank owns a contact (the comm layer
// decides which); the history moves with it when grains migrate.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

struct ContactKey {
  GlobalId first = -1, second = -1; ///< first < second
  static ContactKey of(GlobalId a, GlobalId b) {
    return a < b ? ContactKey{a, b} : ContactKey{b, a};
  }
  friend bool operator==(const ContactKey&, const ContactKey&) = default;
  friend auto operator<=>(const ContactKey&, const ContactKey&) = default;
};

struct ContactKeyHash {
  std::size_t operator()(const ContactKey& k) const noexcept {
    // splitmix-style mixing of the two ids: cheap and well spread for consecutive ids
    std::uint64_t h = static_cast<std::uint64_t>(k.first) * 0x9E3779B97F4A7C15ULL;
    h ^= static_cast<std::uint64_t>(k.second) + 0x7F4A7C159E3779B9ULL + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

/// Bits of ContactState::flags.
enum ContactFlag : std::uint32_t {
  kSliding = 1u << 0,        ///< tangential force on the Coulomb cone at the last update
  kRollingPlastic = 1u << 1, ///< rolling moment at its threshold ([GRC] eq. 10)
  kDistant = 1u << 2,        ///< cohesive interaction across a gap, no contact ([GRC] eq. 5)
};

/// What a contact remembers from one step to the next.
template <int dim> struct ContactState {
  double normal_force = 0; ///< elastic normal force N^e at the last update (Walton, Coulomb)
  Vec<dim> tangential_force = Vec<dim>::Zero(); ///< elastic T, global frame, follows the pair
  RotVec<dim> rolling = RotVec<dim>::Zero();    ///< elastic relative rolling rotation
  std::uint32_t flags = 0;                      ///< ContactFlag bits
  std::int64_t age = 0;                         ///< time steps since the contact formed
};

/// The contacts one rank owns: dense arrays plus a key -> index map.
template <int dim> class ContactStore {
public:
  std::size_t size() const { return keys_.size(); }
  const ContactKey& key(std::size_t k) const { return keys_[k]; }
  ContactState<dim>& state(std::size_t k) { return states_[k]; }
  const ContactState<dim>& state(std::size_t k) const { return states_[k]; }

  /// Index of the contact with this key, or -1.
  std::ptrdiff_t find(const ContactKey& key) const;
  /// Inserts (or overwrites) a contact; returns its index.
  std::size_t insert(const ContactKey& key, const ContactState<dim>& s);
  /// Removes one contact (swap with last: indices of others may change).
  void erase(const ContactKey& key);
  /// Removes every contact for which pred(key, state) is true.
  void erase_if(const std::function<bool(const ContactKey&, const ContactState<dim>&)>& pred);
  void clear();
  /// Reorders the contacts: new index k holds the contact that was at index order[k]
  /// (`order` is a permutation of 0..size()-1). The force loop lays the histories out in
  /// Verlet-list order, so that the hot loop reads them sequentially.
  /// `capacity`: as reserve(), in the same pass.
  void permute(const std::vector<std::size_t>& order, std::size_t capacity = 0);
  /// Makes room for `n` contacts in all, so that inserts up to n move nothing. The force loop
  /// reserves, at each list rebuild, the largest number the store can reach before the next
  /// one (its contacts plus the listed pairs that have none): grown by doubling instead, the
  /// arrays would hold up to twice what the contacts need, and three times while they move.
  void reserve(std::size_t n);

private:
  std::vector<ContactKey> keys_;
  std::vector<ContactState<dim>> states_;
  std::unordered_map<ContactKey, std::size_t, ContactKeyHash> index_;
};

extern template class ContactStore<2>;
extern template class ContactStore<3>;

} // namespace granpack
