// `granpack stiffness` (app/stiffness.h) against closed forms and dense references:
//  - the Hertz FCC crystal: only the trivial translations, H from eq. (19) exactly, and the
//    bulk modulus of the crystal derived in docs/stiffness.md;
//  - small disordered packings (n = 108, frictional and frictionless): the mechanism count,
//    H and the bulk moduli equal a dense Eigen computation (SVD of G, pseudo-inverse /
//    dense LU for the condensation) on 1 and 2 ranks.
#include <gtest/gtest.h>
#include <mpi.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "granpack/analysis/rigidity_blocks.h"
#include "granpack/app/run_deck.h"
#include "granpack/app/stiffness.h"
#include "granpack/engine/material_law.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/packing/packing_view.h"
#include "granpack/rigidity/petsc_support.h"
#include "granpack/rigidity/stiffness_system.h"
#include "mpi_world.h"
#include "stiffness_runs.h"
#include "test_paths.h"

using namespace granpack;
using test::run_stiffness;
using test::run_text_deck;

namespace {

int rank_of() {
  return test::world_rank();
}
int size_of() {
  return test::world_size();
}

/// A small disordered packing: FCC melted by hard-sphere collisions, then compressed at
/// kappa = 1000 (soft, so that it settles quickly) with friction mu; with mu = 0.3 and this
/// seed one grain is divalent, so the rolling-mode path meets the dense SVD too. Without
/// friction 108 equal spheres recrystallise; diameters uniform in [0.8 a, a], placed at
/// random, stay disordered.
std::string small_deck(double mu) {
  return R"([sample]
dimension = 3
n = 108
diameter = 1.0e-3
seed = 3
)" + std::string(mu > 0 ? "" : "distribution = \"uniform\"\nmin_diameter_ratio = 0.8\n") +
         R"(
[material]
density = 2500.0
normal_law = "hertz"
young_modulus = 2.88e8
poisson_ratio = 0.3
friction = )" +
         std::to_string(mu) + R"(
damping = 0.98

[output]
log_every = 100000

)" +
         std::string(mu > 0 ? "[[stage]]\nkind = \"lattice\"\nlattice = \"fcc\"\nphi = 0.45\ncells "
                              "= [3, 3, 3]\n"
                            : "[[stage]]\nkind = \"random\"\nphi = 0.35\n") +
         R"(
[[stage]]
kind = "ed_gas"
collisions_per_grain = 50

[[stage]]
kind = "compress"
pressure = 1.0e4
inertia_max = 1.0e-2
quench_interval = 20000
)";
}

struct Dense {
  std::int64_t mechanisms = 0, rows = 0, dof = 0;
  std::int64_t monovalent = 0;  ///< grains with exactly one contact in touch
  std::int64_t k1_negative = 0; ///< eigenvalues below -1e-9 <k_n> of the pinned, stiffened K(1)_uu
  double bulk_k1 = 0, bulk = 0, smallest_kept_singular = 0, largest_dropped_singular = 0;
  Eigen::MatrixXd tensor_k1, tensor; ///< c_IJ, every strain (Voigt), K(1) and K(1) + K(2)
};

