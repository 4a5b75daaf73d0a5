// `granpack stiffness` (app/stiffness.h) against closed forms and dense references:
//  - the Hertz FCC crystal: only the trivial translations, H from eq. (19) exactly, and the
//    bulk modulus of the crystal derived in docs/stiffness.md;
//  - small disordered packings (n = 108, frictional and frictionless): the mechanism count,
//    H and the bulk moduli equal a dense Eigen computation (SVD of G, pseudo-inverse /
//    dense LU for the condensation) on 1 and 2 ranks.
#include <gtest/gtest.h>
#include <mpi.h>

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "mpi_world.h"
#include "granpack/analysis/rigidity_blocks.h"
#include "granpack/app/packing_view.h"
#include "granpack/app/stiffness.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/prep/material_law.h"
#include "granpack/prep/run_deck.h"
#include "granpack/rigidity/stiffness_system.h"
#include "test_paths.h"

using namespace granpack;

namespace {

int rank_of() { return test::world_rank(); }
int size_of() { return test::world_size(); }

nlohmann::json run_stiffness(const std::filesystem::path& file, double threshold = 1e-4) {
  StiffnessOptions o;
  o.file = file;
  o.threshold = threshold;
  testing::internal::CaptureStdout();
  const auto j = nlohmann::json::parse(stiffness_file(MPI_COMM_WORLD, o));
  testing::internal::GetCapturedStdout();
  return j;
}

/// Runs a deck (text) into a scratch directory; returns final.h5.
std::filesystem::path run_text_deck(const std::string& tag, const std::string& text) {
  const auto dir = test::scratch_dir(tag + "_np" + std::to_string(size_of()));
  if (rank_of() == 0) std::ofstream(dir / "deck.toml") << text;
  MPI_Barrier(MPI_COMM_WORLD);
  RunOptions opt;
  opt.deck = dir / "deck.toml";
  opt.output_dir = dir / "out";
  opt.quiet = true;
  EXPECT_EQ(run_deck(MPI_COMM_WORLD, opt), 0);
  return dir / "out" / "final.h5";
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
)" + std::string(mu > 0 ? "" : "distribution = \"uniform\"\nmin_diameter_ratio = 0.8\n") + R"(
[material]
density = 2500.0
normal_law = "hertz"
young_modulus = 2.88e8
poisson_ratio = 0.3
friction = )" + std::to_string(mu) + R"(
damping = 0.98

[output]
log_every = 100000

)" + std::string(mu > 0 ? "[[stage]]\nkind = \"lattice\"\nlattice = \"fcc\"\nphi = 0.45\ncells = [3, 3, 3]\n"
                         : "[[stage]]\nkind = \"random\"\nphi = 0.35\n") + R"(
[[stage]]
kind = "ed_gas"
collisions_per_grain = 50

[[stage]]
kind = "compress"
pressure = 1.0e4
inertia_max = 1.0e-2
)";
}

struct Dense {
  std::int64_t mechanisms = 0, rows = 0, dof = 0;
  double bulk_k1 = 0, bulk = 0, smallest_kept_singular = 0, largest_dropped_singular = 0;
};

