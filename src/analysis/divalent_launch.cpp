#include "granpack/analysis/divalent_launch.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "granpack/core/error.h"

namespace granpack {

DivalentFrame divalent_frame(const Vec<3>& r_ij, const Vec<3>& r_ik) {
  const Vec<3> n_ij = r_ij.normalized(), n_ik = r_ik.normalized();
  const Vec<3> normal = n_ij.cross(n_ik);
  // Aligned centres: the grain sits on the j-k line, D = 0 and no circle to roll on.
  GRANPACK_CHECK(normal.norm() > 1e-9, "divalent grain: its centre and its two neighbours' "
                                       "centres are aligned (no rolling circle)");
  DivalentFrame fr;
  fr.e = (n_ik - n_ij).normalized();
  fr.t = normal.normalized();
  // [AR] writes f = e x t; with e and t as defined there the centre then lies at -D f (the sign
  // of its angle alpha is left open): t x e puts it at +D f, where fig. 16's trajectories start.
  fr.f = fr.t.cross(fr.e);
  // The centre's offset from the j-k line (through r_ij and r_ik; for equal spheres [AR]'s
  // D = a sqrt(1 - (e.n_ij)^2), with a = |r_ij|). It points along +f.
  const Vec<3> axis = (r_ik - r_ij).normalized();
  const Vec<3> from_line = -(r_ij - r_ij.dot(axis) * axis);
  fr.distance = from_line.norm();
  return fr;
}

double divalent_omega0(double mass, double distance, double contact_force, double ratio) {
  GRANPACK_CHECK(mass > 0 && distance > 0 && contact_force > 0 && ratio > 0,
                 "divalent omega0: mass " << mass << ", D " << distance << ", |F| " << contact_force
                                          << ", ratio " << ratio << " must all be positive");
  return std::sqrt(ratio * contact_force / (mass * distance));
}

DivalentLaunch divalent_launch(const Vec<3>& r_ij, const Vec<3>& r_ik, const Vec<3>& b_ij,
                               const Vec<3>& b_ik, double omega0) {
  DivalentLaunch l;
  l.frame = divalent_frame(r_ij, r_ik);
  l.omega0 = omega0;
  l.velocity = omega0 * l.frame.distance * l.frame.t;
  // Rotation about the contact line: v + Omega x b = 0 at both contact points, i.e.
  // Omega = w c with c along b_ik - b_ij and w c x b_ij = -v. Its sign follows from E1.
  const Vec<3> c = (b_ik - b_ij).normalized();
  const Vec<3> lever = c.cross(b_ij); // Omega x b_ij = w lever must equal -v
  const double w = -l.velocity.dot(lever) / lever.squaredNorm();
  l.angular_velocity = w * c;
  return l;
}

double DivalentCandidate::force() const {
  return std::min(contact[0].force, contact[1].force);
}

std::vector<DivalentCandidate> divalent_candidates(std::vector<DivalentContactRecord> records) {
  std::sort(records.begin(), records.end(), [](const auto& a, const auto& b) {
    return a.grain != b.grain ? a.grain < b.grain : a.neighbour < b.neighbour;
  });
  std::vector<DivalentCandidate> out;
  for (std::size_t k = 0; k < records.size();) {
    std::size_t m = k;
    while (m < records.size() && records[m].grain == records[k].grain)
      ++m;
    GRANPACK_CHECK(m - k == 2, "divalent grain " << records[k].grain << " has " << (m - k)
                                                 << " contact records, expected 2");
    DivalentCandidate c;
    c.grain = records[k].grain;
    c.contact[0] = records[k];
    c.contact[1] = records[k + 1];
    out.push_back(c);
    k = m;
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.force() != b.force() ? a.force() > b.force() : a.grain < b.grain;
  });
  return out;
}

} // namespace granpack