/// The dense reference, on rank 0 alone: the same per-contact kernels, assembled into full
/// Eigen matrices, with an SVD for the rank of G and dense linear algebra for B. With
/// cohesion the network is the whole interaction network, as `granpack stiffness` takes it.
template <int dim>
Dense dense_reference(const std::filesystem::path& file, const nlohmann::json& j,
                      double threshold) {
  const FileMeta meta = read_file_meta(MPI_COMM_SELF, file);
  PackingView<dim> v = load_packing<dim>(MPI_COMM_SELF, file, meta, threshold, 1.5);
  const ContactLaw<dim>& law = v.law;
  if (law.cohesion)
    select_interaction_network(v);
  RigidityLayout<dim> l;
  l.rotations = law.friction.mu > 0;
  l.rolling = l.rotations && law.rolling.has_value();
  l.ell = 0.5 * v.diameter;
  l.cell = v.system.cell.length;
  // K is bordered by every strain (the elastic tensor), G by the diagonal ones only.
  RigidityLayout<dim> lk = l;
  lk.shear_strains = true;
  constexpr int nv = voigt_size<dim>;
  const auto& p = v.particles();
  std::map<GlobalId, int> index;
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    if (!v.rattler(i))
      index.emplace(p.id[i], 0);
  int next = 0;
  for (auto& [id, k] : index)
    k = next++;
  const int g = l.grain_dofs();
  const int nf = next * g + dim;
  std::vector<RigidityContact<dim>> cs;
  std::vector<std::pair<int, int>> ends;
  int rows_total = 0;
  for (const auto& c : v.contacts) {
    if (!on_backbone(v, c))
      continue;
    cs.push_back(make_rigidity_contact(v, c, law, l));
    ends.emplace_back(index.at(p.id[c.i]), index.at(p.id[c.j]));
    rows_total += l.rows_per_contact(c.distant);
  }
  const int nk = next * g + nv;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(rows_total, nf), K1 = Eigen::MatrixXd::Zero(nk, nk);
  Eigen::MatrixXd K = K1;
  double kbar = 0;
  int touching = 0, row = 0;
  for (std::size_t c = 0; c < cs.size(); ++c) {
    std::vector<int> dofs;
    for (int d = 0; d < g; ++d)
      dofs.push_back(ends[c].first * g + d);
    for (int d = 0; d < g; ++d)
      dofs.push_back(ends[c].second * g + d);
    for (int a = 0; a < nv; ++a)
      dofs.push_back(next * g + a);
    const DynMatrix rows = rigidity_rows(cs[c], l);
    const DynMatrix k1 = constitutive_block(cs[c], lk), k = k1 + geometric_block(cs[c], lk);
    for (std::size_t a = 0; a < dofs.size(); ++a) {
      for (int r = 0; r < rows.rows() && a < std::size_t(rows.cols()); ++r)
        G(row + r, dofs[a]) += rows(r, a);
      for (std::size_t b = 0; b < dofs.size(); ++b)
        K1(dofs[a], dofs[b]) += k1(a, b), K(dofs[a], dofs[b]) += k(a, b);
    }
    row += int(rows.rows());
    if (!cs[c].distant)
      kbar += cs[c].stiffness.k_n, ++touching;
  }
  kbar /= double(touching);
  Dense out;
  // Grains with exactly one contact in touch: with rolling resistance in 3D each pivots freely.
  {
    std::vector<int> touching_contacts(next, 0);
    for (std::size_t c = 0; c < cs.size(); ++c)
      if (!cs[c].distant)
        ++touching_contacts[ends[c].first], ++touching_contacts[ends[c].second];
    out.monovalent = std::count(touching_contacts.begin(), touching_contacts.end(), 1);
  }
  out.rows = G.rows();
  out.dof = nf;
  Eigen::BDCSVD<Eigen::MatrixXd> svd(G);
  const auto& sv = svd.singularValues();
  std::int64_t rank = 0;
  out.smallest_kept_singular = sv[0];
  for (int k = 0; k < sv.size(); ++k) {
    if (sv[k] > 1e-9 * sv[0])
      ++rank, out.smallest_kept_singular = sv[k];
    else
      out.largest_dropped_singular = std::max(out.largest_dropped_singular, sv[k]);
  }
  out.mechanisms = nf - rank;

  const int nu = next * g;
  // c_IJ = s_I C_IJ s_J / Omega (+ sigma_I in the diagonal columns with K(2)), written out
  // here from the definitions (docs/stiffness.md) rather than taken from condensation.cpp.
  auto tensor_of = [&](const Eigen::MatrixXd& schur, bool with_stress) {
    Eigen::MatrixXd c(nv, nv);
    for (int i = 0; i < nv; ++i) {
      const auto [a, b] = voigt_pair<dim>(i);
      for (int jj = 0; jj < nv; ++jj) {
        const auto [e, f] = voigt_pair<dim>(jj);
        c(i, jj) = std::sqrt(l.cell[a] * l.cell[b] * l.cell[e] * l.cell[f]) * schur(i, jj) /
                       v.system.cell.volume() +
                   (with_stress && e == f ? 0.5 * (v.stress(a, b) + v.stress(b, a)) : 0.0);
      }
    }
    return c;
  };
  auto bulk_of = [&](const Eigen::MatrixXd& c) {
    return c.topLeftCorner(dim, dim).sum() / double(dim * dim);
  };
  // The same pinned grain and stiffened rolling modes as the distributed code.
  auto pinned = [&](Eigen::MatrixXd m) {
    for (const auto& d : j["divalent_grains"]) {
      if constexpr (dim == 3) {
        const int gi = index.at(d["grain"].get<GlobalId>());
        std::vector<granpack::Vec<3>> pts;
        for (std::size_t c = 0; c < cs.size(); ++c) {
          if (ends[c].first == gi)
            pts.push_back(cs[c].geometry.branch_i());
          if (ends[c].second == gi)
            pts.push_back(cs[c].geometry.branch_j());
        }
        EXPECT_EQ(pts.size(), 2u);
        const auto vmode = divalent_rolling_mode(pts[0], pts[1], l.ell);
        m.block(gi * g, gi * g, 6, 6) += kbar * vmode * vmode.transpose();
      }
    }
    // Pivoting parts (3D, rolling resistance): a pivoting spring <k_n> (n.(ρ_a - ρ_b))² on
    // each hinge contact, n its normal from the hinge grain a to its neighbour b.
    for (const auto& d : j["pivoting_grains"]) {
      if constexpr (dim == 3) {
        const int ga = index.at(d["grain"].get<GlobalId>()),
                  gb = index.at(d["neighbour"].get<GlobalId>());
        int found = 0;
        for (std::size_t c = 0; c < cs.size(); ++c)
          if (!cs[c].distant && ((ends[c].first == ga && ends[c].second == gb) ||
                                 (ends[c].first == gb && ends[c].second == ga))) {
            ++found;
            const granpack::Vec<3> n = ends[c].first == ga
                                           ? cs[c].geometry.normal
                                           : granpack::Vec<3>(-cs[c].geometry.normal);
            Eigen::VectorXd hinge = Eigen::VectorXd::Zero(m.rows());
            hinge.segment<3>(ga * g + 3) = n;
            hinge.segment<3>(gb * g + 3) = -n;
            m += kbar * hinge * hinge.transpose();
          }
        EXPECT_EQ(found, 1);
      }
    }
    const int pin = index.at(j["pinned_grain"].get<GlobalId>());
    for (int a = 0; a < dim; ++a) {
      m.row(pin * g + a).setZero();
      m.col(pin * g + a).setZero();
      m(pin * g + a, pin * g + a) = kbar;
    }
    return m;
  };
  {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(pinned(K1).topLeftCorner(nu, nu));
    for (int k = 0; k < nu; ++k)
      out.k1_negative += es.eigenvalues()[k] < -1e-9 * kbar;
  }
  if (!j["moduli_valid"].get<bool>())
    return out; // floppy or unstable: no response to compare

  // K(1): the grain block's pseudo-inverse (the border lies in its range, K1 = ᵀG 𝒦 G).
  {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(K1.topLeftCorner(nu, nu));
    const auto& lam = es.eigenvalues();
    const double top = lam.cwiseAbs().maxCoeff();
    Eigen::VectorXd inv = Eigen::VectorXd::Zero(nu);
    for (int k = 0; k < nu; ++k)
      if (std::abs(lam[k]) > 1e-10 * top)
        inv[k] = 1.0 / lam[k];
    const Eigen::MatrixXd pinv =
        es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
    const Eigen::MatrixXd schur = K1.bottomRightCorner(nv, nv) -
                                  K1.bottomLeftCorner(nv, nu) * pinv * K1.topRightCorner(nu, nv);
    out.tensor_k1 = tensor_of(schur, false);
    out.bulk_k1 = bulk_of(out.tensor_k1);
  }
  // K: dense LU of the pinned grain block.
  {
    const Eigen::MatrixXd kp = pinned(K);
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(kp.topLeftCorner(nu, nu));
    const Eigen::MatrixXd schur = kp.bottomRightCorner(nv, nv) -
                                  kp.bottomLeftCorner(nv, nu) * lu.solve(kp.topRightCorner(nu, nv));
    out.tensor = tensor_of(schur, true);
    out.bulk = bulk_of(out.tensor);
  }
  return out;
}

