#pragma once
// Wall-clock accounting of the phases of an MD time step (docs/performance.md): integration
// (kicks, drift), neighbours (rebuild test, Verlet list, binding of contact histories),
// communication (halo forward/reverse, migration, ghost borders, the step's all-reduces) and
// contact forces. Always on: a steady_clock read costs ~20 ns, about ten per step, far below
// the 1e-4..1e-1 s of a step. Local to one rank; the caller reduces over ranks.
//
// The force phase is also timed in CPU time of the calling thread: the work a rank does,
// which the wall time overstates when ranks share cores (oversubscribed tests, a loaded
// node). The slowest rank's force CPU time over the mean is the load imbalance of the work.
// The thread CPU clock is a system call (~0.5 µs, and more under a hypervisor), not a vDSO
// read: read twice a step it cost 4-5 % of a 1400-disk step (docs/performance.md), so it is
// read on every kCpuSampleEvery-th force evaluation only, and the CPU time of all of them
// is estimated as the sampled CPU time scaled by the force wall time of all over that of the
// sampled ones (forces_cpu_estimate()).
//
// The steps are also tallied in two classes, dense and loose, by the contacts per grain the
// step ended with (MdEngine::finish_step): the cost of a step grows with the contacts, so a
// rate in particle-steps per second means something only within a class.
//
// A stage's time outside the MD steps that the report splits out (StageTimers): the writing
// and reading of files, and the event-driven engine.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdint>

namespace granpack {

/// A step is dense when its interacting pairs are at least this many per grain (z >= 2):
/// a gas has far fewer (a grain meets another now and then: z << 1), a packing far more
/// (z about 2 dim near jamming, 4 in 2D and 6 in 3D), so the split falls between the two
/// regimes in both dimensions.
inline constexpr double kDenseContactsPerGrain = 1.0;

/// MD steps of one class: how many, the grain-steps they advanced (steps x grains) and the
/// wall time of their phases on this rank.
struct StepClassTally {
  std::int64_t steps = 0, particle_steps = 0;
  double seconds = 0;
  StepClassTally& operator+=(const StepClassTally& o) {
    steps += o.steps, particle_steps += o.particle_steps, seconds += o.seconds;
    return *this;
  }
};

/// One force evaluation in this many has its thread CPU time read (ForcePhaseTimer).
inline constexpr std::int64_t kCpuSampleEvery = 16;

struct StepTimers {
  double integrate = 0, neighbor = 0, comm = 0, forces = 0;
  /// The sampled force evaluations: their CPU time and their wall time (within `forces`).
  double forces_cpu_sampled = 0, forces_sampled = 0;
  std::int64_t force_evaluations = 0; ///< every force evaluation, sampled or not
  /// The steps by class; their seconds are the steps' share of the four phases (the engine's
  /// set-up, its first list and forces, is in the phases and in neither class).
  StepClassTally dense, loose;
  double total() const { return integrate + neighbor + comm + forces; }
  /// The force phase's CPU time, estimated from the sampled evaluations (0 without any).
  double forces_cpu_estimate() const {
    return forces_sampled > 0 ? forces * (forces_cpu_sampled / forces_sampled) : 0.0;
  }
  StepTimers& operator+=(const StepTimers& o) {
    integrate += o.integrate, neighbor += o.neighbor, comm += o.comm, forces += o.forces;
    forces_cpu_sampled += o.forces_cpu_sampled, forces_sampled += o.forces_sampled;
    force_evaluations += o.force_evaluations;
    dense += o.dense, loose += o.loose;
    return *this;
  }
};

/// This rank's time in the parts of a stage that report.json splits out (docs/report.md,
/// `wall_split`). The parts never overlap: a file written inside the event-driven phase counts
/// as I/O only (ScopedPhaseExcept).
struct StageTimers {
  StepTimers md;           ///< the MD steps (every MD engine of the stage adds its timers)
  double io = 0;           ///< configurations and checkpoints written (write_state), files read
  double event_driven = 0; ///< ed_gas, ls_compress: gathering, the serial engine, handing back
};

/// CPU seconds of the calling thread so far.
inline double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Adds the seconds between construction and destruction to one StepTimers field.
class ScopedPhase {
public:
  explicit ScopedPhase(double& sink) : sink_(sink), t0_(std::chrono::steady_clock::now()) {}
  ~ScopedPhase() {
    sink_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }
  ScopedPhase(const ScopedPhase&) = delete;
  ScopedPhase& operator=(const ScopedPhase&) = delete;

private:
  double& sink_;
  std::chrono::steady_clock::time_point t0_;
};

/// Times one force evaluation into `t`: its wall time always, and on every kCpuSampleEvery-th
/// evaluation (counted by t.force_evaluations) its thread CPU time too.
class ForcePhaseTimer {
public:
  // The wall interval encloses the CPU one: a sampled CPU time then never exceeds its wall
  // time by the clock reads' own cost (~1 µs, 5 % of a 1400-disk force phase).
  explicit ForcePhaseTimer(StepTimers& t)
      : t_(t), sampled_(t.force_evaluations++ % kCpuSampleEvery == 0),
        t0_(std::chrono::steady_clock::now()), cpu0_(sampled_ ? thread_cpu_seconds() : 0.0) {}
  ~ForcePhaseTimer() {
    const double cpu = sampled_ ? thread_cpu_seconds() - cpu0_ : 0.0;
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    t_.forces += wall;
    if (sampled_) {
      t_.forces_cpu_sampled += cpu;
      t_.forces_sampled += wall;
    }
  }
  ForcePhaseTimer(const ForcePhaseTimer&) = delete;
  ForcePhaseTimer& operator=(const ForcePhaseTimer&) = delete;

private:
  StepTimers& t_;
  bool sampled_;
  std::chrono::steady_clock::time_point t0_;
  double cpu0_;
};

/// Adds the seconds between construction and stop() (or destruction) to `sink`, less what
/// `nested` gained meanwhile: a phase that contains another (the checkpoints written during an
/// event-driven stage) does not count its seconds twice.
class ScopedPhaseExcept {
public:
  ScopedPhaseExcept(double& sink, const double& nested)
      : sink_(sink), nested_(nested), nested0_(nested), t0_(std::chrono::steady_clock::now()) {}
  void stop() {
    if (stopped_)
      return;
    stopped_ = true;
    const double all =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    sink_ += std::max(0.0, all - (nested_ - nested0_));
  }
  ~ScopedPhaseExcept() { stop(); }
  ScopedPhaseExcept(const ScopedPhaseExcept&) = delete;
  ScopedPhaseExcept& operator=(const ScopedPhaseExcept&) = delete;

private:
  double& sink_;
  const double& nested_;
  double nested0_;
  std::chrono::steady_clock::time_point t0_;
  bool stopped_ = false;
};

} // namespace granpack
