#pragma once
// What a stage works on: the distributed state, the deck, the contact law and stress target
// in force (stages change them; every file written stores them), the log and the output
// directory. Stages orchestrate; physics lives in the kernels and communication in comm/.
#include <mpi.h>

#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "granpack/comm/decomposition.h"
#include "granpack/core/system.h"
#include "granpack/engine/checkpoint.h"
#include "granpack/engine/step_timers.h"
#include "granpack/io/deck.h"
#include "granpack/io/log.h"
#include "granpack/io/report.h"
#include "granpack/io/state_parameters.h"

namespace granpack {

template <int dim> struct RunContext {
  MPI_Comm world = MPI_COMM_WORLD;
  const Deck* deck = nullptr;
  /// The contact law in force: the deck's [material], changed by `set` and `stiffen`.
  ContactLawParams contact_law;
  /// The stresses and fixed axes of the last compress stage (pressure_steps scales them,
  /// fix_rattlers takes its force scale from them); unset before any compress stage.
  StressTarget stress_target;
  System<dim> system;
  /// Created by the stage that builds the sample, once the cell is known.
  std::unique_ptr<Decomposition<dim>> decomposition;
  Log* log = nullptr;
  std::filesystem::path output_dir;
  int stage_index = -1;
  std::string stage_name;
  /// Checkpoints (null: none are written, e.g. in tests that drive stages directly).
  Checkpointer* checkpointer = nullptr;
  /// State of the stages in progress, outermost first, for a checkpoint taken inside a
  /// stage; a stage that can be resumed pushes a frame for its lifetime (StageFrame).
  std::vector<std::function<nlohmann::json()>> frames;
  /// Restart inside a stage: the frames to resume, outermost first; each stage takes the
  /// front one. resume_mid_step: the first MD engine completes the interrupted time step.
  std::deque<nlohmann::json> resume;
  bool resume_mid_step = false;
  /// This rank's time in the parts of the stage in progress: the phases of the MD steps
  /// (every MD engine adds its timers when it ends), the files written and read, the
  /// event-driven engine; run_deck reduces them over the ranks at the stage end (the report's
  /// phase_seconds, wall_split, md_classes) and resets them.
  StageTimers stage_timers;
  /// How often the MD engines of the stage in progress moved the cut planes (load balancing).
  std::int64_t stage_rebalances = 0;
  /// Treatment II of [AR] sec. III C: the ids (sorted) of the rattlers that the last
  /// fix_rattlers stage pushed onto the backbone, every rank's; cleared when a later stage
  /// other than `set` or `write` starts (it moves the grains again). Written as
  /// /network/fixed_rattler and kept in checkpoints' /run_state; a `read` stage takes them
  /// from its file (it leaves the grains as they were).
  std::vector<GlobalId> fixed_rattlers;

  /// Takes the resume frame of the stage starting now (empty json if not resuming).
  nlohmann::json take_resume_frame() {
    if (resume.empty())
      return {};
    nlohmann::json f = std::move(resume.front());
    resume.pop_front();
    return f;
  }

  /// What every file written now records of the run (the HDF5 group /parameters).
  StateParameters parameters() const { return {contact_law, stress_target}; }

  /// Solid fraction: sum of grain volumes (areas in 2D) over the cell's. Collective.
  double solid_fraction() const;
};

/// Registers a stage's state provider for checkpoints while the stage runs.
template <int dim> class StageFrame {
public:
  StageFrame(RunContext<dim>& ctx, std::function<nlohmann::json()> f) : ctx_(ctx) {
    ctx_.frames.push_back(std::move(f));
  }
  ~StageFrame() { ctx_.frames.pop_back(); }
  StageFrame(const StageFrame&) = delete;
  StageFrame& operator=(const StageFrame&) = delete;

private:
  RunContext<dim>& ctx_;
};

} // namespace granpack
