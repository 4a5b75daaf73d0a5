#pragma once
// Wall-clock accounting of the phases of an MD time step (docs/performance.md): integration
// (kicks, drift), neighbours (rebuild test, Verlet list, binding of contact histories),
// communication (halo forward/reverse, migration, ghost borders, the step's all-reduces) and
// contact forces. Always on: a steady_clock read costs ~20 ns, about ten per step, far below
// the 1e-4..1e-1 s of a step. Local to one rank; the caller reduces over ranks.
#include <chrono>

namespace granpack {

struct StepTimers {
  double integrate = 0, neighbor = 0, comm = 0, forces = 0;
  double total() const { return integrate + neighbor + comm + forces; }
};

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

}  // namespace granpack