/// The dense reference, on rank 0 alone: the same per-contact kernels, assembled into full
/// Eigen matrices, with an SVD for the rank of G and dense linear algebra for B.
Dense dense_reference(const std::filesystem::path& file, const nlohmann::json& j, double threshold) {
  const FileMeta meta = read_file_meta(MPI_COMM_SELF, file);
  const PackingView<3> v = load_packing<3>(MPI_COMM_SELF, file, meta, threshold, 1.5);
  MaterialSpec mat = v.deck.material;
  mat.friction = v.friction;
  const ContactLaw<3> law = contact_law_of<3>(mat);
  RigidityLayout<3> l;
  l.rotations = v.friction > 0;
  l.ell = 0.5 * v.diameter;
  l.cell = v.system.cell.length;
  const auto& p = v.particles();
  std::map<GlobalId, int> index;
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    if (!v.rattler(i)) index.emplace(p.id[i], 0);
  int next = 0;
  for (auto& [id, k] : index) k = next++;
  const int g = l.grain_dofs(), rc = l.rows_per_contact();
  const int nf = next * g + 3;
  std::vector<RigidityContact<3>> cs;
  std::vector<std::pair<int, int>> ends;
  for (const auto& c : v.contacts) {
    if (!on_backbone(v, c)) continue;
    RigidityContact<3> x;
    x.geometry = make_pair_geometry<3>(p.radius[c.i], p.radius[c.j], p.mass[c.i], p.mass[c.j], c.branch);
    x.normal_force = c.normal_force;
    if (l.rotations)
      x.tangential_force = c.tangential_force - c.tangential_force.dot(x.geometry.normal) * x.geometry.normal;
    ContactState<3> st;
    x.stiffness = law.stiffness(x.geometry, st);
    cs.push_back(x);
    ends.emplace_back(index.at(p.id[c.i]), index.at(p.id[c.j]));
  }
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(rc * cs.size(), nf), K1 = Eigen::MatrixXd::Zero(nf, nf);
  Eigen::MatrixXd K = K1;
  double kbar = 0;
  
  for (std::size_t c = 0; c < cs.size(); ++c) {
    std::vector<int> dofs;
    for (int d = 0; d < g; ++d) dofs.push_back(ends[c].first * g + d);
    for (int d = 0; d < g; ++d) dofs.push_back(ends[c].second * g + d);
    for (int a = 0; a < 3; ++a) dofs.push_back(next * g + a);
    const DynMatrix rows = rigidity_rows(cs[c], l);
    const DynMatrix k1 = constitutive_block(cs[c], l), k = k1 + geometric_block(cs[c], l);
    for (std::size_t a = 0; a < dofs.size(); ++a) {
      for (int r = 0; r < rc; ++r) G(rc * c + r, dofs[a]) += rows(r, a);
      for (std::size_t b = 0; b < dofs.size(); ++b) K1(dofs[a], dofs[b]) += k1(a, b), K(dofs[a], dofs[b]) += k(a, b);
    }
    kbar += cs[c].stiffness.k_n;
  }
  kbar /= double(cs.size());
  Dense out;
  out.rows = G.rows();
  out.dof = nf;
  Eigen::BDCSVD<Eigen::MatrixXd> svd(G);
  const auto& sv = svd.singularValues();
  std::int64_t rank = 0;
  out.smallest_kept_singular = sv[0];
  for (int k = 0; k < sv.size(); ++k) {
    if (sv[k] > 1e-9 * sv[0]) ++rank, out.smallest_kept_singular = sv[k];
    else out.largest_dropped_singular = std::max(out.largest_dropped_singular, sv[k]);
  }
  out.mechanisms = nf - rank;
  if (!j["moduli_valid"].get<bool>()) return out;  // floppy: no response to compare

  const int nu = next * g;
  auto bulk_of = [&](const Eigen::Matrix3d& schur, bool with_stress) {
    const Eigen::Matrix3d kc = l.cell.asDiagonal() * schur * l.cell.asDiagonal();
    Eigen::Matrix3d c = kc / v.system.cell.volume();
    if (with_stress)
      for (int a = 0; a < 3; ++a) c.row(a).array() += v.stress(a, a);
    return c.sum() / 9.0;
  };
  // K(1): the grain block's pseudo-inverse (the border lies in its range, K1 = ᵀG 𝒦 G).
  {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(K1.topLeftCorner(nu, nu));
    const auto& lam = es.eigenvalues();
    Eigen::VectorXd inv = Eigen::VectorXd::Zero(nu);
    for (int k = 0; k < nu; ++k)
      if (lam[k] > 1e-10 * lam[nu - 1]) inv[k] = 1.0 / lam[k];
    const Eigen::MatrixXd pinv = es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
    const Eigen::Matrix3d schur = K1.bottomRightCorner(3, 3) - K1.bottomLeftCorner(3, nu) * pinv * K1.topRightCorner(nu, 3);
    out.bulk_k1 = bulk_of(schur, false);
  }
  // K: the same pinned grain and stiffened rolling modes as the distributed code, dense LU.
  {
    for (const auto& d : j["divalent_grains"]) {
      const int gi = index.at(d["grain"].get<GlobalId>());
      std::vector<granpack::Vec<3>> pts;
      for (std::size_t c = 0; c < cs.size(); ++c) {
        if (ends[c].first == gi) pts.push_back(cs[c].geometry.branch_i());
        if (ends[c].second == gi) pts.push_back(cs[c].geometry.branch_j());
      }
      EXPECT_EQ(pts.size(), 2u);
      const auto vmode = divalent_rolling_mode(pts[0], pts[1], l.ell);
      K.block(gi * g, gi * g, 6, 6) += kbar * vmode * vmode.transpose();
    }
    const int pin = index.at(j["pinned_grain"].get<GlobalId>());
    for (int a = 0; a < 3; ++a) {
      K.row(pin * g + a).setZero();
      K.col(pin * g + a).setZero();
      K(pin * g + a, pin * g + a) = kbar;
    }
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(K.topLeftCorner(nu, nu));
    const Eigen::Matrix3d schur = K.bottomRightCorner(3, 3) - K.bottomLeftCorner(3, nu) * lu.solve(K.topRightCorner(nu, 3));
    out.bulk = bulk_of(schur, true);
  }
  return out;
}

