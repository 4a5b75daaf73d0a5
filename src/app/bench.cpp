// `granpack bench` (docs/performance.md): the reference problem of issue 8, timed.
//
// 1. read a 3D packing written by granpack (any rank count) and replicate it kx x ky x kz
//    times: the copies of a periodic packing tile the larger cell exactly, so the result is
//    the same equilibrated packing (same Φ, contacts and pressure), n·kx·ky·kz grains;
// 2. drop the stored contact histories (both codes then start from the same state: LAMMPS
//    cannot read them), evaluate the static forces with the grains at rest (the cross-check
//    with LAMMPS) and the typical overlap, from the mean elastic normal force;
// 3. give every grain a small Gaussian velocity drawn from its global id (independent of the
//    rank count), so contacts slide, open and close during the run;
// 4. time `steps` velocity-Verlet steps at fixed volume, dt = fraction x contact time at
//    the typical overlap, and report particle-steps/s per rank, the phase breakdown of the
//    MD engine's timers and the memory per grain.
#include "granpack/app/bench.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>

#include "granpack/comm/barrier.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/gather.h"
#include "granpack/comm/migration.h"
#include "granpack/comm/reduce.h"
#include "granpack/contact/collision_times.h"
#include "granpack/contact/derived_constants.h"
#include "granpack/contact/normal_elasticity.h"
#include "granpack/core/error.h"
#include "granpack/engine/material_law.h"
#include "granpack/engine/md_engine.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/io/log.h"

namespace granpack {

namespace {

double resident_bytes() {
  std::ifstream f("/proc/self/statm");
  long pages = 0, resident = 0;
  f >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE));
}

double peak_resident_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) * 1024.0;
}

/// splitmix64: a counter-based generator, so a grain's draw depends only on (seed, id, k).
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}
double uniform01(std::uint64_t key) {
  return (static_cast<double>(mix(key) >> 11) + 0.5) * 0x1.0p-53;
}
/// Standard normal number k of grain `id` (Box-Muller).
double gaussian(std::uint64_t seed, GlobalId id, int k) {
  const std::uint64_t base = mix(seed ^ mix(static_cast<std::uint64_t>(id))) + 2 * std::uint64_t(k);
  const double u1 = uniform01(base), u2 = uniform01(base + 1);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

/// The grains of `in` (this rank's slice) copied rep[a] times along each axis.
ParticleStore<3> replicate(const ParticleStore<3>& in, const std::array<int, 3>& rep) {
  ParticleStore<3> out;
  const GlobalId copies = GlobalId(rep[0]) * rep[1] * rep[2];
  out.reserve(in.n_owned() * std::size_t(copies));
  for (int cx = 0; cx < rep[0]; ++cx)
    for (int cy = 0; cy < rep[1]; ++cy)
      for (int cz = 0; cz < rep[2]; ++cz) {
        const GlobalId copy = (GlobalId(cx) * rep[1] + cy) * rep[2] + cz;
        const Vec<3> shift(cx, cy, cz), k(rep[0], rep[1], rep[2]);
        for (std::size_t i = 0; i < in.n_owned(); ++i) {
          Particle<3> g = in.get(i);
          // Interleaved ids (id x copies + copy), not blocks (id + copy x n): with blocks,
          // every pair across a copy boundary would have its smaller id in the lower copy,
          // and the smaller id's rank computes a pair, so the lower rank would take all the
          // pairs across the cut. Interleaved, ids stay as uncorrelated with position as in
          // a packing grown from a gas.
          g.id = g.id * copies + copy;
          g.position = (Cell<3>::wrap(g.position) + shift).cwiseQuotient(k);
          out.add_owned(g);
        }
      }
  return out;
}

void write_lammps_data(const std::filesystem::path& path, const std::vector<Particle<3>>& grains,
                       const Cell<3>& cell, double density) {
  std::ofstream f(path);
  GRANPACK_CHECK(f, "bench: cannot write " << path.string());
  char buf[512];
  f << "LAMMPS data file: granpack bench export (atom_style sphere, SI units; id = granpack id + "
       "1)\n\n";
  f << grains.size() << " atoms\n1 atom types\n\n";
  const char* ax[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    std::snprintf(buf, sizeof buf, "0 %.17g %slo %shi\n", cell.length[a], ax[a], ax[a]);
    f << buf;
  }
  f << "\nAtoms # sphere\n\n";
  for (const auto& g : grains) {
    const Vec<3> r = cell.to_real(Cell<3>::wrap(g.position));
    std::snprintf(buf, sizeof buf, "%lld 1 %.17g %.17g %.17g %.17g %.17g\n",
                  static_cast<long long>(g.id + 1), 2 * g.radius, density, r[0], r[1], r[2]);
    f << buf;
  }
  f << "\nVelocities\n\n";
  for (const auto& g : grains) {
    std::snprintf(buf, sizeof buf, "%lld %.17g %.17g %.17g %.17g %.17g %.17g\n",
                  static_cast<long long>(g.id + 1), g.velocity[0], g.velocity[1], g.velocity[2],
                  g.angular_velocity[0], g.angular_velocity[1], g.angular_velocity[2]);
    f << buf;
  }
}

} // namespace