/// The distributed result against the dense one (rank 0).
template <int dim>
void expect_matches_dense(const std::string& tag, const std::filesystem::path& file,
                          const nlohmann::json& json, double threshold) {
  const Dense d = dense_reference<dim>(file, json, threshold);
  // The rank decision is clear-cut: a wide gap between kept and dropped singular values.
  EXPECT_LT(d.largest_dropped_singular, 1e-12 * d.smallest_kept_singular);
  EXPECT_EQ(json["N_f"].get<std::int64_t>(), d.dof);
  EXPECT_EQ(json["G_rows"].get<std::int64_t>(), d.rows);
  EXPECT_EQ(json["mechanisms"].get<std::int64_t>(), d.mechanisms)
      << tag << ", threshold " << threshold;
  EXPECT_EQ(json["H"].get<std::int64_t>(), d.rows + d.mechanisms - d.dof);
  // Every grain with one contact in touch hangs from it (larger parts may hang too).
  if (dim == 3 && json["rolling_rows"].get<bool>())
    EXPECT_GE(json["pivoting_mechanisms"].get<std::int64_t>(), d.monovalent) << tag;
  else
    EXPECT_EQ(json["pivoting_mechanisms"].get<std::int64_t>(), 0) << tag;
  // Measured with distant pairs; without, K(1) = ᵀG 𝒦 G is positive semi-definite, which the
  // dense spectrum confirms.
  EXPECT_EQ(json["K1_negative_pivots"].get<std::int64_t>(), d.k1_negative) << tag;
  if (json["distant_pairs"].get<std::int64_t>() == 0) {
    EXPECT_EQ(d.k1_negative, 0) << tag;
  }
  std::printf("[ stiffness ] %s, threshold %g: k = %lld (dense %lld), H = %lld, K(1) negative %lld "
              "(dense %lld)\n",
              tag.c_str(), threshold, (long long)json["mechanisms"].get<std::int64_t>(),
              (long long)d.mechanisms, (long long)json["H"].get<std::int64_t>(),
              (long long)json["K1_negative_pivots"].get<std::int64_t>(), (long long)d.k1_negative);
  if (!json["moduli_valid"].get<bool>())
    return;
  EXPECT_NEAR(json["constitutive"]["bulk_modulus"].get<double>(), d.bulk_k1, 1e-8 * d.bulk_k1);
  EXPECT_NEAR(json["bulk_modulus"].get<double>(), d.bulk, 1e-8 * d.bulk);
  // The whole tensor, K(1) and K(1) + K(2), entry by entry (relative to its largest entry),
  // and B from the tensor is the bulk modulus.
  for (const auto& [e, dense] : {std::pair{&json["constitutive"]["elastic_tensor"], &d.tensor_k1},
                                 std::pair{&json["elastic_tensor"], &d.tensor}}) {
    const double top = dense->cwiseAbs().maxCoeff();
    double worst = 0;
    for (int i = 0; i < dense->rows(); ++i)
      for (int k = 0; k < dense->cols(); ++k) {
        const double got = (*e)["c"][i][k].template get<double>();
        EXPECT_NEAR(got, (*dense)(i, k), 1e-8 * top) << tag << " c(" << i << ", " << k << ")";
        worst = std::max(worst, std::abs(got - (*dense)(i, k)) / top);
      }
    std::printf("[ stiffness ] %s: elastic tensor %s equals the dense one to %.2g of max |c|\n",
                tag.c_str(), dense == &d.tensor ? "(K)" : "(K1)", worst);
  }
  EXPECT_NEAR(json["elastic_tensor"]["bulk_voigt"].get<double>(),
              json["bulk_modulus"].get<double>(), 1e-12 * d.bulk);
  std::printf("[ stiffness ] %s: B = %.10g (dense %.10g), B1 = %.10g (dense %.10g)\n", tag.c_str(),
              json["bulk_modulus"].get<double>(), d.bulk,
              json["constitutive"]["bulk_modulus"].get<double>(), d.bulk_k1);
}