void compare_with_dense(const std::string& tag, double mu) {
  const auto file = run_text_deck(tag, small_deck(mu));
  const auto j = run_stiffness(file);
  EXPECT_TRUE(j["positive_definite"].get<bool>());
  EXPECT_LT(j["virtual_work_residual"].get<double>(), 1e-3);
  if (mu > 0) {
    EXPECT_EQ(j["divalent_mechanisms"], 1);  // the case this deck is chosen for
  }
  // A threshold of 0.3 a^2 P (0.2 without friction) drops the weak contacts: the backbone
  // left is floppy, and the unexpected mechanisms are counted by SLEPc (this tests that path
  // against the SVD too).
  const double floppy_threshold = mu > 0 ? 0.3 : 0.2;
  const auto floppy = run_stiffness(file, floppy_threshold);
  EXPECT_FALSE(floppy["positive_definite"].get<bool>());
  EXPECT_GT(floppy["other_mechanisms"].get<std::int64_t>(), 0);
  EXPECT_EQ(floppy["other_mechanism_grains"].size(), floppy["other_mechanisms"].get<std::size_t>());
  EXPECT_TRUE(floppy["bulk_modulus"].is_null());
  if (rank_of() != 0) return;
  for (const auto& [json, threshold] : {std::pair{&j, 1e-4}, std::pair{&floppy, floppy_threshold}}) {
    const Dense d = dense_reference(file, *json, threshold);
    // The rank decision is clear-cut: a wide gap between kept and dropped singular values.
    EXPECT_LT(d.largest_dropped_singular, 1e-12 * d.smallest_kept_singular);
    EXPECT_EQ((*json)["N_f"].get<std::int64_t>(), d.dof);
    EXPECT_EQ((*json)["mechanisms"].get<std::int64_t>(), d.mechanisms) << "threshold " << threshold;
    EXPECT_EQ((*json)["H"].get<std::int64_t>(), d.rows + d.mechanisms - d.dof);
    std::printf("[ stiffness ] %s, threshold %g: k = %lld (dense %lld), H = %lld\n", tag.c_str(), threshold,
                (long long)(*json)["mechanisms"].get<std::int64_t>(), (long long)d.mechanisms,
                (long long)(*json)["H"].get<std::int64_t>());
    if (!(*json)["moduli_valid"].get<bool>()) continue;
    EXPECT_NEAR((*json)["constitutive"]["bulk_modulus"].get<double>(), d.bulk_k1, 1e-8 * d.bulk_k1);
    EXPECT_NEAR((*json)["bulk_modulus"].get<double>(), d.bulk, 1e-8 * d.bulk);
    std::printf("[ stiffness ] %s: B = %.10g (dense %.10g), B1 = %.10g (dense %.10g)\n", tag.c_str(),
                (*json)["bulk_modulus"].get<double>(), d.bulk, (*json)["constitutive"]["bulk_modulus"].get<double>(),
                d.bulk_k1);
  }
}

}  // namespace

TEST(Stiffness, SmallFrictionalPackingMatchesDense) { compare_with_dense("stiffness_small_mu03", 0.3); }
TEST(Stiffness, SmallFrictionlessPackingMatchesDense) { compare_with_dense("stiffness_small_mu0", 0.0); }

TEST(Stiffness, HertzFccCrystal) {
  const auto out = test::scratch_dir("stiffness_fcc_np" + std::to_string(size_of()));
  RunOptions opt;
  opt.deck = test::source_dir() / "jobs/decks/ci/fcc_hertz.toml";
  opt.output_dir = out;
  opt.quiet = true;
  ASSERT_EQ(run_deck(MPI_COMM_WORLD, opt), 0);
  const auto j = run_stiffness(out / "final.h5");
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
    std::printf("[ stiffness ] FCC: B = %.10g Pa (analytic %.10g), B(1) = %.10g (analytic %.10g), P = %.8g\n",
                j["bulk_modulus"].get<double>(), b, j["constitutive"]["bulk_modulus"].get<double>(), b1, p);
}
