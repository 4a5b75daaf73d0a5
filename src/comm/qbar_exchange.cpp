#include "granpack/comm/qbar_exchange.h"

namespace granpack {

QBarTable exchange_qbar(const ParticleStore<3>& p, const std::vector<LocalBondOrder>& q6,
                        const Halo<3>& halo, const Decomposition<3>& d) {
  // Component by component (real and imaginary parts of the 13 q6m): the halo moves doubles.
  constexpr int nm = 13;
  std::vector<std::vector<double>> comp(2 * nm, std::vector<double>(p.size(), 0.0));
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    const QlmVector qb = q6[i].normalized();
    for (int m = 0; m < nm; ++m) {
      comp[2 * m][i] = qb[std::size_t(m)].real();
      comp[2 * m + 1][i] = qb[std::size_t(m)].imag();
    }
  }
  for (auto& c : comp)
    halo.forward_values(c, d);
  QBarTable table(6);
  std::vector<std::complex<double>> q(nm);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!table.find(p.id[i]).empty())
      continue; // periodic images of the same grain
    for (int m = 0; m < nm; ++m)
      q[std::size_t(m)] = {comp[2 * m][i], comp[2 * m + 1][i]};
    table.insert(p.id[i], q);
  }
  return table;
}

} // namespace granpack