/// The Krylov path (CG, MINRES or GMRES with multigrid, docs/stiffness.md "Moduli of large
/// packings") on the same packing: the same tensors as the direct path to 1e-6 of max |c|,
/// the quantities it cannot compute null, the divalent grain still named. Every rank.
void expect_krylov_matches_direct(const std::string& tag, const std::filesystem::path& file,
                                  const nlohmann::json& direct, bool frictionless) {
  const auto k = run_stiffness(file, 1e-4, StiffnessSolver::kKrylov);
  EXPECT_EQ(direct["solver"]["path"], "direct") << tag;
  EXPECT_EQ(k["solver"]["path"], "krylov") << tag;
  ASSERT_TRUE(k["moduli_valid"].get<bool>()) << tag << ": " << k["solver"].dump();
  EXPECT_TRUE(k["mechanisms"].is_null() && k["H"].is_null()) << tag;
  EXPECT_EQ(k["divalent_mechanisms"], direct["divalent_mechanisms"]) << tag;
  // K by K(1)'s multigrid: MINRES without friction (symmetric, maybe indefinite), GMRES with.
  const auto& kr = k["solver"]["krylov"];
  EXPECT_EQ(kr["K"]["method"], frictionless ? "minres" : "gmres") << tag;
  EXPECT_EQ(kr["K"]["preconditioner"], "shared gamg") << tag;
  EXPECT_FALSE(kr.contains("K_minres")) << tag << ": MINRES fell back to GMRES";
  for (const char* part : {"", "constitutive"}) {
    const auto& a = part[0] ? direct[part]["elastic_tensor"] : direct["elastic_tensor"];
    const auto& b = part[0] ? k[part]["elastic_tensor"] : k["elastic_tensor"];
    double top = 0, worst = 0;
    for (int i = 0; i < 6; ++i)
      for (int m = 0; m < 6; ++m)
        top = std::max(top, std::abs(a["c"][i][m].get<double>()));
    for (int i = 0; i < 6; ++i)
      for (int m = 0; m < 6; ++m)
        worst = std::max(worst,
                         std::abs(a["c"][i][m].get<double>() - b["c"][i][m].get<double>()) / top);
    EXPECT_LT(worst, 1e-6) << tag << " " << part;
    if (rank_of() == 0)
      std::printf("[ stiffness ] %s: Krylov tensor %s equals the direct one to %.2g of max |c|\n",
                  tag.c_str(), part[0] ? "(K1)" : "(K)", worst);
  }
}

void compare_with_dense(const std::string& tag, double mu) {
  const auto file = run_text_deck(tag, small_deck(mu));
  const auto j = run_stiffness(file);
  EXPECT_TRUE(j["positive_definite"].get<bool>());
  EXPECT_LT(j["virtual_work_residual"].get<double>(), 1e-3);
  if (mu > 0) {
    EXPECT_EQ(j["divalent_mechanisms"], 1); // the case this deck is chosen for
  }
  expect_krylov_matches_direct(tag, file, j, mu == 0);
  // A threshold of 0.3 a^2 P (0.2 without friction) drops the weak contacts: the backbone
  // left is floppy, and the unexpected mechanisms are counted by SLEPc (this tests that path
  // against the SVD too).
  const double floppy_threshold = mu > 0 ? 0.3 : 0.2;
  const auto floppy = run_stiffness(file, floppy_threshold);
  EXPECT_FALSE(floppy["positive_definite"].get<bool>());
  EXPECT_GT(floppy["other_mechanisms"].get<std::int64_t>(), 0);
  EXPECT_EQ(floppy["other_mechanism_grains"].size(), floppy["other_mechanisms"].get<std::size_t>());
  EXPECT_TRUE(floppy["bulk_modulus"].is_null());
  if (rank_of() != 0)
    return;
  for (const auto& [json, threshold] : {std::pair{&j, 1e-4}, std::pair{&floppy, floppy_threshold}})
    expect_matches_dense<3>(tag, file, *json, threshold);
}

} // namespace

TEST(Stiffness, SmallFrictionalPackingMatchesDense) {
  compare_with_dense("stiffness_small_mu03", 0.3);
}
TEST(Stiffness, SmallFrictionlessPackingMatchesDense) {
  compare_with_dense("stiffness_small_mu0", 0.0);
}