std::string run_bench(MPI_Comm world, const BenchOptions& o) {
  const int rank = rank_of(world), ranks = size_of(world);
  const bool root = rank == 0;
  const double rss_base = resident_bytes();

  // --- 1. the packing, replicated ------------------------------------------------------
  const FileMeta meta = read_file_meta(world, o.file);
  if (meta.dimension != 3)
    throw InputError("bench: " + o.file.string() + " holds a " + std::to_string(meta.dimension) +
                     "D sample; the benchmark is 3D");
  for (int k : o.replicate)
    if (k < 1)
      throw InputError("bench: --replicate factors must be >= 1");
  Configuration<3> c = read_configuration<3>(world, o.file);
  RunContext<3> ctx;
  ctx.world = world;
  ctx.system.cell = c.cell;
  ctx.system.cell.rate.setZero();
  for (int a = 0; a < 3; ++a)
    ctx.system.cell.length[a] *= o.replicate[a];
  ctx.system.particles = replicate(c.particles, o.replicate);
  c = Configuration<3>{};
  const std::int64_t n = meta.n_particles * o.replicate[0] * o.replicate[1] * o.replicate[2];
  auto& p = ctx.system.particles;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    p.velocity[i].setZero();
    p.angular_velocity[i].setZero();
  }
  ctx.decomposition = std::make_unique<Decomposition<3>>(world, ctx.system.cell.length);
  distribute(ctx.system, *ctx.decomposition);
  Log log(root, true);
  ctx.log = &log;

  // --- 2. material, static forces, typical overlap ---------------------------------------
  double r_max = 0, mass_sum = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    r_max = std::max(r_max, p.radius[i]);
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    mass_sum += p.mass[i];
  r_max = global_max(world, r_max);
  mass_sum = global_sum(world, mass_sum);
  const double a = 2 * r_max;
  MaterialSpec mat;
  mat.density = 2500.0;
  mat.normal_law = "hertz";
  mat.young_modulus = 70e9;
  mat.poisson_ratio = 0.3;
  mat.friction = 0.3;
  mat.damping = 0.98;
  SampleSpec sample;
  sample.diameter = a;
  ctx.contact_law = contact_law_params(mat);
  const ContactLaw<3> law = make_contact_law<3>(ctx.contact_law);
  MdSettings<3> s;
  s.skin = o.skin * a;
  s.halo = o.halo == "shared_memory" ? HaloTransport::shared_memory : HaloTransport::messages;
  s.dt = o.time_step_fraction *
         contact_duration(ctx.contact_law, mat.density, sample, 3, o.pressure); // provisional

  double static_pressure = 0, mean_force = 0;
  std::int64_t static_contacts = 0;
  {
    MdEngine<3> engine(ctx, law, s); // forces of the grains at rest: elastic only
    static_pressure = engine.observables().stress_elastic.trace() / 3;
    static_contacts = engine.observables().contacts;
    double sum = 0;
    std::int64_t count = 0;
    engine.for_each_contact(
        [&](std::size_t, std::size_t, const Vec<3>&, const ContactState<3>& st) {
          sum += st.normal_force;
          ++count;
        });
    mean_force = global_sum(world, sum) / static_cast<double>(global_sum(world, count));
    if (o.static_forces) {
      std::vector<double> mine;
      for (std::size_t i = 0; i < p.n_owned(); ++i)
        mine.insert(mine.end(), {double(p.id[i]), p.force[i][0], p.force[i][1], p.force[i][2]});
      std::vector<double> all = gather_values(mine, world);
      if (root) {
        std::vector<std::size_t> order(all.size() / 4);
        for (std::size_t k = 0; k < order.size(); ++k)
          order[k] = k;
        std::sort(order.begin(), order.end(),
                  [&](auto x, auto y) { return all[4 * x] < all[4 * y]; });
        std::ofstream f(*o.static_forces);
        char buf[160];
        std::snprintf(buf, sizeof buf, "# pressure %.17g contacts %lld\n# id fx fy fz (N)\n",
                      static_pressure, static_cast<long long>(static_contacts));
        f << buf;
        for (std::size_t k : order) {
          std::snprintf(buf, sizeof buf, "%lld %.17g %.17g %.17g\n",
                        static_cast<long long>(all[4 * k]), all[4 * k + 1], all[4 * k + 2],
                        all[4 * k + 3]);
          f << buf;
        }
      }
    }
  }
  // Hertz, equal spheres: N = (2/3) E~ sqrt(R*) h^{3/2}, K_N = E~ sqrt(R* h), R* = a/4.
  const double e_tilde = e_tilde_of(mat.young_modulus, mat.poisson_ratio);
  const double r_eff = equal_grains_effective_radius(a);
  const double h_typ = hertz_overlap_at_force(e_tilde, r_eff, mean_force);
  const double k_typ = hertz_stiffness(e_tilde, r_eff, h_typ);
  const double m_eff = equal_grains_effective_mass(mass_sum / static_cast<double>(n));
  const double contact_time = linear_contact_duration(k_typ, m_eff);
  s.dt = o.time_step_fraction * contact_time;

  // --- 3. velocities; fresh histories --------------------------------------------------
  ctx.system.contacts.clear();
  p.clear_ghosts();
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    for (int k = 0; k < 3; ++k)
      p.velocity[i][k] = o.velocity_rms * gaussian(o.seed, p.id[i], k);
  if (o.lammps_data) {
    const auto grains = gather_particles(p, world);
    if (root)
      write_lammps_data(*o.lammps_data, grains, ctx.system.cell, mat.density);
  }

  // --- 4. the timed run ------------------------------------------------------------------
  MdEngine<3> engine(ctx, law, s);
  const StepTimers setup = engine.timers();
  const std::int64_t rebuilds0 = engine.rebuilds();
  const double t0 = synchronized_wtime(world);
  // Each step's force time, for the per-step balance below.
  std::vector<double> step_forces(static_cast<std::size_t>(o.steps));
  for (std::int64_t k = 0; k < o.steps; ++k) {
    const double f0 = engine.timers().forces;
    engine.step();
    step_forces[static_cast<std::size_t>(k)] = engine.timers().forces - f0;
  }
  const double wall = synchronized_wtime(world) - t0;
  StepTimers t = engine.timers();
  t.integrate -= setup.integrate;
  t.neighbor -= setup.neighbor;
  t.comm -= setup.comm;
  t.forces -= setup.forces;

  double phases[4] = {t.forces, t.neighbor, t.comm, t.integrate};
  // Load balance: the slowest rank's force time over the mean (the others wait for it in the
  // halo exchange, which the breakdown counts as communication).
  const double forces_max = global_max(world, t.forces);
  global_sum_in_place(world, phases);
  for (double& x : phases)
    x /= ranks;
  // The same ratio step by step: every step the ranks meet at the reverse halo exchange, so
  // each waits for that step's slowest force pass. Sum over steps of the slowest rank's time
  // over the mean: above the whole-run ratio when the ranks take turns being slow (jitter of
  // a shared or virtual machine), equal to it for a steady imbalance.
  std::vector<double> step_max(step_forces.size());
  global_max(world, step_forces, step_max);
  double forces_step_max = 0;
  for (double x : step_max)
    forces_step_max += x;
  const double rss_peak = peak_resident_bytes();
  const double rss_max = global_max(world, rss_peak);
  const double grown = global_sum(world, std::max(0.0, rss_peak - rss_base));
  const double pstep = double(n) * double(o.steps) / wall / ranks;
  const auto& obs = engine.observables();
  // Communication volume: every step, forward sends position, velocity and spin of each
  // ghost (9 doubles) and reverse returns its force and torque (6 doubles).
  const double ghosts = global_sum(world, static_cast<double>(p.n_ghost()));
  const double ghosts_max = global_max(world, static_cast<double>(p.n_ghost()));
  const double owned_max = global_max(world, static_cast<double>(p.n_owned()));
  const double pressure_end = obs.stress.trace() / 3;
  // The transport the halo used (shared_memory asked for falls back to messages on 1 rank or
  // across nodes).
  const char* halo = engine.halo().through_shared_memory() ? "shared_memory" : "messages";

  char buf[2048];
  std::snprintf(
      buf, sizeof buf,
      "granpack bench: n = %lld grains (%s x %d x %d x %d), %d rank(s), %lld steps\n"
      "  static state: P = %.6g Pa, %lld contacts (z = %.3f), mean N^e = %.4g N, typical "
      "overlap h/a = %.3g\n"
      "  dt = %.4g s = %.3g x contact time %.4g s; skin = %.3g m; v_rms = %.3g m/s per axis\n"
      "  wall %.3f s, %.4g s/step, %lld list rebuilds, %lld contacts at the end, P_end = %.6g Pa\n"
      "  particle-steps/s per rank: %.4g\n"
      "  breakdown (mean over ranks): forces %.1f %%, neighbours %.1f %%, communication %.1f %%, "
      "integration %.1f %%, other %.1f %%\n"
      "  force time, slowest rank / mean: %.3f over the run, %.3f step by step (the waits of "
      "the step-by-step imbalance: %.1f %% of the wall time)\n"
      "  memory: peak RSS %.1f MiB per rank (max), %.0f bytes per grain above the start-up "
      "footprint\n"
      "  ghosts: %.0f in all (largest rank: %.0f for %.0f owned), halo traffic %.3g MB per step "
      "per rank, through %s\n",
      static_cast<long long>(n), o.file.filename().c_str(), o.replicate[0], o.replicate[1],
      o.replicate[2], ranks, static_cast<long long>(o.steps), static_pressure,
      static_cast<long long>(static_contacts), 2.0 * double(static_contacts) / double(n),
      mean_force, h_typ / a, s.dt, o.time_step_fraction, contact_time, s.skin, o.velocity_rms, wall,
      wall / double(o.steps), static_cast<long long>(engine.rebuilds() - rebuilds0),
      static_cast<long long>(obs.contacts), pressure_end, pstep, 100 * phases[0] / wall,
      100 * phases[1] / wall, 100 * phases[2] / wall, 100 * phases[3] / wall,
      100 * (wall - phases[0] - phases[1] - phases[2] - phases[3]) / wall,
      phases[0] > 0 ? forces_max / phases[0] : 1.0,
      phases[0] > 0 ? forces_step_max / phases[0] : 1.0, 100 * (forces_step_max - phases[0]) / wall,
      rss_max / 1048576.0, grown / double(n), ghosts, ghosts_max, owned_max,
      ghosts_max * 15 * 8 / 1e6, halo);
  std::string report = root ? std::string(buf) : std::string();
  if (o.json && root) {
    std::ofstream f(*o.json);
    std::snprintf(
        buf, sizeof buf,
        "{\"code\": \"granpack\", \"n\": %lld, \"ranks\": %d, \"steps\": %lld, \"dt\": %.17g, "
        "\"skin\": %.17g, \"wall\": %.6g, \"particle_steps_per_s_per_rank\": %.6g, "
        "\"forces\": %.6g, \"forces_max\": %.6g, \"forces_step_max\": %.6g, \"neighbor\": %.6g, "
        "\"comm\": %.6g, \"integrate\": %.6g, "
        "\"rebuilds\": %lld, \"static_pressure\": %.17g, \"static_contacts\": %lld, "
        "\"rss_max_bytes\": %.6g, \"bytes_per_grain\": %.6g, \"ghosts\": %.0f, "
        "\"ghosts_max\": %.0f, \"owned_max\": %.0f, \"halo\": \"%s\"}\n",
        static_cast<long long>(n), ranks, static_cast<long long>(o.steps), s.dt, s.skin, wall,
        pstep, phases[0], forces_max, forces_step_max, phases[1], phases[2], phases[3],
        static_cast<long long>(engine.rebuilds() - rebuilds0), static_pressure,
        static_cast<long long>(static_contacts), rss_max, grown / double(n), ghosts, ghosts_max,
        owned_max, halo);
    f << buf;
  }
  return report;
}

} // namespace granpack
