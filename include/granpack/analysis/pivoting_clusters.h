#pragma once
// Free pivoting of dangling clusters (3D, rolling resistance): the contact law leaves pivoting
// free (docs/contact-law.md step 8), so a part of the interaction network that hangs from the
// rest by a single contact in touch can spin, as a rigid body, about that contact's normal
// through its contact point. No row of G sees it: inside the part the motion is rigid, at the
// contact the point does not move and the relative rotation is a pure pivoting. A grain with
// one contact is the smallest such part. MPI-free: the rigidity layer gathers the interactions
// and every rank finds the same modes. docs/stiffness.md, "Cohesive and rolling-resistant 3D
// packings".
#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

/// One interaction of the network: a contact in touch or a distant pair.
struct NetworkEdge {
  GlobalId i = 0, j = 0;
  double r[3] = {0, 0, 0};        ///< r_ij, from i's centre to j's (periodic image)
  double branch_i[3] = {0, 0, 0}; ///< from i's centre to the contact point
  std::int32_t distant = 0;       ///< 1: a distant pair (no contact point, never a hinge)
};

/// The pivoting of the part hanging from one contact (the hinge).
struct PivotingCluster {
  GlobalId grain = 0;             ///< the part's grain at the hinge
  GlobalId neighbour = 0;         ///< the grain on the other side of the hinge
  Vec<3> normal = Vec<3>::Zero(); ///< the hinge's normal, from `grain` to `neighbour`
  /// Every grain of the part with its 6 scaled dofs (u = n x (x - p), rho = ell n); unit norm
  /// over the part.
  std::vector<std::pair<GlobalId, Eigen::Matrix<double, 6, 1>>> mode;
};

/// Every contact in touch that is a bridge of the interaction graph (distant pairs included
/// as edges) hangs the smaller of its two sides (by grain count; ties: the side of the larger
/// id) from the rest: one cluster per such contact, sorted by hinge. `edges` in any order.
std::vector<PivotingCluster> pivoting_clusters(const std::vector<NetworkEdge>& edges, double ell);

} // namespace granpack
