// `ed_gas` and `ls_compress`: the event-driven hard-sphere stages ([AR] sec. III, IV B; the
// A' samples). The event-driven engine (dynamics/hard_sphere_md) is serial: these stages
// gather the grains on rank 0, run there, and hand the result back to the distributed
// engine through migrate(). Collisions are instantaneous and there is no time step, so the
// cost is one event calendar; for n = 4000 the 50 collisions per grain of [AR] take about a
// second. Other ranks wait meanwhile (docs/event-driven.md).
//
// Collisions per grain count, as in [AR] ("until each particle has had n_coll collisions on
// average"), the collisions a grain takes part in: 2 C / n for C pair collisions.
//
// Checkpoints inside these stages (docs/long-jobs.md): rank 0 runs the engine in pieces of
// kPiece collisions; between pieces every rank takes part in one all-reduce of the request
// bits (wall-time interval, stop signal), as after an MD step. A checkpoint stores the
// engine's complete state (HardSphereMD::save_state) in the stage's frame, so the continued
// run is the uninterrupted one bit for bit whenever the checkpoint was taken; the grains of
// the checkpoint file are those the stage started from.
//
// The hard-sphere time unit is arbitrary: velocities are drawn from a Maxwell distribution
// and scaled so that the rms speed is one diameter a per unit time. Grains leave these stages
// at rest (the following compress stage starts from zero velocities, as in [AR]) and without
// contacts.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <random>
#include <sstream>

#include "granpack/analysis/translational_order.h"
#include "granpack/comm/broadcast.h"
#include "granpack/comm/collective_error.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/fault_injection.h"
#include "granpack/comm/gather.h"
#include "granpack/comm/migration.h"
#include "granpack/comm/reduce.h"
#include "granpack/core/error.h"
#include "granpack/dynamics/hard_sphere_md.h"
#include "granpack/engine/checkpoint.h"
#include "granpack/engine/stop_signals.h"
#include "granpack/io/base64.h"
#include "granpack/stages/stages.h"

namespace granpack {

namespace {

/// Maxwell velocities at a common temperature, zero total momentum, rms speed a.
template <int dim>
std::vector<Vec<dim>> maxwell_velocities(const std::vector<Particle<dim>>& g, double a,
                                         std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Vec<dim>> v(g.size());
  Vec<dim> momentum = Vec<dim>::Zero();
  double mass = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    for (int k = 0; k < dim; ++k)
      v[i][k] = normal(rng) / std::sqrt(g[i].mass);
    momentum += g[i].mass * v[i];
    mass += g[i].mass;
  }
  double m2 = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    v[i] -= momentum / mass;
    m2 += g[i].mass * v[i].squaredNorm();
  }
  const double scale = a / std::sqrt(m2 / mass);
  for (auto& x : v)
    x *= scale;
  return v;
}

/// The gathered sample as the hard-sphere engine wants it (rank 0 only).
template <int dim>
HardSphereMD<dim> make_gas(const RunContext<dim>& ctx, const std::vector<Particle<dim>>& g,
                           std::uint64_t seed) {
  std::vector<Vec<dim>> x(g.size());
  std::vector<double> r(g.size()), m(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    x[i] = ctx.system.cell.to_real(g[i].position);
    r[i] = g[i].radius;
    m[i] = g[i].mass;
  }
  try {
    return HardSphereMD<dim>(ctx.system.cell.length, std::move(x), std::move(r), std::move(m),
                             maxwell_velocities(g, ctx.deck->sample.diameter, seed));
  } catch (const Error& e) {
    std::ostringstream os;
    os << "stage " << ctx.stage_index << " (" << ctx.stage_name
       << "): the grains overlap, so they cannot start as hard spheres (" << e.what()
       << "); an `expand` stage before it separates the grains of a compressed packing";
    throw Error(os.str());
  }
}

/// Puts the grains back (positions from the gas, at rest, no contacts) and lets migrate()
/// send each to its owner. On ranks other than 0 `g` is empty.
template <int dim>
void scatter_back(RunContext<dim>& ctx, std::vector<Particle<dim>>& g,
                  const std::vector<Vec<dim>>& real_positions) {
  auto& p = ctx.system.particles;
  p.clear_ghosts();
  std::vector<std::size_t> all(p.n_owned());
  for (std::size_t i = 0; i < all.size(); ++i)
    all[i] = i;
  p.remove_owned(all);
  for (std::size_t i = 0; i < g.size(); ++i) {
    g[i].position = ctx.system.cell.to_scaled(real_positions[i]);
    g[i].velocity.setZero();
    g[i].angular_velocity.setZero();
    p.add_owned(g[i]);
  }
  ctx.system.contacts.clear();
  migrate(ctx.system, *ctx.decomposition);
}