TEST(Stiffness, HertzFccCrystal) {
  const auto file = test::run_ci_deck_file("fcc_hertz", "stiffness_fcc");
  const auto j = run_stiffness(file);
  // 256 grains, 12 contacts each: N_c = 1536, N_f = 6 x 256 + 3, k = 3 (translations).
  EXPECT_EQ(j["backbone_contacts"], 1536);
  EXPECT_EQ(j["mechanisms"], 3);
  EXPECT_EQ(j["trivial_mechanisms"], 3);
  EXPECT_EQ(j["divalent_mechanisms"], 0);
  EXPECT_EQ(j["other_mechanisms"], 0);
  EXPECT_EQ(j["H"], 3 * 1536 + 3 - (6 * 256 + 3));
  EXPECT_TRUE(j["positive_definite"].get<bool>());
  EXPECT_FALSE(j["isostatic"].get<bool>());

  // The analytic crystal (docs/stiffness.md): nearest distance r from the cell volume,
  // Omega / n = r^3 / sqrt(2); Hertz k_n = E~ sqrt(a h / 4), N = (2/3) k_n h, h = a - r.
  // Every grain is a centre of inversion: the response to any diagonal strain is affine,
  // B(1) = (2 sqrt 2 / 3) k_n / r, and with K(2) and the volume change B = B(1) + (2/3) P.
  const double a = 1e-3, e_tilde = 70e9 / (1 - 0.09);
  const double volume_per_grain = std::pow(j["phi"].get<double>(), -1) * M_PI * a * a * a / 6;
  const double r = std::cbrt(std::sqrt(2.0) * volume_per_grain);
  const double h = a - r;
  const double kn = e_tilde * std::sqrt(a * h / 4);
  const double n_force = 2.0 / 3.0 * kn * h;
  const double b1 = 2 * std::sqrt(2.0) / 3 * kn / r;
  const double p = 2 * std::sqrt(2.0) * n_force / (r * r);
  const double b = b1 + 2.0 / 3.0 * p;
  EXPECT_NEAR(j["pressure"].get<double>(), p, 1e-6 * p);
  EXPECT_NEAR(j["constitutive"]["bulk_modulus"].get<double>(), b1, 1e-6 * b1);
  EXPECT_NEAR(j["bulk_modulus"].get<double>(), b, 1e-6 * b);
  // Diagonal-strain shear, affine (cubic symmetry cancels the torques too):
  // c11 - c12 = (sqrt 2 / r)(k_n + 3 k_t)/2, G(1) = sqrt 2 (k_n + 3 k_t) / (4 r).
  const double kt = (2 - 2 * 0.3) / (2 - 0.3) * kn;
  const double g1 = std::sqrt(2.0) * (kn + 3 * kt) / (4 * r);
  EXPECT_NEAR(j["constitutive"]["shear_modulus_diag"].get<double>(), g1, 1e-6 * g1);
  if (rank_of() == 0)
    std::printf("[ stiffness ] FCC: B = %.10g Pa (analytic %.10g), B(1) = %.10g (analytic %.10g), "
                "P = %.8g\n",
                j["bulk_modulus"].get<double>(), b, j["constitutive"]["bulk_modulus"].get<double>(),
                b1, p);

  // MUMPS without extra workspace (ICNTL(14) = 0, a run-time option a user may set): the
  // crystal's null pivots then overflow MUMPS's estimate on 4 ranks in most runs (INFOG(1) =
  // -9 in 5 of 6 runs before factorize() retried with more); the retry gives the same moduli
  // and leaves the user's option as it was.
  const char* option = "-stiffness_mat_mumps_icntl_14";
  ASSERT_EQ(PetscOptionsSetValue(nullptr, option, "0"), 0);
  const auto tight = run_stiffness(file);
  char value[32] = "";
  PetscBool set = PETSC_FALSE;
  ASSERT_EQ(PetscOptionsGetString(nullptr, nullptr, option, value, sizeof value, &set), 0);
  ASSERT_EQ(PetscOptionsClearValue(nullptr, option), 0);
  EXPECT_TRUE(set);
  EXPECT_STREQ(value, "0");
  EXPECT_EQ(tight["mechanisms"], 3);
  EXPECT_NEAR(tight["bulk_modulus"].get<double>(), j["bulk_modulus"].get<double>(), 1e-9 * b);
}

namespace {

/// [GRC]-type 2D decks: 80 polydisperse cohesive disks (kappa = a K_N / F0 = 1e3, D0 = 0.02 a
/// so that distant pairs are not too rare) compressed directly at P* = 0.01 from Phi 0.52.
/// `variant`: "rr" (mu = 0.5 with rolling resistance, equilibrated), "mid" (the same stopped
/// after 4000 steps, mid-compression: distant pairs and an unstable K(1)), "norr" (mu = 0.5,
/// no rolling resistance), "mu0" (frictionless).
/// In 3D (dim = 3) the same transposed to 100 spheres: phi_I = 0.35, P = 0.01 F0 / a².
std::string cohesive_deck(const std::string& variant, int dim = 2) {
  const bool rolling = variant == "rr" || variant == "mid";
  return R"([sample]
dimension = )" +
         std::to_string(dim) + (dim == 2 ? "\nn = 80\n" : "\nn = 100\n") + R"(
diameter = 1.0e-3
distribution = "uniform"
min_diameter_ratio = 0.5
seed = 4

[material]
density = 2500.0
normal_law = "linear"
normal_stiffness = 1.0e6
tangential_stiffness_ratio = 1.0
friction = )" +
         std::string(variant == "mu0" ? "0.0" : "0.5") + R"(
