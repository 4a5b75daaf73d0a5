#pragma once
// The distributed rigidity matrix G and stiffness matrices of a packing's backbone
// ([AR] eq. 10-18, App. B), assembled with PETSc from the per-contact blocks of
// analysis/rigidity_blocks.h and the contact law's stiffness() (the dynamics' law).
//
// The strain coordinates couple to every grain, so the bordered stiffness matrix
//     [ K_uu  K_ue ]   grains: sparse, block size g = dim(dim+1)/2 (dim without friction)
//     [ K_eu  K_ee ]   strains: nv = dim(dim+1)/2 dense rows and columns (Voigt order)
// is kept in three parts: K_uu a PETSc AIJ matrix with block size g, the border as nv
// distributed vectors (columns K_ue and rows K_eu, laid out like K_uu's rows), K_ee a small
// replicated nv x nv matrix. The strain coordinates are then eliminated by a Schur
// complement (rigidity/condensation.h): dense rows never enter the sparse factorisation.
// The border has every strain of the periodic cell (diagonal first), for the elastic tensor;
// G keeps [AR]'s dim diagonal strain columns (eq. 9), on which the mechanisms and H are
// counted — the diagonal strains' Schur complement is the leading dim x dim block of the
// full one. docs/stiffness.md.
#include <array>
#include <vector>

#include "granpack/analysis/pivoting_clusters.h"
#include "granpack/analysis/rigidity_blocks.h"
#include "granpack/packing/packing_view.h"
#include "granpack/rigidity/grain_numbering.h"
#include "granpack/rigidity/petsc_support.h"

namespace granpack {

/// One contact point of a divalent backbone grain (two records per such grain).
struct DivalentContact {
  GlobalId grain = 0, neighbour = 0;
  double branch[3] = {0, 0, 0}; ///< from the grain's centre to the contact point
};

/// The stiffness matrix's grain block and its border, for one of K(1) or K(1) + K(2).
template <int dim> struct BorderedMatrix {
  OwnedMat uu;                              ///< K_uu (square, block size g)
  std::array<OwnedVec, voigt_size<dim>> ue; ///< columns K_{u, e_I}, Voigt order
  std::array<OwnedVec, voigt_size<dim>> eu; ///< rows K_{e_I, u}, stored as vectors
  VoigtMatrix<dim> ee = VoigtMatrix<dim>::Zero();
};

template <int dim> struct StiffnessSystem {
  MPI_Comm comm = MPI_COMM_WORLD;
  RigidityLayout<dim> layout; ///< with shear_strains: the border's unknowns
  GrainNumbering numbering;
  std::int64_t contacts = 0; ///< N_c^*: backbone contacts (distant pairs included)
  std::int64_t distant = 0;  ///< N_d: distant attractions among them ([GRC] eq. 19)
  std::int64_t rows = 0;     ///< rows of G: M of [GRC] App. A
  double mean_kn = 0;        ///< <k_n> over the contacts in touch (N/m): the matrices' scale
  OwnedMat G;                ///< rows x N_f, the dim diagonal strain columns last
  OwnedVec f;                ///< contact forces in G's row space
  BorderedMatrix<dim> k1;    ///< constitutive K(1), eq. (18): symmetric
  BorderedMatrix<dim> k;     ///< K(1) + K(2), App. B: unsymmetric with friction
  /// ᵀG |𝒦| G, assembled only when there are distant pairs: their -F0/D0 makes K(1)
  /// indefinite, so that its null space is no longer that of G ([GRC] App. A); with every
  /// stiffness positive the null space is exactly the mechanisms.
  BorderedMatrix<dim> gram;
  bool has_gram() const { return distant > 0; }
  std::vector<DivalentContact> divalent; ///< all ranks' records (3D with friction only)
  /// The parts hanging from one contact, free to pivot (3D with rolling resistance; the same
  /// on every rank): analysis/pivoting_clusters.h.
  std::vector<PivotingCluster> pivoting;
  double assembly_seconds = 0;

  int grain_dofs() const { return layout.grain_dofs(); }
  /// The matrix whose null space is that of G: K(1), or `gram` with distant pairs.
  BorderedMatrix<dim>& mechanism_matrix() { return has_gram() ? gram : k1; }
  std::int64_t dof() const { return numbering.grains * grain_dofs() + dim; } ///< N_f
};

/// Builds every matrix from the view's backbone contacts (on_backbone). `law` must be the
/// dynamics' law at the file's state (friction, K_N, K_r as in force then); rolling rows are
/// added when it has rolling resistance.
/// Collective on v.world.
template <int dim>
StiffnessSystem<dim> assemble_stiffness(const PackingView<dim>& v, const ContactLaw<dim>& law);

/// The per-contact input of the blocks: geometry, the static forces (N = N^e + N^a, T
/// projected on the tangent plane, the elastic rolling moment -K_r δθ) and the law's
/// stiffness at the file's state.
template <int dim>
RigidityContact<dim> make_rigidity_contact(const PackingView<dim>& v, const ContactView<dim>& c,
                                           const ContactLaw<dim>& law,
                                           const RigidityLayout<dim>& layout);

/// The contact-view predicate used everywhere: on the backbone and carrying force, or, on an
/// interaction network (select_interaction_network), any pair between two of its grains.
template <int dim> bool on_backbone(const PackingView<dim>& v, const ContactView<dim>& c) {
  if (v.rattler(c.i) || v.rattler(c.j))
    return false;
  return v.interaction_network || c.normal_force > v.force_threshold;
}

} // namespace granpack
