#pragma once
// Coordination and rattlers, [AR] sec. III B: a contact is force-carrying when its normal
// force exceeds a threshold; a grain is a rattler when it has fewer than `min_contacts`
// force-carrying contacts with non-rattlers (dim+1 without friction; 2 with friction, since
// 2- and 3-coordinated grains carry force there - tables V, VI). Removing rattlers can make
// their neighbours rattlers, so the rule is iterated to a fixed point.
//
// The kernels here work on one rank's contacts (local indices i, j of its particle store,
// ghosts included); the distributed iteration (stages/state_metrics) sums counts over ranks
// between calls. MPI-free.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace granpack {

/// One force-carrying contact between local particles i and j (either may be a ghost).
struct CarryingContact {
  std::size_t i = 0, j = 0;
  double normal_force = 0;
};

/// Adds, for every contact between two grains not flagged as rattlers, one to the count of
/// each end. `counts` and `rattler` are indexed by local particle index (owned + ghosts).
void count_backbone_contacts(const std::vector<CarryingContact>& contacts,
                             const std::vector<std::uint8_t>& rattler, std::vector<double>& counts);

/// Flags owned grains [0, n_owned) with counts < min_contacts as rattlers; returns how many
/// grains were newly flagged.
std::size_t flag_rattlers(std::size_t n_owned, const std::vector<double>& counts, int min_contacts,
                          std::vector<std::uint8_t>& rattler);

/// Histogram of the coordination of owned non-rattler grains (index = number of contacts).
std::vector<std::int64_t> coordination_histogram(std::size_t n_owned,
                                                 const std::vector<double>& counts,
                                                 const std::vector<std::uint8_t>& rattler);

/// Sum of N^alpha over the contacts (for the moments Z(alpha) = <N^alpha>/<N>^alpha, eq. 27).
double sum_force_power(const std::vector<CarryingContact>& contacts, double alpha);

} // namespace granpack