/// Collisions between two looks at the checkpoint requests: milliseconds of engine time
/// (about 3e5 collisions/s for n = 4000), so a signal is honoured at once, and an
/// all-reduce per piece costs nothing next to it.
constexpr std::int64_t kPiece = 2000;

/// Collective. Calls piece() on rank 0 (it advances the engine by at most kPiece collisions
/// and returns true when the engine's work is done) until it is done; between pieces a
/// checkpoint is written when the wall-time interval has passed or a stop signal arrived
/// (then exit 75). Errors of rank 0 reach every rank at the end of the piece.
template <int dim> void run_in_pieces(RunContext<dim>& ctx, const std::function<bool()>& piece) {
  constexpr int kFinished = 1 << 8;
  const int rank = rank_of(ctx.world);
  for (std::int64_t pieces = 1;; ++pieces) {
    int bits = 0;
    collectively(ctx.world, [&] {
      if (rank == 0 && piece())
        bits |= kFinished;
    });
    // Test-only (GRANPACK_FAULT=piece:N / piece_hold:N): a kill or a stop at a chosen piece.
    fault_point(FaultPoint::kPiece, pieces);
    if (fault_point(FaultPoint::kPieceHold, pieces))
      wait_for_stop_signal();
    if (ctx.checkpointer)
      bits |= ctx.checkpointer->clock_request();
    bits = global_bit_or(ctx.world, bits);
    // Once the engine is done, a pending stop is honoured after the stage (run_deck).
    if (bits & kFinished)
      return;
    if (bits & kRequestCheckpoint) {
      ctx.checkpointer->write(ctx, true);
      ctx.checkpointer->stop_if_requested(bits, ctx.system.step);
    }
  }
}

/// The engine of a resumed stage (rank 0), from its frame; checks it is these grains'.
template <int dim>
HardSphereMD<dim> resume_engine(const RunContext<dim>& ctx, const nlohmann::json& frame,
                                std::size_t n) {
  try {
    auto gas =
        HardSphereMD<dim>::restore_state(base64_decode(frame.at("engine").get<std::string>()));
    if (gas.size() != n || gas.box() != ctx.system.cell.length)
      throw Error("it holds " + std::to_string(gas.size()) + " grains in another cell");
    return gas;
  } catch (const std::exception& e) {
    throw InputError("stage " + std::to_string(ctx.stage_index) + " (" + ctx.stage_name +
                     "): the checkpoint's saved event-driven state cannot be resumed (" + e.what() +
                     ")");
  }
}

/// The frame of a resumed stage of kind `kind` (null if not resuming). No MD step to finish.
template <int dim> nlohmann::json take_frame(RunContext<dim>& ctx, const char* kind) {
  nlohmann::json f = ctx.take_resume_frame();
  if (f.is_null())
    return f;
  ctx.resume_mid_step = false;
  if (f.value("stage", "") != kind)
    throw InputError("stage " + std::to_string(ctx.stage_index) + " (" + ctx.stage_name +
                     "): the checkpoint's frame is of a '" + f.value("stage", "?") +
                     "' stage, not " + kind);
  return f;
}

/// Beyond this many grains the Bragg-peak search ((2 N^(1/dim) + 1)^dim / 2 wave vectors times
/// N) costs more than the melt itself; the lattice order is then not measured.
constexpr std::size_t kMaxOrderGrains = 40000;

/// Wave-vector indices up to N^(1/dim): the first peaks of any lattice of N sites in the cell
/// (FCC of c^3 cells: N^(1/3) = 1.59 c, its (111) peaks at index c).
template <int dim> int bragg_index_max(std::size_t n) {
  return static_cast<int>(std::ceil(std::pow(static_cast<double>(n), 1.0 / dim)));
}