damping = 0.8
cohesion_force = 1.0
cohesion_range = 2.0e-5
)" +
         std::string(
             rolling
                 ? "rolling_stiffness = 1.0e-4\nrolling_friction = 5.0e-6\nrolling_damping = 0.8\n"
                 : "") +
         R"(
[output]
log_every = 1000000

[[stage]]
kind = "random"
)" + std::string(dim == 2 ? "phi = 0.52\n" : "phi = 0.35\n") +
         R"(
[[stage]]
kind = "compress"
cell_mass = 0.3
)" +
         std::string(dim == 2 ? "pressure = 10.0\ncell_mass_per_length = true\n"
                              : "pressure = 1.0e4\n") +
         R"(tolerance_force = 1e-3
tolerance_moment = 1e-3
tolerance_stress = 1e-3
tolerance_kinetic = 1e-6
)" + std::string(variant == "mid" ? "max_steps = 4000\n" : "");
}

nlohmann::json cohesive_case(const std::string& variant, std::filesystem::path* file) {
  *file = run_text_deck("stiffness_cohesive_" + variant, cohesive_deck(variant));
  const auto j = run_stiffness(*file);
  EXPECT_EQ(j["network"], "interactions");
  EXPECT_EQ(j["other_mechanism_grains"].size(), j["other_mechanisms"].get<std::size_t>());
  return j;
}

} // namespace

TEST(Stiffness, CohesiveRollingPackingMatchesDense) {
  // [GRC] App. A: with rolling resistance the equilibrated packing at P* = 0.01 is rigid and
  // K(1) positive definite; rows 3 per contact, H from eq. (21).
  std::filesystem::path file;
  const auto j = cohesive_case("rr", &file);
  EXPECT_EQ(j["H_relation"], "GRC eq. 21");
  EXPECT_TRUE(j["rigid"].get<bool>());
  EXPECT_TRUE(j["positive_definite"].get<bool>());
  EXPECT_EQ(j["mechanisms"], 2);
  EXPECT_EQ(j["G_rows"].get<std::int64_t>(), 3 * j["backbone_contacts"].get<std::int64_t>());
  EXPECT_LT(j["virtual_work_residual"].get<double>(), 2e-2); // criteria 1e-3 F0 per grain
  if (rank_of() == 0)
    expect_matches_dense<2>("cohesive rr", file, j, 1e-4);
}

TEST(Stiffness, CohesiveDistantPairsMatchDense) {
  // Mid-compression: distant pairs (one normal row, stiffness -F0/D0) make K(1) indefinite;
  // the mechanisms still come from G (ᵀG|𝒦|G), and the negative pivots of K(1) equal the
  // negative eigenvalues of the dense matrix.
  std::filesystem::path file;
  const auto j = cohesive_case("mid", &file);
  ASSERT_GT(j["distant_pairs"].get<std::int64_t>(), 0);
  EXPECT_GT(j["K1_negative_pivots"].get<std::int64_t>(), 0);
  EXPECT_FALSE(j["positive_definite"].get<bool>());
  EXPECT_TRUE(j["bulk_modulus"].is_null());
  if (rank_of() == 0)
    expect_matches_dense<2>("cohesive mid", file, j, 1e-4);
}

TEST(Stiffness, CohesiveWithoutRollingMatchesDense) {
  // No rolling resistance (eq. 19) and no friction (eq. 22): the disks with a single contact
  // keep a free motion each ([GRC] sec. III: "the free rolling of isolated grains with only
  // one contact"), named as one-grain mechanisms.
  for (const std::string variant : {"norr", "mu0"}) {
    std::filesystem::path file;
    const auto j = cohesive_case(variant, &file);
    EXPECT_EQ(j["H_relation"], variant == "mu0" ? "GRC eq. 22" : "GRC eq. 19");
    const auto rows_per = variant == "mu0" ? 1 : 2;
    EXPECT_EQ(j["G_rows"].get<std::int64_t>(),
              rows_per * j["backbone_contacts"].get<std::int64_t>());
    EXPECT_GT(j["other_mechanisms"].get<std::int64_t>(), 0);
    for (const auto& m : j["other_mechanism_grains"])
      EXPECT_EQ(m.size(), 1u) << variant;
    if (rank_of() == 0)
      expect_matches_dense<2>("cohesive " + variant, file, j, 1e-4);
  }
}

