#include "granpack/engine/checkpoint.h"

#include <bit>
#include <cstdio>
#include <sstream>

#include "granpack/comm/broadcast.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/reduce.h"
#include "granpack/core/error.h"
#include "granpack/engine/run_context.h"
#include "granpack/engine/state_file.h"
#include "granpack/engine/stop_signals.h"

namespace granpack {

nlohmann::json exact(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "0x%016llx",
                static_cast<unsigned long long>(std::bit_cast<std::uint64_t>(v)));
  return buf;
}

double exact_double(const nlohmann::json& j) {
  const std::string s = j.get<std::string>();
  std::size_t used = 0;
  const unsigned long long bits = std::stoull(s, &used, 16);
  if (used != s.size() || s.size() != 18)
    throw std::invalid_argument("not an exact double: " + s);
  return std::bit_cast<double>(static_cast<std::uint64_t>(bits));
}

Checkpointer::Checkpointer(MPI_Comm world, CheckpointPolicy policy)
    : world_(world), policy_(std::move(policy)), last_(std::chrono::steady_clock::now()),
      start_(last_) {
  rank_ = rank_of(world_);
}

int Checkpointer::local_request(std::int64_t step_after) const {
  int bits = clock_request() | deferred_;
  if (policy_.every_steps > 0 && step_after % policy_.every_steps == 0)
    bits |= kRequestCheckpoint;
  return bits;
}

int Checkpointer::clock_request() const {
  int bits = 0;
  if (rank_ == 0 && policy_.every_seconds > 0 &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_).count() >=
          policy_.every_seconds)
    bits |= kRequestCheckpoint;
  if (stop_signal_received() != 0)
    bits |= kRequestStop | kRequestCheckpoint;
  return bits;
}

int Checkpointer::global_request(std::int64_t step_after) const {
  return global_bit_or(world_, local_request(step_after));
}

bool Checkpointer::take_now(int bits) {
  if (!(bits & kRequestCheckpoint))
    return false;
  if (bits & kRequestRebuild)
    return true;
  if (++deferred_steps_ > kMaxDeferredSteps)
    return true; // forced (write() says so)
  deferred_ = bits & (kRequestCheckpoint | kRequestStop);
  return false;
}

void Checkpointer::stop_if_requested(int bits, std::int64_t step) const {
  if (!(bits & kRequestStop))
    return;
  throw CheckpointedStop("stopped on request (SIGTERM, SIGUSR1 or SIGINT) at step " +
                         std::to_string(step) + " after writing " + policy_.file.string() +
                         "; continue with --restart " + policy_.file.string());
}

template <int dim> void Checkpointer::write(RunContext<dim>& ctx, bool mid_stage) {
  GRANPACK_CHECK(ctx.decomposition, "a checkpoint needs a sample");
  const auto t0 = std::chrono::steady_clock::now();
  nlohmann::json st;
  // Format 2: the contact law and stress target are in /parameters (write_state), not here.
  st["format"] = 2;
  st["stage_index"] = mid_stage ? ctx.stage_index : ctx.stage_index + 1;
  st["mid_stage"] = mid_stage;
  const int size = size_of(world_);
  st["ranks"] = size;
  st["grid"] = std::vector<int>(ctx.decomposition->dims().begin(), ctx.decomposition->dims().end());
  // Moved cut planes (load balancing) are part of the state: a restart on the same rank count
  // puts every grain on the same rank, so its sums run in the same order (bit for bit).
  if (!ctx.decomposition->uniform()) {
    st["cuts"] = nlohmann::json::array();
    for (int a = 0; a < dim; ++a) {
      nlohmann::json axis = nlohmann::json::array();
      for (const double c : ctx.decomposition->cuts(a))
        axis.push_back(exact(c));
      st["cuts"].push_back(axis);
    }
  }
  st["completed"] = nlohmann::json::array();
  if (completed)
    for (const auto& r : *completed)
      st["completed"].push_back(nlohmann::json::parse(stage_report_json(r)));
  st["frames"] = nlohmann::json::array();
  if (mid_stage)
    for (const auto& f : ctx.frames)
      st["frames"].push_back(f());
  // Rank 0's clock: the run state must be the same text on every rank.
  const double wall = broadcast_value(
      world_, earlier_wall_seconds + std::chrono::duration<double>(t0 - start_).count());
  st["wall_seconds"] = wall;
  if (!ctx.fixed_rattlers.empty())
    st["fixed_rattlers"] = ctx.fixed_rattlers;
  write_state(ctx, policy_.file, st.dump());
  last_ = std::chrono::steady_clock::now();
  ++written_;
  char buf[200];
  std::snprintf(buf, sizeof buf, "  checkpoint %d at step %lld (%s) in %.2f s", written_,
                static_cast<long long>(ctx.system.step),
                mid_stage ? "inside the stage" : "after the stage",
                std::chrono::duration<double>(last_ - t0).count());
  ctx.log->info(buf + std::string(": ") + policy_.file.string());
  if (deferred_steps_ > kMaxDeferredSteps) {
    std::snprintf(
        buf, sizeof buf,
        "  (forced: no neighbour-list rebuild in %lld steps after the request; a continuation "
        "from it is not bit-identical to the run without it)",
        static_cast<long long>(kMaxDeferredSteps));
    ctx.log->info(buf);
  }
  deferred_ = 0;
  deferred_steps_ = 0;
}

