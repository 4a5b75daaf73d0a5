#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "granpack/core/contact_store.h"

using namespace granpack;

namespace {
ContactState<3> state_with(double n) {
  ContactState<3> s;
  s.normal_force = n;
  return s;
}
} // namespace

TEST(ContactStore, PermuteReordersAndKeepsTheKeyIndex) {
  ContactStore<3> store;
  for (GlobalId k = 0; k < 5; ++k)
    store.insert(ContactKey::of(k, k + 10), state_with(double(k)));
  store.permute({4, 2, 0, 1, 3});
  const double expect[] = {4, 2, 0, 1, 3};
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(store.state(k).normal_force, expect[k]);
    EXPECT_EQ(store.find(store.key(k)), static_cast<std::ptrdiff_t>(k));
  }
  EXPECT_EQ(store.find(ContactKey::of(3, 13)), 4);
}

// The memory rule of the force loop (docs/performance.md): the room reserved at a rebuild,
// directly or through permute's capacity, takes every later insert up to it without moving the
// arrays (no growth by doubling, which held up to twice the memory the contacts need).
TEST(ContactStore, ReservedRoomTakesInsertsWithoutMoving) {
  ContactStore<3> store;
  store.reserve(1000);
  store.insert(ContactKey::of(0, 1), state_with(1));
  const ContactState<3>* first = &store.state(0);
  for (GlobalId k = 1; k < 1000; ++k)
    store.insert(ContactKey::of(k, k + 5000), state_with(double(k)));
  EXPECT_EQ(&store.state(0), first);

  std::vector<std::size_t> order(store.size());
  std::iota(order.rbegin(), order.rend(), std::size_t{0});
  store.permute(order, 3000);
  const ContactState<3>* moved = &store.state(0);
  EXPECT_EQ(store.state(0).normal_force, 999.0);
  for (GlobalId k = 1000; k < 3000; ++k)
    store.insert(ContactKey::of(k, k + 5000), state_with(double(k)));
  EXPECT_EQ(&store.state(0), moved);
  EXPECT_EQ(store.size(), 3000u);
  EXPECT_EQ(
      store.state(static_cast<std::size_t>(store.find(ContactKey::of(2999, 7999)))).normal_force,
      2999.0);
}
