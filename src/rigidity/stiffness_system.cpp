#include "granpack/rigidity/stiffness_system.h"

#include <algorithm>
#include <chrono>

#include "granpack/comm/allgather.h"
#include "granpack/comm/collective_error.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/reduce.h"

namespace granpack {

namespace {

/// A vector laid out like K_uu's rows (n_local grains x g dofs).
OwnedVec grain_vector(MPI_Comm comm, PetscInt local_rows) {
  OwnedVec x;
  GRANPACK_PETSC(VecCreateMPI(comm, local_rows, PETSC_DETERMINE, x.address()));
  GRANPACK_PETSC(VecSet(x, 0.0));
  return x;
}

/// K_uu with block size g, preallocated from the number of backbone contacts per grain.
OwnedMat grain_matrix(MPI_Comm comm, PetscInt g, PetscInt local_grains,
                      const std::vector<PetscInt>& nnz) {
  OwnedMat a;
  GRANPACK_PETSC(MatCreate(comm, a.address()));
  GRANPACK_PETSC(
      MatSetSizes(a, local_grains * g, local_grains * g, PETSC_DETERMINE, PETSC_DETERMINE));
  GRANPACK_PETSC(MatSetType(a, MATAIJ));
  GRANPACK_PETSC(MatSetBlockSize(a, g));
  // Blocks per block row: the grain itself and one per contact, as diagonal- or
  // off-diagonal-part bound (an over-estimate of each, cheap at these sizes).
  GRANPACK_PETSC(MatXAIJSetPreallocation(a, g, nnz.data(), nnz.data(), nullptr, nullptr));
  GRANPACK_PETSC(MatSetOption(a, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  return a;
}

template <int dim>
void init_bordered(BorderedMatrix<dim>& b, MPI_Comm comm, PetscInt g, PetscInt local_grains,
                   const std::vector<PetscInt>& nnz) {
  b.uu = grain_matrix(comm, g, local_grains, nnz);
  for (int a = 0; a < voigt_size<dim>; ++a) {
    b.ue[a] = grain_vector(comm, local_grains * g);
    b.eu[a] = grain_vector(comm, local_grains * g);
  }
}

/// Adds the m x m local block (unknowns u_i rho_i, u_j rho_j, e: every strain) at the grains'
/// rows.
template <int dim>
void add_block(BorderedMatrix<dim>& b, const DynMatrix& block, const std::vector<PetscInt>& rows,
               int g) {
  constexpr int nv = voigt_size<dim>;
  const int two_g = 2 * g;
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> uu =
      block.topLeftCorner(two_g, two_g);
  GRANPACK_PETSC(MatSetValues(b.uu, two_g, rows.data(), two_g, rows.data(), uu.data(), ADD_VALUES));
  for (int a = 0; a < nv; ++a) {
    const DynVector col = block.block(0, two_g + a, two_g, 1);
    const DynVector row = block.block(two_g + a, 0, 1, two_g).transpose();
    GRANPACK_PETSC(VecSetValues(b.ue[a], two_g, rows.data(), col.data(), ADD_VALUES));
    GRANPACK_PETSC(VecSetValues(b.eu[a], two_g, rows.data(), row.data(), ADD_VALUES));
  }
  b.ee += block.bottomRightCorner(nv, nv);
}

template <int dim> void finish_bordered(BorderedMatrix<dim>& b, MPI_Comm comm) {
  GRANPACK_PETSC(MatAssemblyBegin(b.uu, MAT_FINAL_ASSEMBLY));
  GRANPACK_PETSC(MatAssemblyEnd(b.uu, MAT_FINAL_ASSEMBLY));
  for (int a = 0; a < voigt_size<dim>; ++a) {
    GRANPACK_PETSC(VecAssemblyBegin(b.ue[a]));
    GRANPACK_PETSC(VecAssemblyEnd(b.ue[a]));
    GRANPACK_PETSC(VecAssemblyBegin(b.eu[a]));
    GRANPACK_PETSC(VecAssemblyEnd(b.eu[a]));
  }
  global_sum_in_place(comm, std::span<double>(b.ee.data(), b.ee.size()));
}

} // namespace

template <int dim>
RigidityContact<dim> make_rigidity_contact(const PackingView<dim>& v, const ContactView<dim>& c,
                                           const ContactLaw<dim>& law,
                                           const RigidityLayout<dim>& layout) {
  const auto& p = v.particles();
  RigidityContact<dim> rc;
  rc.geometry =
      make_pair_geometry<dim>(p.radius[c.i], p.radius[c.j], p.mass[c.i], p.mass[c.j], c.branch);
  rc.normal_force = c.total_normal_force();
  rc.distant = c.distant;
  if (layout.rotations && !c.distant)
    rc.tangential_force =
        c.tangential_force - c.tangential_force.dot(rc.geometry.normal) * rc.geometry.normal;
  ContactState<dim> state;
  state.normal_force = c.normal_force;
  rc.stiffness = law.stiffness(rc.geometry, state);
  if (layout.rolling && !c.distant) {
    rc.rolling_moment = -rc.stiffness.k_r * c.rolling;
    // In 3D δθ is tangent up to the rounding of its transport; the rows see its rolling part.
    if constexpr (dim == 3)
      rc.rolling_moment -= rc.rolling_moment.dot(rc.geometry.normal) * rc.geometry.normal;
  }
  return rc;
}

template <int dim>
StiffnessSystem<dim> assemble_stiffness(const PackingView<dim>& v, const ContactLaw<dim>& law) {
  const auto start = std::chrono::steady_clock::now();
  const auto& p = v.particles();
  StiffnessSystem<dim> s;
  s.comm = v.world;
  s.layout.rotations = law.friction.mu > 0;
  s.layout.rolling = s.layout.rotations && law.rolling.has_value();
  s.layout.ell = 0.5 * v.diameter;
  s.layout.cell = v.system.cell.length;
  s.layout.shear_strains = true; // the stiffness border: every strain (the elastic tensor)
  RigidityLayout<dim> g_layout = s.layout;
  g_layout.shear_strains = false; // G: [AR]'s diagonal strains, on which k and H are counted
  const int g = s.grain_dofs();

  // Backbone grains and contacts of this rank, then the partition and numbering.
  std::vector<GlobalId> owned;
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    if (!v.rattler(i))
      owned.push_back(p.id[i]);
  std::vector<const ContactView<dim>*> mine;
  std::vector<std::pair<GlobalId, GlobalId>> edges;
  for (const auto& c : v.contacts)
    if (on_backbone(v, c))
      mine.push_back(&c), edges.emplace_back(p.id[c.i], p.id[c.j]);
  s.numbering = number_backbone_grains(v.world, owned, edges);
  const auto& num = s.numbering;
  s.contacts = global_sum(v.world, static_cast<std::int64_t>(mine.size()));
  PetscInt local_rows = 0;
  std::int64_t local_distant = 0;
  for (const auto* c : mine)
    local_rows += s.layout.rows_per_contact(c->distant), local_distant += c->distant;
  s.distant = global_sum(v.world, local_distant);
  s.rows = global_sum(v.world, std::int64_t(local_rows));

  // Block nonzeros per owned grain row: 1 + its backbone contacts (counted where the rows live).
  OwnedVec counts = grain_vector(v.world, num.local);
  collectively(v.world, [&] { // at() throws on one rank if a grain were not numbered
    for (const auto* c : mine) {
      const PetscInt ij[2] = {PetscInt(num.index.at(p.id[c->i])),
                              PetscInt(num.index.at(p.id[c->j]))};
      const PetscScalar one[2] = {1.0, 1.0};
      GRANPACK_PETSC(VecSetValues(counts, 2, ij, one, ADD_VALUES));
    }
  });
  GRANPACK_PETSC(VecAssemblyBegin(counts));
  GRANPACK_PETSC(VecAssemblyEnd(counts));
  std::vector<PetscInt> nnz(num.local);
  {
    const PetscScalar* x = nullptr;
    GRANPACK_PETSC(VecGetArrayRead(counts, &x));
    for (std::int64_t k = 0; k < num.local; ++k)
      nnz[k] = 1 + PetscInt(x[k]);
    GRANPACK_PETSC(VecRestoreArrayRead(counts, &x));
  }
  init_bordered(s.k1, v.world, g, num.local, nnz);
  init_bordered(s.k, v.world, g, num.local, nnz);
  if (s.has_gram())
    init_bordered(s.gram, v.world, g, num.local, nnz);

  // G: this rank's contact rows; columns laid out like K_uu's rows, strains on the last rank.
  const int rank = rank_of(v.world), size = size_of(v.world);
  const PetscInt local_cols = PetscInt(num.local) * g + (rank == size - 1 ? dim : 0);
  GRANPACK_PETSC(MatCreate(v.world, s.G.address()));
  GRANPACK_PETSC(MatSetSizes(s.G, local_rows, local_cols, PETSC_DETERMINE, PETSC_DETERMINE));
  GRANPACK_PETSC(MatSetType(s.G, MATAIJ));
  const PetscInt per_row = 2 * g + dim;
  GRANPACK_PETSC(MatMPIAIJSetPreallocation(s.G, per_row, nullptr, per_row, nullptr));
  GRANPACK_PETSC(MatSeqAIJSetPreallocation(s.G, per_row, nullptr));
  GRANPACK_PETSC(MatCreateVecs(s.G, nullptr, s.f.address()));
  PetscInt first_row = 0;
  GRANPACK_PETSC(MatGetOwnershipRange(s.G, &first_row, nullptr));
  const PetscInt strain_col = PetscInt(num.grains) * g;

  double sum_kn = 0;
  std::int64_t touching = 0;
  std::vector<DivalentContact> divalent;
  std::vector<NetworkEdge> network;
  std::vector<PetscInt> rows(2 * g), cols(per_row);
  PetscInt row = first_row;
  // A failure here (a contact without overlap, a grain missing from the numbering) is seen by
  // one rank only: collectively() makes every rank throw it before the next collective call.
  collectively(v.world, [&] {
    for (const auto* c : mine) {
      const RigidityContact<dim> rc = make_rigidity_contact(v, *c, law, s.layout);
      if (c->distant) {
        GRANPACK_CHECK(rc.stiffness.distant, "stiffness: the distant pair of grains "
                                                 << p.id[c->i] << " and " << p.id[c->j]
                                                 << " is not within the cohesion range D0");
      } else {
        GRANPACK_CHECK(rc.stiffness.k_n > 0, "stiffness: a force-carrying contact between grains "
                                                 << p.id[c->i] << " and " << p.id[c->j]
                                                 << " has no overlap");
        sum_kn += rc.stiffness.k_n, ++touching;
      }

      const PetscInt gi = PetscInt(num.index.at(p.id[c->i])),
                     gj = PetscInt(num.index.at(p.id[c->j]));
      for (int d = 0; d < g; ++d)
        rows[d] = gi * g + d, rows[g + d] = gj * g + d;
      const DynMatrix k1 = constitutive_block(rc, s.layout);
      add_block(s.k1, k1, rows, g);
      add_block(s.k, DynMatrix(k1 + geometric_block(rc, s.layout)), rows, g);
      if (s.has_gram()) {
        RigidityContact<dim> positive = rc;
        positive.stiffness.k_n = std::abs(rc.stiffness.k_n);
        add_block(s.gram, constitutive_block(positive, s.layout), rows, g);
      }

      // G rows and the contact force.
      std::copy(rows.begin(), rows.end(), cols.begin());
      for (int a = 0; a < dim; ++a)
        cols[2 * g + a] = strain_col + a;
      const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> grows =
          rigidity_rows(rc, g_layout);
      const int rows_c = s.layout.rows_per_contact(rc.distant);
      std::vector<PetscInt> grow_idx(rows_c);
      for (int k = 0; k < rows_c; ++k)
        grow_idx[k] = row + k;
      GRANPACK_PETSC(MatSetValues(s.G, rows_c, grow_idx.data(), per_row, cols.data(), grows.data(),
                                  INSERT_VALUES));
      const DynVector fc = contact_force_vector(rc, s.layout);
      GRANPACK_PETSC(VecSetValues(s.f, rows_c, grow_idx.data(), fc.data(), INSERT_VALUES));
      row += rows_c;

      // The interaction graph (3D, rolling resistance), for the pivoting parts.
      if constexpr (dim == 3) {
        if (s.layout.rolling) {
          const Vec<3> rij = rc.geometry.distance * rc.geometry.normal, bi = rc.geometry.branch_i();
          network.push_back({p.id[c->i],
                             p.id[c->j],
                             {rij[0], rij[1], rij[2]},
                             {bi[0], bi[1], bi[2]},
                             c->distant ? 1 : 0});
        }
      }
      // Divalent grains ([AR] fig. 14): their two contact points define the rolling mode.
      // Not with rolling resistance (the mode rolls on both contacts: the springs resist it)
      // nor with cohesion (a distant pair counts as an interaction but moves with the mode):
      // there free rollings are found, as any mechanism, by the factorisation.
      if constexpr (dim == 3) {
        if (s.layout.rotations && !s.layout.rolling && !law.cohesion) {
          if (std::lround(v.backbone.counts[c->i]) == 2)
            divalent.push_back({p.id[c->i],
                                p.id[c->j],
                                {rc.geometry.branch_i()[0], rc.geometry.branch_i()[1],
                                 rc.geometry.branch_i()[2]}});
          if (std::lround(v.backbone.counts[c->j]) == 2)
            divalent.push_back({p.id[c->j],
                                p.id[c->i],
                                {rc.geometry.branch_j()[0], rc.geometry.branch_j()[1],
                                 rc.geometry.branch_j()[2]}});
        }
      }
    }
  });
  GRANPACK_PETSC(MatAssemblyBegin(s.G, MAT_FINAL_ASSEMBLY));
  GRANPACK_PETSC(MatAssemblyEnd(s.G, MAT_FINAL_ASSEMBLY));
  GRANPACK_PETSC(VecAssemblyBegin(s.f));
  GRANPACK_PETSC(VecAssemblyEnd(s.f));
  finish_bordered(s.k1, v.world);
  finish_bordered(s.k, v.world);
  if (s.has_gram())
    finish_bordered(s.gram, v.world);
  s.mean_kn =
      global_sum(v.world, sum_kn) / std::max<std::int64_t>(1, global_sum(v.world, touching));

  // Every rank gets every divalent record (a few per cent of the grains, 40 bytes each).
  const auto by_grain = [](const auto& a, const auto& b) {
    return a.grain != b.grain ? a.grain < b.grain : a.neighbour < b.neighbour;
  };
  s.divalent = allgather_concat(v.world, divalent);
  std::sort(s.divalent.begin(), s.divalent.end(), by_grain);
  // The whole interaction graph on every rank (3D with rolling resistance only: the cohesive
  // packings are small; 72 bytes per interaction), so that every rank finds the same parts.
  if (s.layout.rolling)
    s.pivoting = pivoting_clusters(allgather_concat(v.world, network), s.layout.ell);
  s.assembly_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

template RigidityContact<2> make_rigidity_contact<2>(const PackingView<2>&, const ContactView<2>&,
                                                     const ContactLaw<2>&,
                                                     const RigidityLayout<2>&);
template RigidityContact<3> make_rigidity_contact<3>(const PackingView<3>&, const ContactView<3>&,
                                                     const ContactLaw<3>&,
                                                     const RigidityLayout<3>&);
template StiffnessSystem<2> assemble_stiffness<2>(const PackingView<2>&, const ContactLaw<2>&);
template StiffnessSystem<3> assemble_stiffness<3>(const PackingView<3>&, const ContactLaw<3>&);

} // namespace granpack
