// `granpack stiffness`: rigidity matrix, stiffness matrix, mechanisms, hyperstaticity and
// elastic moduli of a packing's backbone (docs/stiffness.md). The linear algebra lives in
// rigidity/; this file reads the packing, chains the steps and reports.
#include "granpack/app/stiffness.h"

#ifdef GRANPACK_HAVE_RIGIDITY // the executable reports NotImplemented without the layer

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>

#include "granpack/analysis/force_statistics.h"
#include "granpack/app/analysis_sections.h"
#include "granpack/app/stiffness_elastic_report.h"
#include "granpack/app/stiffness_krylov.h"
#include "granpack/app/stiffness_modes.h"
#include "granpack/comm/allgather.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/reduce.h"
#include "granpack/contact/derived_constants.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/io/report.h"
#include "granpack/packing/packing_view.h"
#include "granpack/rigidity/condensation.h"
#include "granpack/rigidity/mechanisms.h"
#include "granpack/rigidity/virtual_work.h"

namespace granpack {

namespace {

/// The stress the file's packing was equilibrated under: its stress target (the last compress
/// stage or pressure_steps level), on the axes it controlled; the measured elastic stress on
/// fixed axes and without a target. `source` says which.
template <int dim> Vec<dim> prescribed_stress(const PackingView<dim>& v, std::string& source) {
  Vec<dim> sigma = v.stress.diagonal();
  const StressTarget& t = v.stress_target;
  if (!t.set()) {
    source = "measured";
    return sigma;
  }
  bool any_fixed = false;
  for (int a = 0; a < dim; ++a) {
    if (t.fixed[a])
      any_fixed = true;
    else
      sigma[a] = t.stress[a];
  }
  source = "deck stage " + std::to_string(t.stage) + (any_fixed ? " (fixed axes measured)" : "");
  return sigma;
}

template <int dim> std::vector<GlobalId> gather_rattlers(const PackingView<dim>& v) {
  std::vector<GlobalId> mine;
  for (std::size_t i = 0; i < v.particles().n_owned(); ++i)
    if (v.rattler(i))
      mine.push_back(v.particles().id[i]);
  std::vector<GlobalId> all = allgather_concat(v.world, mine);
  std::sort(all.begin(), all.end());
  return all;
}

/// Z(5/3) over the backbone contacts ([AR] eq. 27), for eq. (30).
template <int dim> double z_five_thirds(const PackingView<dim>& v) {
  ForceMomentSums sums({5.0 / 3.0});
  for (const auto& c : v.contacts)
    if (on_backbone(v, c))
      sums.add(ContactForceSample{c.normal_force, 0, 0, 0, 0});
  global_sum_in_place(v.world, sums.sums());
  const double mean = sums.mean_normal_force();
  return sums.sums()[3] / sums.contacts() / std::pow(mean, 5.0 / 3.0);
}

/// Eigenvalues, ascending, of the symmetric part of the diagonal strains' Schur complement
/// ([AR]'s strain unknowns, on which the mechanisms are counted).
template <int dim> Vec<dim> schur_eigenvalues(const Moduli<dim>& m) {
  const Tensor<dim> c = m.diagonal_schur();
  return Eigen::SelfAdjointEigenSolver<Tensor<dim>>(0.5 * (c + c.transpose())).eigenvalues();
}

template <int dim> nlohmann::json moduli_json(const Moduli<dim>& m, bool valid) {
  if (!valid)
    return {{"bulk_modulus", nullptr},
            {"shear_modulus_diag", nullptr},
            {"c_diagonal_strains", nullptr},
            {"elastic_tensor", nullptr}};
  std::vector<std::vector<double>> c(dim, std::vector<double>(dim));
  for (int a = 0; a < dim; ++a)
    for (int b = 0; b < dim; ++b)
      c[a][b] = m.stiffness(a, b);
  return {{"bulk_modulus", m.bulk},
          {"shear_modulus_diag", m.shear_diag},
          {"c_diagonal_strains", c},
          {"elastic_tensor", elastic_tensor_json<dim>(m.tensor, m.affine)}};
}

/// What the factorisations give (docs/stiffness.md, "Mechanisms"): the counts, the inertia,
/// the smallest eigenvalues, and the moduli when the backbone is rigid.
template <int dim> struct DirectAnalysis {
  std::int64_t null_pivots = 0, negative_pivots = 0, k1_negative = 0;
  int strain_mechanisms = 0;
  bool rigid = false, positive_definite = false;
  std::vector<double> eigenvalues;
  std::vector<std::vector<GlobalId>> floppy; ///< grains of each unexpected mechanism
  std::optional<DirectSolver> ldl_k;         ///< inertia of K (frictionless)
  Moduli<dim> m1, m;
  std::int64_t gmres_iterations = 0;
  double cholesky_seconds = 0, eigen_seconds = 0;
};

/// Counts the strain mechanisms: the null space of the (symmetric part of the) diagonal
/// strains' Schur complement of the matrix whose null space is G's.
template <int dim> int count_strain_mechanisms(const Moduli<dim>& mm, double mean_kn) {
  const Vec<dim> mech_schur = schur_eigenvalues(mm);
  int strain_mechanisms = 0;
  for (int a = 0; a < dim; ++a)
    strain_mechanisms += mech_schur[a] < 1e-9 * mean_kn;
  return strain_mechanisms;
}

template <int dim>
DirectAnalysis<dim> direct_analysis(const PackingView<dim>& v, StiffnessSystem<dim>& s,
                                    const StiffnessOptions& opt, double volume) {
  DirectAnalysis<dim> d;
  const int g = s.grain_dofs();
  // Mechanisms: the null space of G, that of mechanism_matrix() (K(1), or ᵀG|𝒦|G with
  // distant pairs), whose factorisation counts the null pivots.
  BorderedMatrix<dim>& mech = s.mechanism_matrix();
  const DirectSolver chol = factorize(mech.uu, true, opt.null_pivot_threshold);
  d.cholesky_seconds = chol.seconds;
  d.null_pivots = chol.null_pivots;
  d.negative_pivots = chol.negative_pivots;
  const GrainSolve mech_solve = [&](::Vec b, ::Vec x) { chol.solve(b, x); };
  const Moduli<dim> mm = condense<dim>(mech, mech_solve, s.layout, volume, VoigtVec<dim>::Zero());
  d.strain_mechanisms = count_strain_mechanisms(mm, s.mean_kn);
  d.rigid = chol.null_pivots == 0 && chol.negative_pivots == 0 && d.strain_mechanisms == 0;
  // K(1) itself: the same factors without distant pairs, its own LDLᵀ (inertia) with them.
  std::optional<DirectSolver> own_k1;
  if (s.has_gram())
    own_k1 = factorize(s.k1.uu, true, opt.null_pivot_threshold);
  const DirectSolver& k1f = own_k1 ? *own_k1 : chol;
  // Inertia of K(1): the negative eigenvalues that distant pairs can bring. On a floppy
  // network the null pivots of a singular matrix come out with either sign, so the count is
  // taken on K(1) + 1e-9 <k_n> 1: what is counted lies below -1e-9 <k_n>. Without distant
  // pairs K(1) = ᵀG 𝒦 G with 𝒦 > 0 has none by construction.
  if (s.has_gram()) {
    OwnedMat shifted;
    GRANPACK_PETSC(MatDuplicate(s.k1.uu, MAT_COPY_VALUES, shifted.address()));
    GRANPACK_PETSC(MatShift(shifted, 1e-9 * s.mean_kn));
    d.k1_negative = factorize(shifted, true, 0.0).negative_pivots;
  }
  d.eigenvalues = smallest_eigenvalues(s.k1.uu, k1f, opt.eigenvalues, s.mean_kn, &d.eigen_seconds);
  if (opt.modes > 0)
    write_stiffness_modes(v, s, k1f, opt.modes, opt.modes_file.value());
  d.m1 = !own_k1 ? mm
                 : condense<dim>(
                       s.k1, [&](::Vec b, ::Vec x) { k1f.solve(b, x); }, s.layout, volume,
                       VoigtVec<dim>::Zero());
  d.positive_definite = d.rigid && k1f.null_pivots == 0 && k1f.negative_pivots == 0 &&
                        d.k1_negative == 0 && schur_eigenvalues(d.m1)[0] > 1e-9 * s.mean_kn &&
                        !d.eigenvalues.empty() && d.eigenvalues.front() > 0;
  // Unexpected mechanisms are named; the response of such a backbone is not computed.
  if (chol.null_pivots > 0)
    d.floppy =
        floppy_modes(mech.uu, s.numbering, g, s.mean_kn, int(chol.null_pivots) + 4, 1e-8, 1e-7);

  // Without friction K = K(1) + K(2) is symmetric (central forces): its inertia says whether
  // the prestress (K(2) is negative there, [AR] App. B) leaves the backbone stable.
  if (d.positive_definite) {
    if (!s.layout.rotations)
      d.ldl_k = factorize(s.k.uu, true, opt.null_pivot_threshold);
    // K = K(1) + K(2): GMRES preconditioned by the K(1) factors (no second factorisation).
    PreconditionedSolver gmres = krylov_with_factors(s.k.uu, k1f, 1e-13);
    d.m = condense<dim>(
        s.k, [&](::Vec b, ::Vec x) { gmres.solve(b, x); }, s.layout, volume,
        stress_to_voigt<dim>(v.stress));
    d.gmres_iterations = gmres.iterations;
  }
  return d;
}

/// Which path computes the moduli: the user's choice, or with `auto` the direct one up to
/// opt.krylov_above grain unknowns (the factorisation's memory grows as n^{4/3} in 3D:
/// 3.6 GB per rank for the 172 000 unknowns of D at n = 32 000).
struct SolverChoice {
  bool krylov = false;
  std::string reason;
};
SolverChoice choose_solver(const StiffnessOptions& opt, std::int64_t unknowns) {
  if (opt.solver == StiffnessSolver::kDirect)
    return {false, "requested (--solver direct)"};
  if (opt.solver == StiffnessSolver::kKrylov)
    return {true, "requested (--solver krylov)"};
  const bool big = unknowns > opt.krylov_above;
  return {big, "auto: " + std::to_string(unknowns) + " grain unknowns " +
                   (big ? "above " : "not above ") + std::to_string(opt.krylov_above)};
}

/// What the Krylov path does not compute (no factorisation: no pivots, no inertia, no
/// shift-and-invert), reported as null and listed under solver.not_computed.
const std::vector<std::string>& not_computed_by_krylov() {
  static const std::vector<std::string> keys = {
      "mechanisms",        "other_mechanisms",    "other_mechanism_grains",
      "null_pivots",       "negative_pivots",     "H",
      "H_over_Nf",         "isostatic",           "rigid",
      "positive_definite", "K1_negative_pivots",  "K_negative_pivots",
      "K_null_pivots",     "K_positive_definite", "smallest_eigenvalues_over_mean_kn",
      "gmres_iterations_K"};
  return keys;
}

template <int dim>
nlohmann::json stiffness(MPI_Comm world, const StiffnessOptions& opt, const FileMeta& meta) {
  const auto start = std::chrono::steady_clock::now();
  ensure_petsc_initialized();
  PackingView<dim> v = load_packing<dim>(world, opt.file, meta, opt.threshold, 1.5);
  const ContactLaw<dim>& law = v.law;
  const bool cohesive = law.cohesion.has_value();
  // With cohesion the whole interaction network is analysed ([GRC] sec. III): a contact at
  // h = h0 carries no force but has the stiffness K_N.
  if (cohesive)
    select_interaction_network(v);

  if (v.backbone.metrics.backbone_contacts == 0) // known on every rank (a global count)
    throw InputError(opt.file.string() +
                     (cohesive ? std::string(": no interaction between grains")
                               : ": no force-carrying contact (N > " +
                                     std::to_string(opt.threshold) + " a^2 P)") +
                     ": there is no backbone to analyse");
  StiffnessSystem<dim> s = assemble_stiffness(v, law);
  const int g = s.grain_dofs();
  const double volume = v.system.cell.volume();
  std::string stress_source;
  const Vec<dim> sigma = prescribed_stress(v, stress_source);
  // With cohesion the forces are of order F0 whatever the pressure (0 at P* = 0): the
  // residual is relative to the contact forces then.
  const VirtualWork vw = check_virtual_work(s, sigma, volume, cohesive);

  const KnownMechanisms km = remove_known_mechanisms(s);
  const std::int64_t n_star = s.numbering.grains;
  const SolverChoice choice = choose_solver(opt, n_star * g);
  if (choice.krylov && opt.modes > 0) // known on every rank: global counts
    throw InputError("stiffness: --modes needs the direct solver (" + choice.reason +
                     "); run with --solver direct");

  std::optional<DirectAnalysis<dim>> direct;
  std::optional<KrylovModuli<dim>> krylov;
  if (choice.krylov)
    krylov = krylov_moduli<dim>(v, s, stress_to_voigt<dim>(v.stress), opt.krylov_rtol,
                                opt.krylov_max_iterations);
  else
    direct = direct_analysis(v, s, opt, volume);
  // Without a factorisation the strain mechanisms still come from the Schur complement of
  // K(1) (the Krylov path condenses it too); the unexpected ones are not counted.
  const int strain_mechanisms =
      direct ? direct->strain_mechanisms : count_strain_mechanisms(krylov->k1, s.mean_kn);
  const bool moduli_valid = direct ? direct->positive_definite : krylov->converged;
  const Moduli<dim>& m = direct ? direct->m : krylov->k;
  const Moduli<dim>& m1 = direct ? direct->m1 : krylov->k1;

  // Counts, eq. (19)-(20).
  const std::int64_t other =
      direct && direct->null_pivots > 0 ? std::int64_t(direct->floppy.size()) : 0;
  const std::int64_t k = dim + std::int64_t(km.divalent.size()) + std::int64_t(km.pivoting.size()) +
                         other + strain_mechanisms;
  const std::int64_t nf = s.dof();
  const std::int64_t h = s.rows + k - nf;
  const Hyperstaticity eq37 =
      hyperstaticity<dim>(s.contacts, n_star, std::int64_t(km.divalent.size()), s.layout.rotations);
  const std::vector<GlobalId> rattlers = gather_rattlers(v);

  nlohmann::json j = packing_summary(v, opt.file);
  j["force_threshold"] = v.force_threshold;
  j["backbone_grains"] = n_star;
  j["backbone_contacts"] = s.contacts;
  j["rattlers"] = std::int64_t(rattlers.size());
  j["detached_clusters"] =
      v.detached_clusters; // interaction network only: not in the largest cluster
  j["detached_grains"] = v.detached_grains;
  j["grain_dofs"] = g;
  j["N_f"] = nf;
  j["G_rows"] = s.rows;
  j["network"] = cohesive ? "interactions" : "backbone";
  j["distant_pairs"] = s.distant;
  j["rolling_rows"] = s.layout.rolling;
  // [GRC]'s names for the same count N_f + H = M + k: eq. (19) with friction, (21) with
  // rolling resistance, (22) without friction.
  j["H_relation"] = !cohesive ? (s.layout.rotations ? "AR eq. 19" : "AR eq. 19 (normal rows)")
                    : !s.layout.rotations ? "GRC eq. 22"
                    : s.layout.rolling    ? "GRC eq. 21"
                                          : "GRC eq. 19";
  j["mechanisms"] = k;
  j["trivial_mechanisms"] = dim;
  j["divalent_mechanisms"] = std::int64_t(km.divalent.size());
  j["pivoting_mechanisms"] = std::int64_t(km.pivoting.size());
  j["other_mechanisms"] = other;
  j["strain_mechanisms"] = strain_mechanisms;
  j["rattler_mechanisms"] = std::int64_t(rattlers.size()) * g;
  nlohmann::json div = nlohmann::json::array();
  for (const auto& d : km.divalent)
    div.push_back({{"grain", d.grain}, {"neighbours", {d.neighbours[0], d.neighbours[1]}}});
  j["divalent_grains"] = div;
  nlohmann::json piv = nlohmann::json::array();
  for (const auto& d : km.pivoting)
    piv.push_back(
        {{"grain", d.grain}, {"neighbour", d.neighbours[0]}, {"grains", d.neighbours[1]}});
  j["pivoting_grains"] = piv;
  j["pivoting_mode_residual"] = km.pivoting_residual;
  j["rattler_grains"] = rattlers;
  j["divalent_mode_residual"] = km.divalent_residual;
  j["pinned_grain"] = km.pinned_grain;
  j["modes_file"] = opt.modes > 0 ? nlohmann::json(opt.modes_file->string()) : nlohmann::json();
  j["H"] = h;
  j["H_over_Nf"] = double(h) / double(n_star * g);
  // Eq. (37) is [AR]'s count for backbones without cohesion or rolling resistance.
  j["H_eq37"] = cohesive || s.layout.rolling ? nlohmann::json() : nlohmann::json(eq37.degree);
  j["H_over_Nf_eq37"] =
      cohesive || s.layout.rolling ? nlohmann::json() : nlohmann::json(eq37.per_dof);
  j["isostatic"] = h == 0 && k == dim;
  j["K_negative_pivots"] = j["K_null_pivots"] = j["K_positive_definite"] = nullptr;
  if (direct) {
    j["other_mechanism_grains"] = direct->floppy;
    j["null_pivots"] = direct->null_pivots;
    j["negative_pivots"] = direct->negative_pivots;
    j["smallest_eigenvalues_over_mean_kn"] = direct->eigenvalues;
    j["positive_definite"] = direct->positive_definite;
    j["rigid"] = direct->rigid;
    j["K1_negative_pivots"] = direct->k1_negative;
    if (direct->ldl_k) {
      j["K_negative_pivots"] = direct->ldl_k->negative_pivots;
      j["K_null_pivots"] = direct->ldl_k->null_pivots;
      j["K_positive_definite"] =
          direct->ldl_k->negative_pivots == 0 && direct->ldl_k->null_pivots == 0;
    }
    j["gmres_iterations_K"] = direct->gmres_iterations;
  }
  j["virtual_work_residual"] = vw.residual;
  j["virtual_work_reference"] = cohesive ? "|f| (contact forces)" : "|F_ext|";
  j["virtual_work_grain_residual"] = vw.grain_residual;
  j["max_net_grain_force"] = vw.max_grain_force;
  j["prescribed_stress_source"] = stress_source;
  std::vector<double> sig(sigma.data(), sigma.data() + dim),
      sig_f(vw.stress_from_forces.data(), vw.stress_from_forces.data() + dim);
  j["prescribed_stress"] = sig;
  j["stress_from_forces"] = sig_f;
  j["mean_kn"] = s.mean_kn;
  j["solver"] = {{"requested", opt.solver == StiffnessSolver::kDirect   ? "direct"
                               : opt.solver == StiffnessSolver::kKrylov ? "krylov"
                                                                        : "auto"},
                 {"path", choice.krylov ? "krylov" : "direct"},
                 {"reason", choice.reason},
                 {"grain_unknowns", n_star * g},
                 {"krylov", krylov ? krylov->report : nlohmann::json()},
                 {"not_computed", choice.krylov ? nlohmann::json(not_computed_by_krylov())
                                                : nlohmann::json::array()}};
  if (krylov) // null, not a count that would look like a result
    for (const auto& key : not_computed_by_krylov())
      j[key] = nullptr;

  // With an unexpected mechanism the response is not defined: the moduli are null. On the
  // Krylov path: with a solve that stopped short of its tolerance.
  j["moduli_valid"] = moduli_valid;
  j.update(moduli_json(m, moduli_valid));
  j["constitutive"] = moduli_json(m1, moduli_valid);
  // eq. (30), Hertz monodisperse 3D only: the packing's own z = 2 N_c*/n, Phi and Z(5/3).
  const auto& mat = v.contact_law;
  const double z = 2.0 * double(s.contacts) / double(v.n);
  const double z53 = z_five_thirds(v);
  j["z"] = z;
  j["Z_5_3"] = z53;
  if (dim == 3 && mat.normal == NormalLawKind::kHertz &&
      v.deck.sample.distribution == "monodisperse") {
    const double e_tilde = e_tilde_of(mat.young_modulus, mat.poisson_ratio);
    const double b30 = 1.0 / (2.0 * z53) *
                       std::pow(z * v.phi / (3.0 * std::numbers::pi), 2.0 / 3.0) *
                       std::pow(e_tilde, 2.0 / 3.0) * std::cbrt(v.pressure);
    j["bulk_modulus_eq30"] = b30;
    j["bulk_modulus_over_eq30"] = moduli_valid ? nlohmann::json(m.bulk / b30) : nlohmann::json();
    j["bulk_modulus_reduced"] =
        moduli_valid
            ? nlohmann::json(m.bulk / (std::pow(e_tilde, 2.0 / 3.0) * std::cbrt(v.pressure)))
            : nlohmann::json();
  } else {
    j["bulk_modulus_eq30"] = nullptr;
  }
  const int size = size_of(world);
  j["ranks"] = size;
  j["partition"] = {{"method", s.numbering.metis ? "metis" : "none (one rank)"},
                    {"edge_cut_metis", s.numbering.edge_cut_metis},
                    {"edge_cut_spatial", s.numbering.edge_cut_spatial}};
  const auto krylov_seconds = [&](const char* matrix) {
    if (!krylov || !krylov->report.contains(matrix))
      return 0.0;
    const nlohmann::json& r = krylov->report[matrix];
    return r["setup_seconds"].template get<double>() + r["solve_seconds"].template get<double>();
  };
  j["timings_seconds"] = {
      {"assembly", s.assembly_seconds},
      {"cholesky_K1", direct ? direct->cholesky_seconds : 0.0},
      {"eigensolve", direct ? direct->eigen_seconds : 0.0},
      {"condensation_K1", m1.seconds},
      {"condensation_K_gmres", direct ? m.seconds : 0.0},
      {"ldlt_K", direct && direct->ldl_k ? direct->ldl_k->seconds : 0.0},
      {"krylov_K1", krylov_seconds("K1")},
      {"krylov_K", krylov_seconds("K")},
      {"total", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()}};
  return j;
}

std::string fixed(const nlohmann::json& v) {
  if (v.is_null())
    return "-";
  char b[40];
  std::snprintf(b, sizeof b, "%.6g", v.get<double>());
  return b;
}
std::string count(const nlohmann::json& v) {
  return v.is_null() ? "-" : std::to_string(v.get<long long>());
}

/// The moduli's solver: the path, why, and on the Krylov path each matrix's method, largest
/// iteration count and true residual over its solves, and what was not computed.
std::vector<std::pair<std::string, std::string>> solver_lines(const nlohmann::json& solver) {
  std::vector<std::pair<std::string, std::string>> lines = {
      {"moduli solver",
       solver["path"].get<std::string>() + " (" + solver["reason"].get<std::string>() + ")"}};
  const auto& k = solver["krylov"];
  if (k.is_null())
    return lines;
  for (const char* matrix : {"K1", "K"}) {
    if (!k.contains(matrix))
      continue;
    const auto& r = k[matrix];
    long long its = 0;
    double res = 0;
    for (const auto& i : r["iterations"])
      its = std::max(its, i.get<long long>());
    for (const auto& x : r["residuals"])
      res = std::max(res, x.get<double>());
    lines.emplace_back(std::string("  ") + (matrix[1] == '1' ? "K(1)" : "K(1)+K(2)") + ": " +
                           r["method"].get<std::string>() + ", " +
                           r["preconditioner"].get<std::string>(),
                       std::to_string(r["iterations"].size()) + " solves, max " +
                           std::to_string(its) + " its, max |r|/|b| " + fixed(res) +
                           (r["converged"].get<bool>() ? "" : " NOT CONVERGED"));
  }
  std::string skipped;
  for (const auto& key : solver["not_computed"])
    skipped += (skipped.empty() ? "" : ", ") + key.get<std::string>();
  lines.emplace_back("  not computed (no factorisation)", skipped);
  return lines;
}
std::string yes_no(const nlohmann::json& v) {
  return v.is_null() ? "-" : v.get<bool>() ? "yes" : "no";
}

/// The readable summary rank 0 prints: (label, value) lines.
std::string table(const nlohmann::json& j) {
  const auto& t = j["timings_seconds"];
  const auto& part = j["partition"];
  std::string eig;
  for (const auto& e : j["smallest_eigenvalues_over_mean_kn"])
    eig += fixed(e) + " ";
  const std::vector<std::pair<std::string, std::string>> lines = {
      {"dimension, n, ranks",
       count(j["dimension"]) + ", " + count(j["n"]) + ", " + count(j["ranks"])},
      {"friction mu", j["friction"].dump()},
      {"backbone grains, contacts",
       count(j["backbone_grains"]) + ", " + count(j["backbone_contacts"])},
      {"network", j["network"].get<std::string>() + " (distant pairs " + count(j["distant_pairs"]) +
                      (j["rolling_rows"].get<bool>() ? ", rolling rows)" : ")")},
      {"N_f, rows of G", count(j["N_f"]) + ", " + count(j["G_rows"])},
      {"virtual work |tG f - F|/|F|", fixed(j["virtual_work_residual"]) + " (grain rows " +
                                          fixed(j["virtual_work_grain_residual"]) + ", Sigma: " +
                                          j["prescribed_stress_source"].get<std::string>() + ")"},
      {"mechanisms k", count(j["mechanisms"]) + " = " + count(j["trivial_mechanisms"]) +
                           " trivial + " + count(j["divalent_mechanisms"]) + " divalent + " +
                           count(j["pivoting_mechanisms"]) + " pivoting + " +
                           count(j["other_mechanisms"]) + " other + " +
                           count(j["strain_mechanisms"]) + " strain"},
      {"rattlers (not in G), their dofs",
       count(j["rattlers"]) + ", " + count(j["rattler_mechanisms"]) +
           (j["network"] == "interactions"
                ? " (" + count(j["detached_grains"]) + " in " + count(j["detached_clusters"]) +
                      " detached clusters)"
                : std::string())},
      {"divalent, pivoting |K1 v|/(<k_n>|v|)",
       fixed(j["divalent_mode_residual"]) + ", " + fixed(j["pivoting_mode_residual"])},
      {"smallest eig. (stiffened)/<k_n>", eig},
      {"rigid (only trivial/divalent/pivoting)", yes_no(j["rigid"])},
      {"K(1) positive definite (stiffened)", yes_no(j["positive_definite"]) + " (negative pivots " +
                                                 count(j["K1_negative_pivots"]) + ")"},
      {"K(1)+K(2) positive definite", yes_no(j["K_positive_definite"])},
      {"H (N_f + H = M + k), H/N_f*", count(j["H"]) + ", " + fixed(j["H_over_Nf"]) + " (" +
                                          j["H_relation"].get<std::string>() + ")"},
      {"H, H/N_f* from counts (eq. 37)", fixed(j["H_eq37"]) + ", " + fixed(j["H_over_Nf_eq37"])},
      {"isostatic", yes_no(j["isostatic"])},
      {"bulk modulus B (K1+K2) / Pa", fixed(j["bulk_modulus"])},
      {"B from K1 only / Pa", fixed(j["constitutive"]["bulk_modulus"])},
      {"B eq. (30) / Pa, B / B(30)",
       fixed(j["bulk_modulus_eq30"]) + ", " +
           fixed(j.value("bulk_modulus_over_eq30", nlohmann::json()))},
      {"shear modulus (diag. strains) / Pa", fixed(j["shear_modulus_diag"]) + " (K1 only " +
                                                 fixed(j["constitutive"]["shear_modulus_diag"]) +
                                                 ")"},
      {"edge cut: METIS / spatial",
       count(part["edge_cut_metis"]) + " / " + count(part["edge_cut_spatial"])},
      {"time: assembly, Cholesky, eig (s)",
       fixed(t["assembly"]) + ", " + fixed(t["cholesky_K1"]) + ", " + fixed(t["eigensolve"])},
      {"time: condense K1, K (GMRES its)", fixed(t["condensation_K1"]) + ", " +
                                               fixed(t["condensation_K_gmres"]) + " (" +
                                               count(j["gmres_iterations_K"]) + ")"},
      {"time: Krylov K1, K; total (s)",
       fixed(t["krylov_K1"]) + ", " + fixed(t["krylov_K"]) + "; " + fixed(t["total"])},
  };
  std::vector<std::pair<std::string, std::string>> all = lines;
  const auto solver = solver_lines(j["solver"]);
  all.insert(all.begin() + 1, solver.begin(), solver.end());
  // The tensor's lines after the diagonal-strain moduli.
  const auto shear = std::find_if(all.begin(), all.end(), [](const auto& line) {
    return line.first.starts_with("shear modulus");
  });
  const auto tensor = elastic_tensor_lines(j["elastic_tensor"]);
  all.insert(shear + 1, tensor.begin(), tensor.end());
  const auto& other = j["other_mechanism_grains"];
  for (std::size_t k = 0; k < other.size() && k < 5; ++k) {
    std::string ids;
    for (const auto& id : other[k])
      ids += count(id) + " ";
    all.emplace_back("  other mechanism " + std::to_string(k + 1) + ": grains", ids);
  }
  std::string out = "granpack stiffness: " + j["file"].get<std::string>() + "\n";
  for (const auto& [label, value] : all) {
    out += "  " + label;
    out.append(label.size() < 36 ? 36 - label.size() : 1, ' ');
    out += value + "\n";
  }
  return out;
}

} // namespace

std::string stiffness_file(MPI_Comm world, const StiffnessOptions& options) {
  const FileMeta meta = read_file_meta(world, options.file);
  nlohmann::json j =
      meta.dimension == 3 ? stiffness<3>(world, options, meta) : stiffness<2>(world, options, meta);
  const int rank = rank_of(world);
  if (rank == 0) {
    std::cout << table(j);
    if (options.json)
      write_text_atomically(*options.json, j.dump(2) + "\n");
  }
  return j.dump();
}

} // namespace granpack

#endif // GRANPACK_HAVE_RIGIDITY
