#pragma once
// The launch of a divalent grain along its free rolling ([AR] fig. 14, App. E, eqs. E1-E2),
// and the picking of the divalent grains worth launching. MPI-free: the divalent_launch stage
// (stages/) gathers the two contacts of each divalent grain and calls these.
//
// Grain i touches j and k only. [AR]'s frame: e = (n_ik - n_ij) / |n_ik - n_ij| along the line
// of the centres of j and k, t = n_ij x n_ik / |.| normal to the plane of the three centres,
// f = t x e (from the j-k line towards i's centre; [AR] writes e x t, see divalent_frame); D the
// distance of i's centre to the j-k line. The free motion turns i's centre about that line at the
// angular velocity omega0: v_i = omega0 D t (E1), while i rolls on both contacts, Omega_i = 2
// omega0 e (E2) for equal spheres. Here Omega is the rotation about the line through the two
// contact points (the dynamics' branch vectors, contact point at mid-overlap) that gives E1
// exactly: neither contact point moves, so (v, Omega) is the null vector of G that `granpack
// stiffness` removes (analysis/rigidity_blocks.h, divalent_rolling_mode), and |Omega| = 2 omega0 (1
// + O(h/a)) for equal spheres. omega0 is set by the centrifugal force of the circular motion of the
// centre, m omega0^2 D, a fraction (1e-4 in [AR]) of the contact force |F_ij|: small enough not to
// unload the grain.
#include <cstdint>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

/// [AR] App. E's frame of one divalent grain.
struct DivalentFrame {
  Vec<3> e = Vec<3>::Zero(); ///< along the line of the neighbours' centres, from j towards k
  Vec<3> t = Vec<3>::Zero(); ///< normal to the plane of the three centres: the launch direction
  Vec<3> f = Vec<3>::Zero(); ///< t x e: from the j-k line towards i's centre
  double distance = 0;       ///< D, from i's centre to the j-k line (m)
};

/// The frame from the vectors r_ij, r_ik from i's centre to the centres of j and k (periodic
/// images). Throws granpack::Error when the three centres are aligned (no rolling circle).
DivalentFrame divalent_frame(const Vec<3>& r_ij, const Vec<3>& r_ik);

/// omega0 of [AR] App. E: m omega0^2 D = ratio |F|, F the contact force on the grain.
double divalent_omega0(double mass, double distance, double contact_force, double ratio);

/// The grain's velocity and angular velocity for the free rolling at omega0.
struct DivalentLaunch {
  DivalentFrame frame;
  double omega0 = 0;
  Vec<3> velocity = Vec<3>::Zero();         ///< omega0 D t (E1)
  Vec<3> angular_velocity = Vec<3>::Zero(); ///< about the contact line (E2)
};

/// b_ij, b_ik: branch vectors from i's centre to its two contact points.
DivalentLaunch divalent_launch(const Vec<3>& r_ij, const Vec<3>& r_ik, const Vec<3>& b_ij,
                               const Vec<3>& b_ik, double omega0);

/// One contact of a divalent grain, as seen from the grain.
struct DivalentContactRecord {
  GlobalId grain = 0, neighbour = 0;
  double r[3] = {0, 0, 0};      ///< from the grain's centre to the neighbour's
  double branch[3] = {0, 0, 0}; ///< from the grain's centre to the contact point
  double force = 0;             ///< |F| = |N n + T| (N the elastic normal force)
};

/// A divalent grain ready to be launched: both its contacts, neighbour ids ascending.
struct DivalentCandidate {
  GlobalId grain = 0;
  DivalentContactRecord contact[2];
  /// The ranking force: the smaller |F| of the two contacts (equal in equilibrium).
  double force() const;
};

/// Pairs the records (any order, exactly two per grain; throws granpack::Error otherwise)
/// into candidates sorted by decreasing force, ties by grain id: the same list on every rank
/// that holds the same records.
std::vector<DivalentCandidate> divalent_candidates(std::vector<DivalentContactRecord> records);

} // namespace granpack