template <int dim> void require_sample(const RunContext<dim>& ctx) {
  GRANPACK_CHECK(ctx.decomposition, "stage " << ctx.stage_index << " (" << ctx.stage_name
                                             << "): there is no sample yet (a lattice or random "
                                                "stage must come first)");
}

} // namespace

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const EdGasStage& e) {
  require_sample(ctx);
  const int rank = rank_of(ctx.world);
  // The event-driven part, from gathering the grains to handing them back: on rank 0 the
  // serial engine, on the others the wait for it (checkpoints written meanwhile count as I/O).
  ScopedPhaseExcept phase(ctx.stage_timers.event_driven, ctx.stage_timers.io);
  auto g = gather_particles(ctx.system.particles, ctx.world);
  // collisions, hard-sphere time, reduced pressure Z, lattice order (-1: not measured), peaks
  double stats[5] = {0, 0, 0, -1, 0};
  std::vector<Vec<dim>> x;
  const nlohmann::json resume = take_frame(ctx, "ed_gas");
  std::optional<HardSphereMD<dim>> gas;
  std::int64_t total = 0;
  // The Bragg peaks of the starting configuration (a lattice, usually), whose mean rho_k at
  // the end says how much of it the melt left; kept in the frame across restarts.
  BraggPeaks<dim> peaks;
  bool order_measured = false;
  collectively(ctx.world, [&] {
    if (rank != 0)
      return;
    total = std::llround(0.5 * e.collisions_per_grain * static_cast<double>(g.size()));
    if (!resume.is_null()) {
      gas.emplace(resume_engine(ctx, resume, g.size()));
      order_measured = resume.contains("bragg_peaks");
      if (order_measured)
        for (const auto& m : resume["bragg_peaks"])
          peaks.m.push_back(m.get<std::array<int, dim>>());
    } else {
      gas.emplace(make_gas(ctx, g, e.seed));
      gas->reset_pressure();
      order_measured = g.size() <= kMaxOrderGrains;
      if (order_measured) {
        const auto x0 = gas->positions();
        peaks =
            find_bragg_peaks<dim>(x0, ctx.system.cell.length, bragg_index_max<dim>(g.size()), 0.5);
      }
    }
  });
  StageFrame<dim> frame(ctx, [&] {
    nlohmann::json f{{"stage", "ed_gas"}};
    if (gas)
      f["engine"] = base64_encode(gas->save_state());
    if (order_measured)
      f["bragg_peaks"] = peaks.m;
    return f;
  });
  run_in_pieces(ctx, [&] {
    gas->run_collisions(std::min(kPiece, total - gas->collisions()));
    return gas->collisions() >= total;
  });
  collectively(ctx.world, [&] {
    if (rank != 0)
      return;
    GRANPACK_CHECK(gas->min_relative_gap() > -1e-9, "the hard-sphere gas developed an overlap");
    const auto n = static_cast<double>(g.size());
    stats[0] = static_cast<double>(gas->collisions());
    stats[1] = gas->time();
    // Compressibility factor Z = P V / (N k T) with k T = 2 K / (dim N).
    const double kT = 2.0 * gas->kinetic_energy() / (dim * n);
    stats[2] = gas->pressure() * ctx.system.cell.volume() / (n * kT);
    x = gas->positions();
    if (order_measured && !peaks.m.empty()) {
      stats[3] = mean_translational_order<dim>(x, ctx.system.cell.length, peaks);
      stats[4] = static_cast<double>(peaks.m.size());
    }
  });
  broadcast_in_place(ctx.world, stats);
  scatter_back(ctx, g, x);
  phase.stop();
  const double n = static_cast<double>(ctx.deck->sample.n);
  std::ostringstream os;
  os << "  " << stats[0] << " collisions (" << 2 * stats[0] / n << " per grain) in " << stats[1]
     << " a/v_rms at phi " << ctx.solid_fraction() << ", compressibility factor PV/NkT "
     << stats[2];
  ctx.log->info(os.str());
  StageReport r;
  r.values = {{"collisions_per_grain", 2 * stats[0] / n},
              {"hard_sphere_time", stats[1]},
              {"compressibility_factor", stats[2]}};
  if (stats[3] >= 0) {
    std::ostringstream lo;
    lo << "  order left of the starting lattice: mean rho_k " << stats[3] << " over its "
       << stats[4] << " Bragg peaks (uncorrelated positions: about " << 1.0 / std::sqrt(n) << ")";
    ctx.log->info(lo.str());
    r.values.emplace_back("lattice_order", stats[3]);
    r.values.emplace_back("lattice_order_random", 1.0 / std::sqrt(n));
  }
  return r;
}

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const LsCompressStage& l) {
  require_sample(ctx);
  const int rank = rank_of(ctx.world);
  // The event-driven part, from gathering the grains to handing them back: on rank 0 the
  // serial engine, on the others the wait for it (checkpoints written meanwhile count as I/O).
  ScopedPhaseExcept phase(ctx.stage_timers.event_driven, ctx.stage_timers.io);
  auto g = gather_particles(ctx.system.particles, ctx.world);
  // Collisions per grain in each interval [start, report_phi[0]], ..., [report_phi.back(), phi];
  // then the growth factor of the radii.
  const std::size_t intervals = l.report_phi.size() + 1;
  std::vector<double> stats(intervals + 1, 0.0);
  std::vector<Vec<dim>> x;
  const double phi0 = ctx.solid_fraction();
  GRANPACK_CHECK(l.phi > phi0, "stage " << ctx.stage_index << " (" << ctx.stage_name
                                        << "): target phi " << l.phi
                                        << " is not above the current solid fraction " << phi0);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<double> targets;
  for (double p : l.report_phi)
    if (p > phi0)
      targets.push_back(p);
  targets.push_back(l.phi);
  // The growth's progress through the targets: the one in progress (targets[next - 1] once
  // begun), the collision count when it began, the initial radius of grain 0.
  std::size_t next = 0;
  std::int64_t before = 0;
  double r0 = 0;
  const nlohmann::json resume = take_frame(ctx, "ls_compress");
  std::optional<HardSphereMD<dim>> gas;
  collectively(ctx.world, [&] {
    if (rank != 0)
      return;
    if (resume.is_null()) {
      gas.emplace(make_gas(ctx, g, l.seed));
      r0 = gas->radii().front();
      return;
    }
    gas.emplace(resume_engine(ctx, resume, g.size()));
    next = resume.at("next").get<std::size_t>();
    before = resume.at("before").get<std::int64_t>();
    r0 = exact_double(resume.at("r0"));
    const auto done = resume.at("stats");
    if (next > targets.size() || done.size() != stats.size())
      throw InputError("stage " + std::to_string(ctx.stage_index) + " (" + ctx.stage_name +
                       "): the checkpoint's frame does not match this stage's targets");
    for (std::size_t k = 0; k < stats.size(); ++k)
      stats[k] = exact_double(done[k]);
  });
  StageFrame<dim> frame(ctx, [&] {
    nlohmann::json f{{"stage", "ls_compress"}};
    if (!gas)
      return f;
    f["engine"] = base64_encode(gas->save_state());
    f["next"] = next;
    f["before"] = before;
    f["r0"] = exact(r0);
    f["stats"] = nlohmann::json::array();
    for (double v : stats)
      f["stats"].push_back(exact(v));
    return f;
  });
  const auto n = static_cast<double>(g.size());
  // d(diameter)/dt = growth_rate v_rms for the largest diameter a, and v_rms is one a per
  // time unit: the relative growth rate of every radius is growth_rate.
  const double rate = l.growth_rate;
  auto last_log = std::chrono::steady_clock::now();
  auto progress = [&](const HardSphereMD<dim>& s) {
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_log).count() < 10)
      return;
    last_log = now;
    std::ostringstream os;
    os << "  LS: phi " << s.solid_fraction() << ", " << 2 * double(s.collisions()) / n
       << " collisions per grain";
    ctx.log->progress(os.str());
  };
  const std::size_t first_interval = intervals - targets.size(); // passed ones count zero
  run_in_pieces(ctx, [&] {
    if (!gas->growing()) {
      if (next > 0) // the growth to targets[next - 1] has ended
        stats[first_interval + next - 1] = 2 * double(gas->collisions() - before) / n;
      if (next == targets.size())
        return true;
      before = gas->collisions();
      gas->begin_growth(targets[next++], rate, l.rescale_every);
    }
    gas->continue_growth(kPiece, progress);
    return false;
  });
  collectively(ctx.world, [&] {
    if (rank != 0)
      return;
    GRANPACK_CHECK(gas->min_relative_gap() > -1e-9, "the hard-sphere growth developed an overlap");
    stats[intervals] = gas->radii().front() / r0;
    x = gas->positions();
  });
  broadcast_in_place(ctx.world, stats);
  // The grains keep their diameter: the cell shrinks by the growth factor instead.
  const double growth = stats[intervals];
  for (auto& xi : x)
    xi /= growth;
  ctx.system.cell.length /= growth;
  scatter_back(ctx, g, x);
  phase.stop();

  StageReport r;
  std::ostringstream os;
  os << "  LS growth to phi " << ctx.solid_fraction() << " ("
     << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()
     << " s); collisions per grain:";
  std::vector<double> bounds = {phi0};
  for (double p : l.report_phi)
    bounds.push_back(p);
  bounds.push_back(l.phi);
  for (std::size_t k = 0; k < intervals; ++k) {
    std::ostringstream key;
    key.precision(3);
    key << "collisions_per_grain_" << std::fixed << bounds[k] << "_" << bounds[k + 1];
    r.values.emplace_back(key.str(), stats[k]);
    os << " [" << bounds[k] << ", " << bounds[k + 1] << "] " << stats[k];
  }
  ctx.log->info(os.str());
  return r;
}

template StageReport run_stage<2>(RunContext<2>&, const EdGasStage&);
template StageReport run_stage<3>(RunContext<3>&, const EdGasStage&);
template StageReport run_stage<2>(RunContext<2>&, const LsCompressStage&);
template StageReport run_stage<3>(RunContext<3>&, const LsCompressStage&);

} // namespace granpack
