#include "granpack/core/contact_store.h"

#include <algorithm>

namespace granpack {

template <int dim> std::ptrdiff_t ContactStore<dim>::find(const ContactKey& key) const {
  auto it = index_.find(key);
  return it == index_.end() ? -1 : static_cast<std::ptrdiff_t>(it->second);
}

template <int dim>
std::size_t ContactStore<dim>::insert(const ContactKey& key, const ContactState<dim>& s) {
  auto [it, fresh] = index_.try_emplace(key, keys_.size());
  if (fresh) {
    keys_.push_back(key);
    states_.push_back(s);
  } else {
    states_[it->second] = s;
  }
  return it->second;
}

template <int dim> void ContactStore<dim>::erase(const ContactKey& key) {
  auto it = index_.find(key);
  if (it == index_.end())
    return;
  std::size_t k = it->second, last = keys_.size() - 1;
  index_.erase(it);
  if (k != last) {
    keys_[k] = keys_[last];
    states_[k] = states_[last];
    index_[keys_[k]] = k;
  }
  keys_.pop_back();
  states_.pop_back();
}

template <int dim>
void ContactStore<dim>::erase_if(
    const std::function<bool(const ContactKey&, const ContactState<dim>&)>& pred) {
  std::size_t out = 0;
  for (std::size_t k = 0; k < keys_.size(); ++k) {
    if (pred(keys_[k], states_[k]))
      continue;
    keys_[out] = keys_[k];
    states_[out] = states_[k];
    ++out;
  }
  keys_.resize(out);
  states_.resize(out);
  index_.clear();
  for (std::size_t k = 0; k < out; ++k)
    index_.emplace(keys_[k], k);
}

template <int dim>
void ContactStore<dim>::permute(const std::vector<std::size_t>& order, std::size_t capacity) {
  std::vector<ContactKey> keys;
  std::vector<ContactState<dim>> states;
  const std::size_t room = std::max(order.size(), capacity);
  keys.reserve(room);
  states.reserve(room);
  index_.reserve(room);
  for (std::size_t k : order) {
    keys.push_back(keys_[k]);
    states.push_back(states_[k]);
  }
  keys_.swap(keys);
  states_.swap(states);
  for (std::size_t k = 0; k < keys_.size(); ++k)
    index_[keys_[k]] = k;
}

template <int dim> void ContactStore<dim>::reserve(std::size_t n) {
  keys_.reserve(n);
  states_.reserve(n);
  index_.reserve(n);
}

template <int dim> void ContactStore<dim>::clear() {
  keys_.clear();
  states_.clear();
  index_.clear();
}

template class ContactStore<2>;
template class ContactStore<3>;

} // namespace granpack