RunState parse_run_state(const std::string& text, const std::string& file) {
  RunState s;
  try {
    const auto j = nlohmann::json::parse(text);
    const int format = j.at("format").get<int>();
    if (format != 1 && format != 2)
      throw std::invalid_argument("unknown run_state format");
    s.stage_index = j.at("stage_index").get<int>();
    s.mid_stage = j.at("mid_stage").get<bool>();
    s.ranks = j.at("ranks").get<int>();
    s.grid = j.at("grid").get<std::vector<int>>();
    if (j.contains("cuts"))
      for (const auto& axis : j.at("cuts")) {
        s.cuts.emplace_back();
        for (const auto& v : axis)
          s.cuts.back().push_back(exact_double(v));
      }
    for (const auto& r : j.at("completed"))
      s.completed.push_back(stage_report_from_json(r.dump()));
    if (format == 1) {
      RunState::Legacy& l = s.legacy.emplace();
      l.friction = exact_double(j.at("friction"));
      l.damping = exact_double(j.at("damping"));
      // Written since the stiffen stage (checkpoints of older versions: the deck's values).
      if (j.contains("normal_stiffness"))
        l.normal_stiffness = exact_double(j.at("normal_stiffness"));
      if (j.contains("rolling_stiffness"))
        l.rolling_stiffness = exact_double(j.at("rolling_stiffness"));
      for (const auto& v : j.at("stress"))
        l.stress.push_back(exact_double(v));
      l.fixed = j.at("fixed").get<std::vector<bool>>();
      l.pressure = exact_double(j.at("pressure"));
    }
    for (const auto& f : j.at("frames"))
      s.frames.push_back(f);
    s.wall_seconds = j.at("wall_seconds").get<double>();
    if (j.contains("fixed_rattlers"))
      s.fixed_rattlers = j.at("fixed_rattlers").get<std::vector<std::int64_t>>();
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(file + ": dataset /run_state is not a granpack run state (" + e.what() + ")");
  }
  if (s.stage_index < 0)
    throw InputError(file + ": /run_state has a negative stage_index");
  // The grid is reused on the same rank count (MPI_Cart_create would abort on a wrong one).
  long long cells = 1;
  for (const int g : s.grid)
    cells *= g >= 1 && g <= 1 << 20 ? g : 0;
  if (s.ranks < 1 || s.grid.empty() || cells != s.ranks) {
    std::string grid;
    for (const int g : s.grid)
      grid += (grid.empty() ? "" : " x ") + std::to_string(g);
    throw InputError(file + ": /run_state's domain grid (" + (grid.empty() ? "empty" : grid) +
                     ") does not fit its rank count " + std::to_string(s.ranks) +
                     ": a damaged checkpoint");
  }
  if (!s.cuts.empty()) {
    bool fits = s.cuts.size() == s.grid.size();
    for (std::size_t a = 0; fits && a < s.cuts.size(); ++a) {
      const auto& c = s.cuts[a];
      fits = c.size() == static_cast<std::size_t>(s.grid[a]) + 1 && c.front() == 0.0 &&
             c.back() == 1.0;
      for (std::size_t k = 0; fits && k + 1 < c.size(); ++k)
        fits = c[k] < c[k + 1];
    }
    if (!fits)
      throw InputError(file + ": /run_state's cut planes do not fit its domain grid (each axis "
                              "needs grid + 1 increasing positions from 0 to 1): a damaged "
                              "checkpoint");
  }
  return s;
}

