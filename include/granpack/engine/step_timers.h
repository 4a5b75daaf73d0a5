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
#include <time.h>

#include <chrono>

namespace granpack {

struct StepTimers {
  double integrate = 0, neighbor = 0, comm = 0, forces = 0;
  double forces_cpu = 0; ///< CPU time of the force phase (within `forces`)
  double total() const { return integrate + neighbor + comm + forces; }
  StepTimers& operator+=(const StepTimers& o) {
    integrate += o.integrate, neighbor += o.neighbor, comm += o.comm, forces += o.forces;
    forces_cpu += o.forces_cpu;
    return *this;
  }
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

/// Adds the thread's CPU seconds between construction and destruction to `sink`.
class ScopedCpuPhase {
public:
  explicit ScopedCpuPhase(double& sink) : sink_(sink), t0_(thread_cpu_seconds()) {}
  ~ScopedCpuPhase() { sink_ += thread_cpu_seconds() - t0_; }
  ScopedCpuPhase(const ScopedCpuPhase&) = delete;
  ScopedCpuPhase& operator=(const ScopedCpuPhase&) = delete;

private:
  double& sink_;
  double t0_;
};

} // namespace granpack
