#pragma once
// The distributed rigidity matrix G and stiffness matrices of a packing's backbone
// ([AR] eq. 10-18, App. B), assembled with PETSc from the per-contact blocks of
// analysis/rigidity_blocks.h and the contact law's stiffness() (the dynamics' law).
//
// The strain coordinates couple to every grain, so the bordered stiffness matrix
//     [ K_uu  K_ue ]   grains: sparse, block size g = dim(dim+1)/2 (dim without friction)
//     [ K_eu  K_ee ]   strains: dim dense rows and columns
// is kept in three parts: K_uu a PETSc AIJ matrix with block size g, the border as dim
// distributed vectors (columns K_ue and rows K_eu, laid out like K_uu's rows), K_ee a small
// replicated dim x dim matrix. The strain coordinates are then eliminated by a Schur
// complement (rigidity/condensation.h): dense rows never enter the sparse factorisation.
// G keeps its dim strain columns (its rows are sparse either way). docs/stiffness.md.
#include <array>
#include <vector>

#include "granpack/analysis/rigidity_blocks.h"
#include "granpack/app/packing_view.h"
#include "granpack/rigidity/grain_numbering.h"
#include "granpack/rigidity/petsc_support.h"

namespace granpack {

/// One contact point of a divalent backbone grain (two records per such grain).
struct DivalentContact {
  GlobalId grain = 0, neighbour = 0;
  double branch[3] = {0, 0, 0};  ///< from the grain's centre to the contact point
};

/// The stiffness matrix's grain block and its border, for one of K(1) or K(1) + K(2).
template <int dim> struct BorderedMatrix {
  OwnedMat uu;                  ///< K_uu (square, block size g)
  std::array<OwnedVec, dim> ue; ///< columns K_{u, e_alpha}
  std::array<OwnedVec, dim> eu; ///< rows K_{e_alpha, u}, stored as vectors
  Tensor<dim> ee = Tensor<dim>::Zero();
};

template <int dim> struct StiffnessSystem {
  MPI_Comm comm = MPI_COMM_WORLD;
  RigidityLayout<dim> layout;
  GrainNumbering numbering;
  std::int64_t contacts = 0;      ///< N_c^*: backbone contacts
  double mean_kn = 0;             ///< <k_n> over backbone contacts (N/m): the matrices' scale
  OwnedMat G;                     ///< (rows_per_contact N_c^*) x N_f, strain columns last
  OwnedVec f;                     ///< contact forces in G's row space
  BorderedMatrix<dim> k1;         ///< constitutive K(1), eq. (18): symmetric
  BorderedMatrix<dim> k;          ///< K(1) + K(2), App. B: unsymmetric with friction
  std::vector<DivalentContact> divalent;  ///< all ranks' records (3D with friction only)
  double assembly_seconds = 0;

  int grain_dofs() const { return layout.grain_dofs(); }
  std::int64_t dof() const { return numbering.grains * grain_dofs() + dim; }  ///< N_f
};

/// Builds every matrix from the view's backbone contacts (N > threshold, no rattler).
/// `law` must be the dynamics' law at the file's state (friction as in force then).
/// Collective on v.world.
template <int dim>
StiffnessSystem<dim> assemble_stiffness(const PackingView<dim>& v, const ContactLaw<dim>& law);

/// The contact-view predicate used everywhere: on the backbone and carrying force.
template <int dim> bool on_backbone(const PackingView<dim>& v, const ContactView<dim>& c) {
  return c.normal_force > v.force_threshold && !v.rattler(c.i) && !v.rattler(c.j);
}

}  // namespace granpack