StateParameters legacy_parameters(const RunState& state, const Deck& deck) {
  GRANPACK_CHECK(state.legacy, "legacy_parameters: the run state is not of format 1");
  const RunState::Legacy& l = *state.legacy;
  MaterialSpec m = deck.material;
  m.friction = l.friction;
  m.damping = l.damping;
  if (l.normal_stiffness)
    m.normal_stiffness = *l.normal_stiffness;
  if (l.rolling_stiffness)
    m.rolling_stiffness = *l.rolling_stiffness;
  StressTarget t;
  if (!l.stress.empty()) {
    // A compress stage sets the target when it ends; pressure_steps at each level's end.
    for (const auto& st : deck.stages)
      if ((st.kind == "compress" && st.index < state.stage_index) ||
          (st.kind == "pressure_steps" && st.index <= state.stage_index))
        t.stage = st.index;
    t.stage = std::max(t.stage, 0);
    t.stress = l.stress;
    t.fixed = l.fixed;
    t.pressure = l.pressure;
  }
  return {contact_law_params(m), t};
}

void check_restart_deck(const Deck& original, const Deck& now, const RunState& state,
                        bool allow_later_stages, const std::string& checkpoint_file) {
  std::vector<std::string> diffs;
  if (!(original.sample == now.sample)) {
    SampleSpec reseeded = now.sample;
    reseeded.seed = original.sample.seed;
    diffs.push_back(reseeded == original.sample
                        ? "[sample] seed (the checkpoint's run used seed " +
                              std::to_string(original.sample.seed) + ": restart with --seed " +
                              std::to_string(original.sample.seed) + ")"
                        : std::string("[sample]"));
  }
  if (!(original.material == now.material))
    diffs.push_back("[material]");
  if (!(original.numerics == now.numerics))
    diffs.push_back("[numerics]");
  // Stages up to the one in progress have shaped the stored state: they must be the same.
  const std::size_t fixed_count =
      static_cast<std::size_t>(state.stage_index) + (state.mid_stage ? 1 : 0);
  const std::size_t common = std::min(original.stages.size(), now.stages.size());
  for (std::size_t i = 0; i < common; ++i) {
    const auto& a = original.stages[i];
    const auto& b = now.stages[i];
    if (a.kind == b.kind && a.name == b.name && a.params == b.params)
      continue;
    if (i < fixed_count || !allow_later_stages)
      diffs.push_back("stage[" + std::to_string(i) + "] ('" + a.name + "' in the checkpoint, '" +
                      b.name + "' now)" + (i < fixed_count ? " (already run)" : ""));
  }
  if (original.stages.size() != now.stages.size()) {
    if (now.stages.size() < fixed_count)
      diffs.push_back("the number of stages (" + std::to_string(now.stages.size()) +
                      "; the checkpoint is at stage " + std::to_string(state.stage_index) + ")");
    else if (!allow_later_stages)
      diffs.push_back("the number of stages (" + std::to_string(original.stages.size()) +
                      " in the checkpoint, " + std::to_string(now.stages.size()) + " now)");
  }
  if (diffs.empty())
    return;
  std::ostringstream os;
  os << "cannot restart from " << checkpoint_file << ": the deck " << now.file
     << " differs from the one the checkpoint was written with in ";
  for (std::size_t i = 0; i < diffs.size(); ++i)
    os << (i ? ", " : "") << diffs[i];
  os << ". Only [output] may change on a restart";
  if (!allow_later_stages)
    os << " (and, with --allow-deck-change, the stages after the one in progress)";
  os << "; `granpack info " << checkpoint_file << "` shows the stored deck's stage";
  throw InputError(os.str());
}

template void Checkpointer::write<2>(RunContext<2>&, bool);
template void Checkpointer::write<3>(RunContext<3>&, bool);

} // namespace granpack
