#include "granpack/stages/divalent_pick.h"

#include <algorithm>

#include "granpack/comm/allgather.h"
#include "granpack/comm/backbone.h"
#include "granpack/contact/derived_constants.h"
#include "granpack/contact/pair_geometry.h"

namespace granpack {

namespace {
void put(double (&out)[3], const Vec<3>& v) {
  for (int a = 0; a < 3; ++a)
    out[a] = v[a];
}
} // namespace

std::vector<DivalentCandidate> divalent_candidates(RunContext<3>& ctx, const MdEngine<3>& engine,
                                                   double threshold) {
  const auto& p = ctx.system.particles;
  std::vector<CarryingContact> carrying;
  engine.for_each_contact(
      [&](std::size_t i, std::size_t j, const Vec<3>&, const ContactState<3>& st) {
        if (st.normal_force > threshold)
          carrying.push_back({i, j, st.normal_force});
      });
  const Backbone bb = find_backbone(p, engine.halo(), *ctx.decomposition, carrying,
                                    min_backbone_contacts(3, ctx.contact_law.friction));
  // The divalent ids on every rank: a contact's rank may hold the grain as a ghost, whose
  // backbone count only its owner knows.
  std::vector<GlobalId> mine;
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    if (!bb.rattler[i] && std::lround(bb.counts[i]) == 2)
      mine.push_back(p.id[i]);
  std::vector<GlobalId> divalent = allgather_concat(ctx.world, mine);
  std::sort(divalent.begin(), divalent.end());
  const auto is_divalent = [&](GlobalId id) {
    return std::binary_search(divalent.begin(), divalent.end(), id);
  };

  // Each backbone contact of a divalent grain, seen from the grain, on the contact's rank.
  std::vector<DivalentContactRecord> records;
  engine.for_each_contact(
      [&](std::size_t i, std::size_t j, const Vec<3>& r, const ContactState<3>& st) {
        if (!(st.normal_force > threshold) || bb.rattler[i] || bb.rattler[j])
          return;
        const PairGeometry<3> g =
            make_pair_geometry<3>(p.radius[i], p.radius[j], p.mass[i], p.mass[j], r);
        const double force = (st.normal_force * g.normal + st.tangential_force).norm();
        if (is_divalent(p.id[i])) {
          DivalentContactRecord c{p.id[i], p.id[j], {}, {}, force};
          put(c.r, r);
          put(c.branch, g.branch_i());
          records.push_back(c);
        }
        if (is_divalent(p.id[j])) {
          DivalentContactRecord c{p.id[j], p.id[i], {}, {}, force};
          put(c.r, -r);
          put(c.branch, g.branch_j());
          records.push_back(c);
        }
      });
  return divalent_candidates(allgather_concat(ctx.world, records));
}

std::vector<ContactKey> all_contact_keys(RunContext<3>& ctx) {
  std::vector<ContactKey> mine;
  const auto& store = ctx.system.contacts;
  for (std::size_t k = 0; k < store.size(); ++k)
    mine.push_back(store.key(k));
  std::vector<ContactKey> all = allgather_concat(ctx.world, mine);
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  return all;
}

} // namespace granpack