TEST(Stiffness, Cohesive3DRRMatchesDense) {
  // 3D, rolling resistance: 5 rows per contact (δu, two rolling rows), 1 per distant pair;
  // pivoting is free, so each part hanging from one contact (a grain with one contact, a
  // dimer...) keeps one mechanism (removed like the divalent rolling of [AR]); the rest is
  // rigid here, and the whole tensor equals the dense Schur complement.
  std::filesystem::path file;
  file = run_text_deck("stiffness_cohesive3d_rr", cohesive_deck("rr", 3));
  const auto j = run_stiffness(file);
  EXPECT_EQ(j["network"], "interactions");
  EXPECT_EQ(j["H_relation"], "GRC eq. 21");
  EXPECT_EQ(j["G_rows"].get<std::int64_t>(), 5 * (j["backbone_contacts"].get<std::int64_t>() -
                                                  j["distant_pairs"].get<std::int64_t>()) +
                                                 j["distant_pairs"].get<std::int64_t>());
  EXPECT_GT(j["pivoting_mechanisms"].get<std::int64_t>(), 0); // the case this deck is chosen for
  EXPECT_LT(j["pivoting_mode_residual"].get<double>(), 1e-12);
  EXPECT_EQ(j["divalent_mechanisms"], 0);
  EXPECT_TRUE(j["rigid"].get<bool>());
  EXPECT_TRUE(j["moduli_valid"].get<bool>());
  EXPECT_LT(j["virtual_work_residual"].get<double>(), 2e-2); // criteria 1e-3 F0 per grain
  std::printf("[ stiffness ] cohesive 3D rr: k = %lld (pivoting %lld, other %lld), H = %lld, "
              "B = %.6g Pa, virtual work %.2g\n",
              (long long)j["mechanisms"].get<std::int64_t>(),
              (long long)j["pivoting_mechanisms"].get<std::int64_t>(),
              (long long)j["other_mechanisms"].get<std::int64_t>(),
              (long long)j["H"].get<std::int64_t>(), j["bulk_modulus"].get<double>(),
              j["virtual_work_residual"].get<double>());
  if (rank_of() == 0)
    expect_matches_dense<3>("cohesive 3D rr", file, j, 1e-4);
}

TEST(Stiffness, Cohesive3DDistantPairsMatchDense) {
  // Mid-compression in 3D: distant pairs (normal row, -F0/D0) make K(1) indefinite; k, H and
  // the negative eigenvalue count of K(1) equal the dense reference's.
  const auto file = run_text_deck("stiffness_cohesive3d_mid", cohesive_deck("mid", 3));
  const auto j = run_stiffness(file);
  ASSERT_GT(j["distant_pairs"].get<std::int64_t>(), 0);
  std::printf("[ stiffness ] cohesive 3D mid: %lld distant pairs, K(1) negative %lld, k = %lld\n",
              (long long)j["distant_pairs"].get<std::int64_t>(),
              (long long)j["K1_negative_pivots"].get<std::int64_t>(),
              (long long)j["mechanisms"].get<std::int64_t>());
  if (rank_of() == 0)
    expect_matches_dense<3>("cohesive 3D mid", file, j, 1e-4);
}

TEST(Stiffness, CohesiveHexCrystalAtZeroPressure) {
  // 128 equal cohesive disks on a triangular lattice relaxed at P = 0: every contact at
  // h0 = F0/K_N carries N = 0, so K(2) = 0, and the response is affine (every disk is a
  // centre of inversion). Linear springs: B = sqrt(3)/2 K_N, G_diag = sqrt(3)/4 (K_N + K_T),
  // whatever the lattice spacing (docs/stiffness.md). Rows: 3 per contact with rolling
  // resistance; k = 2; H = 3 N_c + 2 - (3 n + 2) with N_c = 3 n.
  const std::string deck = R"([sample]
dimension = 2
n = 128
diameter = 1.0e-3

[material]
density = 2500.0
normal_law = "linear"
normal_stiffness = 1.0e5
tangential_stiffness_ratio = 0.5
friction = 0.5
damping = 0.8
cohesion_force = 0.1
cohesion_range = 1.0e-6
rolling_stiffness = 1.0e-5
rolling_friction = 5.0e-6
rolling_damping = 0.8

[output]
log_every = 1000000

[[stage]]
kind = "lattice"
lattice = "hex"
phi = 0.90689
cells = [8, 8]

[[stage]]
kind = "compress"
pressure = 0.0
cell_mass = 0.3
cell_mass_per_length = true
tolerance_force = 1e-6
tolerance_moment = 1e-6
tolerance_stress = 1e-6
tolerance_kinetic = 1e-12
)";
  const auto file = run_text_deck("stiffness_cohesive_hex", deck);
  const auto j = run_stiffness(file);
  EXPECT_EQ(j["backbone_contacts"], 384);
  EXPECT_EQ(j["distant_pairs"], 0);
  EXPECT_EQ(j["N_f"], 3 * 128 + 2);
  EXPECT_EQ(j["G_rows"], 3 * 384);
  EXPECT_EQ(j["mechanisms"], 2);
  EXPECT_EQ(j["H"], 3 * 384 + 2 - (3 * 128 + 2));
  EXPECT_TRUE(j["rigid"].get<bool>());
  EXPECT_TRUE(j["positive_definite"].get<bool>());
  const double kn = 1e5, kt = 0.5e5;
  const double b = std::sqrt(3.0) / 2 * kn, g = std::sqrt(3.0) / 4 * (kn + kt);
  // The relaxed crystal keeps a self-stress (H > 0) of ~1e-4 F0 and bond lengths that differ
  // by ~1e-6 between the three directions; the affine moduli of its actual bonds,
  //   c_ab = (1/A) sum_c [k_n n_a r_a n_b r_b + k_t sum_g P_ga r_a P_gb r_b], P = 1 - n nᵀ,
  // are exact up to the second order in that distortion, the closed forms to the first.
  Eigen::Matrix2d c = Eigen::Matrix2d::Zero();
  {
    const FileMeta meta = read_file_meta(MPI_COMM_WORLD, file);
    const PackingView<2> v = load_packing<2>(MPI_COMM_WORLD, file, meta, 1e-4, 1.5);
    for (const auto& ct : v.contacts) {
      const Eigen::Vector2d r = ct.branch, n = r.normalized();
      const Eigen::Matrix2d proj = Eigen::Matrix2d::Identity() - n * n.transpose();
      for (int a = 0; a < 2; ++a)
        for (int bb = 0; bb < 2; ++bb)
          c(a, bb) += kn * n[a] * r[a] * n[bb] * r[bb] +
                      kt * (proj.col(a) * r[a]).dot(proj.col(bb) * r[bb]);
    }
    MPI_Allreduce(MPI_IN_PLACE, c.data(), 4, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    c /= v.system.cell.volume();
  }
  const double b_affine = c.sum() / 4, g_affine = ((c(0, 0) + c(1, 1)) / 2 - c(0, 1)) / 2;
  EXPECT_NEAR(j["constitutive"]["bulk_modulus"].get<double>(), b_affine, 1e-9 * b);
  EXPECT_NEAR(j["constitutive"]["shear_modulus_diag"].get<double>(), g_affine, 1e-9 * g);
  EXPECT_NEAR(j["constitutive"]["bulk_modulus"].get<double>(), b, 1e-5 * b);
  EXPECT_NEAR(j["constitutive"]["shear_modulus_diag"].get<double>(), g, 1e-5 * g);
  // With K(2) and the stress term: the self-stress is ~1e-4 F0, N/r ~ 1e-4 K_N.
  EXPECT_NEAR(j["bulk_modulus"].get<double>(), b, 1e-4 * b);
  if (rank_of() == 0)
    std::printf("[ stiffness ] cohesive hex: B1 = %.10g (affine %.10g, sqrt3/2 K_N = %.10g), G1 = "
                "%.10g (affine "
                "%.10g, sqrt3/4 (K_N + K_T) = %.10g), B = %.10g\n",
                j["constitutive"]["bulk_modulus"].get<double>(), b_affine, b,
                j["constitutive"]["shear_modulus_diag"].get<double>(), g_affine, g,
                j["bulk_modulus"].get<double>());
}

// A file written before /parameters existed (docs/data/2d/seriesA_rr_P0.01.h5, cohesive, rolling
// resistance) replays its deck: the contact law, and the target of its last compress stage.
// The same grains written with those parameters in /parameters give the same report.
TEST(Stiffness, OldFilesReplayTheirDeckAsTheirParametersWould) {
  const auto old_file = test::source_dir() / "docs/data/2d/seriesA_rr_P0.01.h5";
  const FileMeta meta = read_file_meta(MPI_COMM_WORLD, old_file);
  ASSERT_FALSE(meta.parameters);
  const StateParameters replayed =
      replayed_parameters(parse_deck(meta.deck_text, "deck"), meta.stage_index);
  EXPECT_EQ(replayed.stress_target.stage, 4);
  EXPECT_EQ(replayed.stress_target.stress, std::vector<double>(2, 10.0));
  EXPECT_EQ(replayed.contact_law.cohesion_force, 1.0);
  EXPECT_GT(replayed.contact_law.rolling_stiffness, 0.0);
  Configuration<2> c = read_configuration<2>(MPI_COMM_WORLD, old_file);
  c.meta.parameters = replayed;
  const auto with =
      test::scratch_dir("stiffness_old_file_np" + std::to_string(size_of())) / "with_parameters.h5";
  write_configuration<2>(MPI_COMM_WORLD, with, c);
  testing::internal::CaptureStderr();
  nlohmann::json a = run_stiffness(old_file), b = run_stiffness(with);
  const std::string said = testing::internal::GetCapturedStderr();
  if (rank_of() == 0) { // once, naming the file
    EXPECT_NE(said.find(old_file.string() + " has no /parameters"), std::string::npos) << said;
  }
  EXPECT_EQ(said.find("with_parameters.h5"), std::string::npos) << said;
  EXPECT_EQ(a["prescribed_stress_source"], "deck stage 4");
  for (auto* j : {&a, &b})
    j->erase("file"), j->erase("timings_seconds");
  if (size_of() == 1) {
    EXPECT_EQ(a, b);
    return;
  }
  // On 2 ranks the contacts come back in another row order, and the solvers' sums round
  // differently (the smallest eigenvalues vary in their last digits from run to run anyway).
  // The tensors' symmetry_deviation is a difference of nearly equal entries (1e-15 of them for
  // the symmetric K(1), 1e-6 with K(2)): it keeps only the last digits, and is compared
  // relative to the tensor instead (1e-9 of max |c|, as the entries themselves).
  a.erase("smallest_eigenvalues_over_mean_kn"), b.erase("smallest_eigenvalues_over_mean_kn");
  for (const char* tensor : {"/elastic_tensor", "/constitutive/elastic_tensor"}) {
    const nlohmann::json::json_pointer p(std::string(tensor) + "/symmetry_deviation");
    EXPECT_NEAR(a[p].get<double>(), b[p].get<double>(), 1e-9) << tensor;
    a[p] = b[p] = nullptr;
  }
  const auto fa = a.flatten(), fb = b.flatten();
  ASSERT_EQ(fa.size(), fb.size());
  for (const auto& [key, x] : fa.items()) {
    const auto& y = fb.at(key);
    if (x.is_number_float() && y.is_number_float())
      EXPECT_NEAR(x.get<double>(), y.get<double>(), 1e-9 * std::abs(x.get<double>())) << key;
    else
      EXPECT_EQ(x, y) << key;
  }
}
